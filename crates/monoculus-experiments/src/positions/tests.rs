use super::*;

/// RFC 4180: every input CSV may end without a line break; a file cut short is told
/// by its content, with its line and column.
#[test]
fn every_input_csv_may_end_without_a_line_break_and_a_cut_row_is_named() {
    use crate::durations::parse_durations;
    use crate::schedule::parse_schedule;
    let p = parse_positions("x,y\n0,0\n1,1\n5,5", "p.csv").unwrap();
    assert_eq!(p.rows.len(), 3);
    assert_eq!(
        parse_schedule("round,robot\n1,0\n2,1", "s.csv")
            .unwrap()
            .list
            .rounds(),
        2
    );
    let d = parse_durations("robot,cycle,phase,ticks\n0,1,move,5", "d.csv").unwrap();
    assert_eq!(d.durations.iter().count(), 1);
    let t = parse_trace_positions("round,robot,x,y\n0,0,0,0\n1,0,1,0", "t.csv").unwrap();
    assert_eq!(t.rounds.len(), 2);
    let err = |r: Result<(), PositionsError>| r.unwrap_err().to_string();
    assert_eq!(
        err(parse_positions("x,y\n0,0\n5", "p.csv").map(drop)),
        "p.csv:3: column y: missing (the row has 1 of the 2 fields of the header: is the file cut short?)"
    );
    assert!(
        err(parse_schedule("round,robot\n1,0\n2", "s.csv").map(drop))
            .starts_with("s.csv:3: column robot: missing")
    );
    assert!(
        err(parse_durations("robot,cycle,phase,ticks\n0,1,mo", "d.csv").map(drop))
            .starts_with("d.csv:2: column ticks: missing")
    );
    assert!(
        err(parse_positions("x,y\n0,0\n5,1e", "p.csv").map(drop))
            .starts_with("p.csv:3: column y: `1e` is not a finite number")
    );
    assert!(
        err(parse_positions("x,y\n0,0\n5,1,2", "p.csv").map(drop))
            .contains("3 fields, but the header names 2 columns")
    );
}

#[test]
fn reads_and_reports_lines() {
    let p = parse_positions("x,y\n1,2\n3.5, -4\n", "f.csv").unwrap();
    assert_eq!(p.rows, vec![[1.0, 2.0, 0.0], [3.5, -4.0, 0.0]]);
    assert!(!p.has_z);
    let q = parse_positions("z,x,y\n1,2,3\n", "f.csv").unwrap();
    assert_eq!((q.rows[0], q.has_z), ([2.0, 3.0, 1.0], true));
    let e = parse_positions("x,y\n1,2\n3,abc\n", "f.csv")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "f.csv:3: column y: `abc` is not a finite number");
    let e = parse_positions("x,y\n1e200,2\n", "f.csv")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("f.csv:2: column x: `1e200`"), "{e}");
    let e = parse_positions("a,b\n1,2\n", "f.csv")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("f.csv:1: header must name columns x and y"),
        "{e}"
    );
    assert!(
        parse_positions("x,y\n", "f.csv")
            .unwrap_err()
            .to_string()
            .contains("no robots")
    );
}

#[test]
fn bad_trace_files_name_the_line() {
    let bad = [
        ("x,y\n1,2\n", "columns round, robot, x and y"),
        (
            "round,robot,x,y\n1,0,0,0\n",
            ":2: column round: 1 out of order",
        ),
        (
            "round,robot,x,y\n0,0,0,0\n0,2,0,0\n",
            ":3: column robot: 2 out of order",
        ),
        (
            "round,robot,x,y\n0,0,0,0\n0,1,1,1\n1,0,0,0\n2,0,0,0\n",
            ":5: round 1 lists 1 robots",
        ),
        (
            "round,robot,x,y\n0,0,0,0\n0,1,1,1\n1,0,0,0\n",
            ":4: round 1 lists 1 robots",
        ),
        ("round,robot,x,y\n0,-1,0,0\n", ":2: column robot: `-1`"),
        ("round,robot,x,y\n0,0,0,nan\n", ":2: column y"),
    ];
    for (text, want) in bad {
        let e = parse_trace_positions(text, "t.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{text:?}: {e}");
        assert!(e.starts_with("t.csv:"), "{e}");
    }
}
