//! Nothing mixed, nothing cut, nothing injected: one test per way data could be mixed
//! (an input changed between a run and its resume or merge), cut (an output written in
//! place when a signal or a full disk strikes), overwritten (an output on an input),
//! merged unchecked, or injected (a value written into a script), and the limits and
//! messages that keep bad input harmless.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{fails, monoculus, ok, s};

/// A folder with a config whose robots come from `start.csv` and whose schedule is
/// `schedule.csv`: two cells (n fixed by the file, two step lengths), 4 seeds.
fn with_files(dir: &Path) -> PathBuf {
    std::fs::write(dir.join("start.csv"), "x,y\n0,0\n4,0\n0,3\n5,5\n1,6\n7,2\n").unwrap();
    std::fs::write(
        dir.join("schedule.csv"),
        "round,robot\n1,0\n1,1\n2,2\n2,3\n3,4\n3,5\n4,0\n5,1\n",
    )
    .unwrap();
    let cfg = dir.join("files.toml");
    std::fs::write(
        &cfg,
        r#"name = "files"
seeds = 4

[swarm]
init = "file"
file = "start.csv"

[algorithm]
name = "converge_locality"
step = [1.0, 0.5]

[scheduler]
kind = "file"
file = "schedule.csv"
"#,
    )
    .unwrap();
    cfg
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

// 1. A result's identity covers every file its config names.

#[test]
fn an_input_file_changed_between_shards_or_before_a_resume_is_refused_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = with_files(tmp.path());
    let out = tmp.path().join("out");
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "0/2"]);
    // Edit the positions file: shard 1 must not run on other robots.
    std::fs::write(
        tmp.path().join("start.csv"),
        "x,y\n0,0\n4,0\n0,3\n5,5\n1,6\n7,3\n",
    )
    .unwrap();
    for args in [
        vec!["run", s(&cfg), "--out", s(&out), "--shard", "1/2"],
        vec!["run", s(&cfg), "--out", s(&out), "--shard", "0/2"],
        vec!["merge", s(&out)],
    ] {
        let e = fails(&args);
        assert!(
            e.contains("swarm.file") && e.contains("start.csv") && e.contains("has changed"),
            "{args:?}: {e}"
        );
    }
    assert!(!out.join("runs.csv").exists());
    // A whole run, then its schedule edited: no resume.
    let whole = tmp.path().join("whole");
    std::fs::write(
        tmp.path().join("start.csv"),
        "x,y\n0,0\n4,0\n0,3\n5,5\n1,6\n7,2\n",
    )
    .unwrap();
    ok(&["run", s(&cfg), "--out", s(&whole)]);
    let before = read(&whole.join("runs.csv"));
    let mut sched = read(&tmp.path().join("schedule.csv"));
    sched.push_str("6,2\n");
    std::fs::write(tmp.path().join("schedule.csv"), sched).unwrap();
    let e = fails(&["run", s(&cfg), "--out", s(&whole)]);
    assert!(
        e.contains("scheduler.file") && e.contains("schedule.csv"),
        "{e}"
    );
    assert_eq!(read(&whole.join("runs.csv")), before);
    // The identity is in every row: config.toml records each file's hash.
    assert!(read(&whole.join("config.toml")).contains("# input swarm.file \"start.csv\" "));
    // ASYNC durations given from a file are an input too.
    let timed = tmp.path().join("timed.toml");
    let text = read(&cfg).replace(
        "kind = \"file\"\nfile = \"schedule.csv\"",
        "kind = \"async\"\ndurations = \"durations.csv\"",
    );
    assert!(text.contains("durations.csv"), "{text}");
    std::fs::write(&timed, text).unwrap();
    let durations = tmp.path().join("durations.csv");
    std::fs::write(&durations, "robot,cycle,phase,ticks\n1,0,compute,9\n").unwrap();
    let async_out = tmp.path().join("async");
    ok(&["run", s(&timed), "--out", s(&async_out)]);
    assert!(read(&async_out.join("config.toml")).contains("# input scheduler.durations "));
    std::fs::write(&durations, "robot,cycle,phase,ticks\n1,0,compute,8\n").unwrap();
    let e = fails(&["run", s(&timed), "--out", s(&async_out)]);
    assert!(
        e.contains("scheduler.durations")
            && e.contains("durations.csv")
            && e.contains("has changed"),
        "{e}"
    );
}

// 2. No command writes over its own inputs, or two outputs to one path.

#[test]
fn outputs_on_inputs_or_on_each_other_are_refused_and_nothing_is_touched() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = with_files(tmp.path());
    let schedule = tmp.path().join("schedule.csv");
    let before = read(&schedule);
    let t = tmp.path().join("t.csv");
    let respelled = format!("{}/./x/../schedule.csv", s(tmp.path()));
    let t_positions = tmp.path().join("t.positions.csv");
    let base = ["trace", s(&cfg), "--cell", "0", "--seed", "0"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--out", s(&t), "--schedule", s(&schedule)],
            "scheduler.file",
        ),
        // The same file by another spelling.
        (
            vec!["--out", s(&t), "--schedule", &respelled],
            "scheduler.file",
        ),
        (vec!["--out", s(&schedule)], "scheduler.file"),
        (vec!["--out", s(&cfg)], "the config"),
        (
            vec!["--out", s(&t), "--schedule", s(&t)],
            "two outputs in one file",
        ),
        (
            vec!["--out", s(&t), "--positions", "--schedule", s(&t_positions)],
            "two outputs in one file",
        ),
    ];
    std::fs::create_dir(tmp.path().join("x")).unwrap();
    for (extra, want) in cases {
        let mut args = base.to_vec();
        args.extend(&extra);
        let e = fails(&args);
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(read(&schedule), before);
        assert!(!t.exists());
    }
    // A hard link to the schedule is the schedule.
    let link = tmp.path().join("link.csv");
    std::fs::hard_link(&schedule, &link).unwrap();
    fails(&[&base[..], &["--out", s(&t), "--schedule", s(&link)]].concat());
    assert_eq!(read(&schedule), before);
    // replay and run: the config or its files are never outputs.
    let e = fails(&["replay", s(&cfg), "--cell", "0", "--out", s(&schedule)]);
    assert!(e.contains("--out"), "{e}");
    let e = fails(&[
        "replay",
        s(&cfg),
        "--cell",
        "0",
        "--out",
        s(&t),
        "--gif",
        s(&t),
    ]);
    assert!(e.contains("two outputs"), "{e}");
    std::fs::copy(&cfg, tmp.path().join("config.toml")).unwrap();
    let e = fails(&[
        "run",
        s(&tmp.path().join("config.toml")),
        "--out",
        s(tmp.path()),
    ]);
    assert!(e.contains("config.toml"), "{e}");
    assert_eq!(read(&schedule), before);
}

// 3. Every file is written whole or not at all.

const LONG: &str = r#"
name = "long"
seeds = 1

[swarm]
n = 3000
init = "square"
side = 300.0

[algorithm]
name = "converge_locality"

[stop]
max_rounds = 100000
"#;

#[test]
fn a_signal_during_trace_leaves_the_previous_files_and_no_temporary() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("long.toml");
    std::fs::write(&cfg, LONG).unwrap();
    let (t, p, sch) = (
        tmp.path().join("t.csv"),
        tmp.path().join("t.positions.csv"),
        tmp.path().join("s.csv"),
    );
    for f in [&t, &p, &sch] {
        std::fs::write(f, "the good file\n").unwrap();
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .args([
            "trace",
            s(&cfg),
            "--seed",
            "0",
            "--out",
            s(&t),
            "--positions",
        ])
        .args(["--schedule", s(&sch), "--threads", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the positions' temporary holds rows, then interrupt.
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let big = files_in(tmp.path()).iter().any(|n| {
            n.ends_with(".tmp")
                && std::fs::metadata(tmp.path().join(n)).is_ok_and(|m| m.len() > 100_000)
        });
        if big {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "no temporary: {:?}",
            files_in(tmp.path())
        );
        assert!(child.try_wait().unwrap().is_none(), "trace ended too soon");
        std::thread::sleep(Duration::from_millis(5));
    }
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    for f in [&t, &p, &sch] {
        assert_eq!(read(f), "the good file\n", "{}", f.display());
    }
    assert_eq!(
        files_in(tmp.path()),
        ["long.toml", "s.csv", "t.csv", "t.positions.csv"]
    );
}

/// Runs `monoculus` with file writes limited to `blocks` kilobytes (`ulimit -f`): a
/// write past the limit fails as on a full disk, and the process is killed by SIGXFSZ.
fn with_file_limit(blocks: u32, args: &[&str]) -> std::process::Output {
    let mut script = format!(
        "ulimit -f {blocks}; exec '{}'",
        env!("CARGO_BIN_EXE_monoculus")
    );
    for a in args {
        script.push_str(&format!(" '{a}'"));
    }
    Command::new("bash").args(["-c", &script]).output().unwrap()
}

#[test]
fn a_write_that_fails_midway_leaves_the_previous_page_figures_and_results() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("r.toml");
    std::fs::write(
        &cfg,
        LONG.replace("n = 3000", "n = 60")
            .replace("side = 300.0", "side = 30.0"),
    )
    .unwrap();
    let page = tmp.path().join("r.html");
    let gif = tmp.path().join("r.gif");
    ok(&["replay", s(&cfg), "--out", s(&page), "--gif", s(&gif)]);
    let (good_page, good_gif) = (std::fs::read(&page).unwrap(), std::fs::read(&gif).unwrap());
    assert!(good_page.len() > 20_000 && good_gif.len() > 20_000);
    // 10 kB (`ulimit -f` counts kilobytes): the new page and GIF cannot be written whole.
    let out = with_file_limit(10, &["replay", s(&cfg), "--seed", "0", "--out", s(&page)]);
    assert!(!out.status.success());
    let out = with_file_limit(10, &["replay", s(&cfg), "--seed", "0", "--gif", s(&gif)]);
    assert!(!out.status.success());
    assert!(
        std::fs::read(&page).unwrap() == good_page,
        "the page was cut"
    );
    assert!(std::fs::read(&gif).unwrap() == good_gif, "the GIF was cut");
    // Figures of a results folder, the same.
    let res = tmp.path().join("res");
    ok(&["run", s(&cfg), "--out", s(&res)]);
    ok(&["plot", s(&res)]);
    let figures = res.join("figures");
    let before: Vec<(String, Vec<u8>)> = files_in(&figures)
        .into_iter()
        .map(|n| (n.clone(), std::fs::read(figures.join(&n)).unwrap()))
        .collect();
    let out = with_file_limit(1, &["plot", s(&res)]);
    assert!(!out.status.success());
    for (n, bytes) in &before {
        assert!(
            &std::fs::read(figures.join(n)).unwrap() == bytes,
            "{n} was cut"
        );
    }
    // The killed writers' temporaries are removed by the next write to those names.
    ok(&["replay", s(&cfg), "--out", s(&page), "--gif", s(&gif)]);
    ok(&["plot", s(&res)]);
    assert!(!files_in(tmp.path()).iter().any(|n| n.ends_with(".tmp")));
    assert!(!files_in(&figures).iter().any(|n| n.ends_with(".tmp")));
}

// 4. Merge checks what it merges.

const SHARDED: &str = r#"
name = "sharded"
seeds = 4

[swarm]
n = [5, 8]
init = "square"
side = 5.0

[algorithm]
name = "converge_locality"
"#;

/// Rewrites `file` with `edit` applied to its rows (header first).
fn edit_csv(file: &Path, edit: impl FnOnce(&mut Vec<Vec<String>>)) {
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(file)
        .unwrap();
    let mut rows: Vec<Vec<String>> = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    edit(&mut rows);
    let mut w = csv::Writer::from_path(file).unwrap();
    for row in rows {
        w.write_record(row).unwrap();
    }
    w.flush().unwrap();
}

#[test]
fn merge_refuses_a_row_that_is_not_its_shards_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(&cfg, SHARDED).unwrap();
    let out = tmp.path().join("o");
    for k in ["0/2", "1/2"] {
        ok(&["run", s(&cfg), "--out", s(&out), "--shard", k]);
    }
    let (s0, s1) = (out.join("shards/0-of-2.csv"), out.join("shards/1-of-2.csv"));
    let good = std::fs::read(&s0).unwrap();
    let col = |name: &str| {
        read(&s0)
            .lines()
            .next()
            .unwrap()
            .split(',')
            .position(|h| h == name)
            .unwrap()
    };
    let (rho, n) = (col("rho"), col("n"));
    let other_row: Vec<String> = read(&s1)
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    type Edit = Box<dyn Fn(&mut Vec<Vec<String>>)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(move |r| r[2][rho] = "abc".into()),
            "0-of-2.csv:3: column rho: `abc` is not a number",
        ),
        (
            Box::new(move |r| r[1][n] = "6".into()),
            "0-of-2.csv:2: column n: `6` is not cell",
        ),
        (
            Box::new(move |r| r.push(other_row.clone())),
            "not of shard 0/2",
        ),
        (
            Box::new(|r| {
                let again = r[1].clone();
                r.push(again)
            }),
            "is also at",
        ),
    ];
    for (edit, want) in cases {
        std::fs::write(&s0, &good).unwrap();
        edit_csv(&s0, edit);
        let e = fails(&["merge", s(&out)]);
        assert!(e.contains(want), "{want}: {e}");
        for f in ["runs.csv", "summary.csv", "provenance.toml"] {
            assert!(!out.join(f).exists(), "{f} written by a refused merge");
        }
    }
    // A partial merge says so: in summary.csv, in the provenance, in the table.
    std::fs::write(&s0, &good).unwrap();
    edit_csv(&s0, |r| {
        r.pop();
    });
    let e = monoculus(&["merge", s(&out)]);
    assert_eq!(e.status.code(), Some(1));
    assert!(!out.join("runs.csv").exists());
    ok(&["merge", s(&out), "--partial"]);
    let summary = read(&out.join("summary.csv"));
    let missing: Vec<&str> = summary
        .lines()
        .map(|l| l.rsplit(',').next().unwrap())
        .collect();
    assert_eq!(missing[0], "missing");
    assert_eq!(
        missing[1..]
            .iter()
            .map(|m| m.parse::<u64>().unwrap())
            .sum::<u64>(),
        1
    );
    assert!(read(&out.join("provenance.toml")).contains("missing_runs = 1"));
    let table = ok(&["table", s(&out), "--format", "text"]);
    assert!(table.starts_with("partial: 1 of 8 runs missing"), "{table}");
    assert!(
        table.lines().nth(2).unwrap().ends_with("missing runs"),
        "{table}"
    );
    // Complete, it says nothing of the kind.
    std::fs::write(&s0, &good).unwrap();
    ok(&["merge", s(&out)]);
    assert!(!read(&out.join("provenance.toml")).contains("missing_runs"));
    assert!(!ok(&["table", s(&out)]).contains("partial"));
}

// 5. Generated scripts carry only safe values.

#[test]
fn hostile_values_never_reach_a_script_and_quoted_ones_run_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(&cfg, SHARDED).unwrap();
    let out = tmp.path().join("o");
    let base = ["slurm", s(&cfg), "--shards", "2"];
    let hostile = "short\ntouch PWNED #";
    let bad_out = format!("{}\ntouch PWNED", s(&out));
    for (option, value) in [
        ("--partition", hostile),
        ("--job-name", hostile),
        ("--time", hostile),
        ("--mem", hostile),
        ("--account", hostile),
        ("--sbatch", "--qos=x\ntouch PWNED"),
        ("--partition", "short;touch PWNED"),
        ("--time", "1:00; touch PWNED"),
        ("--job-name", "$(touch PWNED)"),
        ("--sbatch", "--qos=x touch PWNED"),
        ("--set", "seeds=2\ntouch PWNED"),
    ] {
        let e = fails(&[&base[..], &["--out", s(&out), option, value]].concat());
        assert!(e.contains(option), "{option}: {e}");
        assert!(
            !out.join("slurm").exists(),
            "{option}: a script was written"
        );
    }
    let e = fails(&[&base[..], &["--out", &bad_out]].concat());
    assert!(e.contains("--out"), "{e}");
    // Values a script may hold, hostile to a shell: quoted, they run nothing.
    let odd = tmp.path().join("$(touch PWNED) x; `touch PWNED`");
    let written = ok(&[
        &base[..],
        &[
            "--out",
            s(&odd),
            "--set",
            "name=\"sharded\" #$(touch PWNED)",
        ],
    ]
    .concat());
    assert!(written.contains("array.sh"), "{written}");
    let slurm = odd.join("slurm");
    for (script, task) in [
        ("array.sh", Some("0")),
        ("array.sh", Some("1")),
        ("merge.sh", None),
    ] {
        let mut c = Command::new("bash");
        c.arg(slurm.join(script)).current_dir(tmp.path());
        if let Some(t) = task {
            c.env("SLURM_ARRAY_TASK_ID", t);
        }
        let o = c.output().unwrap();
        assert!(
            o.status.success(),
            "{script}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    assert!(
        odd.join("runs.csv").exists(),
        "the scripts ran the shards and the merge"
    );
    for dir in [tmp.path(), &odd, &slurm] {
        assert!(
            !files_in(dir).iter().any(|n| n == "PWNED"),
            "{}",
            dir.display()
        );
    }
}

// 6. Input files are read strictly.

#[test]
fn positions_and_trace_files_are_read_strictly() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    let pos = tmp.path().join("p.csv");
    std::fs::write(
        &cfg,
        "name = \"p\"\n[swarm]\ninit = \"file\"\nfile = \"p.csv\"\n[algorithm]\nname = \"converge_locality\"\n",
    )
    .unwrap();
    for (text, want) in [
        ("x,y,z\n0,0,1\n1,1,1\n", "has a z column, but dim = 2"),
        ("x,y,x\n0,0,1\n1,1,1\n", "names column `x` twice"),
        (
            "x,y,w\n0,0,1\n1,1,1\n",
            "column `w`, which this file does not take",
        ),
        // A file cut short is told by its content: a row missing a field, a number cut
        // where it is no number.
        ("x,y\n0,0\n1", "p.csv:3: column y: missing"),
        (
            "x,y\n0,0\n1,",
            "p.csv:3: column y: `` is not a finite number",
        ),
        (
            "x,y\n0,0\n1,1.2e",
            "p.csv:3: column y: `1.2e` is not a finite number",
        ),
    ] {
        std::fs::write(&pos, text).unwrap();
        let e = fails(&["check", s(&cfg)]);
        assert!(e.contains(want) && e.contains("p.csv"), "{text:?}: {e}");
    }
    // RFC 4180: the last record need not end with a line break.
    for text in [
        "x,y\n0,0\n1,1.25\n",
        "x,y\n0,0\n1,1.25",
        "x,y\r\n0,0\r\n1,1.25",
    ] {
        std::fs::write(&pos, text).unwrap();
        ok(&["check", s(&cfg)]);
    }
    // A trace whose positions file belongs to another run.
    let small = tmp.path().join("s.toml");
    std::fs::write(&small, SHARDED.replace("n = [5, 8]", "n = 8")).unwrap();
    let t = tmp.path().join("t.csv");
    ok(&[
        "trace",
        s(&small),
        "--seed",
        "0",
        "--out",
        s(&t),
        "--positions",
    ]);
    ok(&["plot", s(&t)]);
    ok(&[
        "replay",
        s(&tmp.path().join("t.positions.csv")),
        "--out",
        s(&tmp.path().join("r.html")),
    ]);
    // The same name traced again from another run, without --positions.
    ok(&[
        "trace",
        s(&small),
        "--seed",
        "0",
        "--set",
        "swarm.n=7",
        "--out",
        s(&t),
    ]);
    let e = fails(&["plot", s(&t)]);
    assert!(e.contains("belongs to another run"), "{e}");
    let e = fails(&[
        "replay",
        s(&tmp.path().join("t.positions.csv")),
        "--out",
        s(&tmp.path().join("r.html")),
    ]);
    assert!(e.contains("belongs to another run"), "{e}");
}

// 7. Limits that hold in time and memory.

#[test]
fn clocks_that_could_overflow_huge_configs_and_long_values_are_refused_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    let base = SHARDED.replace("n = [5, 8]", "n = 5");
    for (timing, key) in [
        (
            "idle = { kind = \"fixed\", ticks = 4611686018427387904 }",
            "scheduler.idle",
        ),
        (
            "move = { kind = \"exponential\", mean = 1e300 }",
            "scheduler.move",
        ),
        (
            "compute = { kind = \"uniform\", min = 1, max = 2000000000000 }",
            "scheduler.compute",
        ),
    ] {
        std::fs::write(
            &cfg,
            format!("{base}\n[scheduler]\nkind = \"async\"\n{timing}\n"),
        )
        .unwrap();
        let e = fails(&["check", s(&cfg)]);
        assert!(e.contains(key), "{e}");
    }
    std::fs::write(
        &cfg,
        format!("{base}\n[scheduler]\nkind = \"async\"\nidle = {{ kind = \"fixed\", ticks = 1000000000 }}\n[stop]\nmax_rounds = 10000000000\n"),
    )
    .unwrap();
    assert!(fails(&["check", s(&cfg)]).contains("stop.max_rounds"));
    // The most runs an experiment may have is what one machine sorts and summarises
    // at the end of a sweep (10^7; 10^8 needed over 100 GB).
    std::fs::write(&cfg, base.replace("seeds = 4", "seeds = 100000000")).unwrap();
    let e = fails(&["check", s(&cfg)]);
    assert!(
        e.contains("seeds: 100000000 seeds x 1 cells: at most 10000000 runs"),
        "{e}"
    );
    // A config of 50 MB: refused at once, in a short message.
    let big = tmp.path().join("big.toml");
    std::fs::write(&big, "#".repeat(50 << 20)).unwrap();
    let e = fails(&["check", s(&big)]);
    assert!(e.len() < 200, "{e}");
    // No message quotes more than about 100 characters of a value.
    let long = "y".repeat(20_000);
    for (line, key) in [
        (format!("n = \"{long}\""), "swarm.n"),
        (format!("init = \"{long}\""), "swarm.init"),
    ] {
        let text = base.replace(
            "n = 5",
            &if key == "swarm.n" {
                line.clone()
            } else {
                format!("n = 5\n{line}")
            },
        );
        let text = if key == "swarm.init" {
            text.replace("init = \"square\"\n", "")
        } else {
            text
        };
        std::fs::write(&cfg, text).unwrap();
        let e = fails(&["check", s(&cfg)]);
        assert!(
            e.contains(key) && e.len() < 300,
            "{} characters: {}",
            e.len(),
            &e[..300.min(e.len())]
        );
    }
    let pos = tmp.path().join("p.csv");
    std::fs::write(&pos, format!("x,y\n0,{long}\n")).unwrap();
    let e = fails(&["look", s(&pos), "--robot", "0"]);
    assert!(e.len() < 300, "{}", e.len());
    let e = fails(&["check", s(&cfg), "--set", &format!("swarm.init={long}")]);
    assert!(e.len() < 300, "{}", e.len());
}

#[test]
fn a_sweep_of_fifty_thousand_values_is_checked_in_linear_time() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    let sides: Vec<String> = (1..=50_000).map(|k| format!("{k}.5")).collect();
    std::fs::write(
        &cfg,
        SHARDED
            .replace("n = [5, 8]", "n = 5")
            .replace("side = 5.0", &format!("side = [{}]", sides.join(", "))),
    )
    .unwrap();
    // A guard against quadratic validation (which took minutes), not a speed target:
    // linear, it takes about a second even in a debug build.
    let start = Instant::now();
    let out = ok(&["check", s(&cfg)]);
    assert!(
        out.starts_with("sharded: 50000 cells x 4 seeds"),
        "{}",
        &out[..100]
    );
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{:?}",
        start.elapsed()
    );
    // A repeated value is found in the same pass.
    let dup = read(&cfg).replace("50000.5]", "50000.5, 17.5]");
    std::fs::write(&cfg, dup).unwrap();
    assert!(fails(&["check", s(&cfg)]).contains("the list has 17.5 twice"));
}

// 8. Distinct outputs get distinct names.

#[test]
fn pages_of_cells_that_differ_in_characters_a_name_cannot_hold_are_distinct() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, y) in [("é.csv", 1), ("ü.csv", 2), ("ö.csv", 3)] {
        std::fs::write(tmp.path().join(name), format!("x,y\n0,0\n3,{y}\n1,5\n")).unwrap();
    }
    let cfg = tmp.path().join("c.toml");
    std::fs::write(
        &cfg,
        "name = \"pages\"\n[swarm]\ninit = \"file\"\nfile = [\"é.csv\", \"ü.csv\", \"ö.csv\"]\n[algorithm]\nname = \"converge_locality\"\n",
    )
    .unwrap();
    let dir = tmp.path().join("pages");
    ok(&["replay", s(&cfg), "--out", &format!("{}/", s(&dir))]);
    let pages = files_in(&dir);
    assert_eq!(
        pages,
        ["pages_cell0.html", "pages_cell1.html", "pages_cell2.html"]
    );
    let texts: std::collections::HashSet<String> =
        pages.iter().map(|p| read(&dir.join(p))).collect();
    assert_eq!(texts.len(), 3, "each page is its own cell's");
}

// 9. Messages a user understands.

#[test]
fn untagged_values_and_deep_nesting_say_what_is_allowed_and_where() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    let base = SHARDED.replace("n = [5, 8]", "n = 5");
    for at in ["-1", "1.5", "\"soon\"", "true"] {
        std::fs::write(
            &cfg,
            format!("{base}\n[faults]\nkind = \"crash\"\ncount = 1\nat = {at}\n"),
        )
        .unwrap();
        let e = fails(&["check", s(&cfg)]);
        assert!(
            e.contains(
                "c.toml:16: faults.at: expected a round (a whole number, at least 0) or \"random\""
            ),
            "{e}"
        );
        assert!(!e.contains("untagged"), "{e}");
    }
    let deep = format!("name = \"d\"\n[{}]\n", vec!["a"; 100_000].join("."));
    std::fs::write(&cfg, deep).unwrap();
    let e = fails(&["check", s(&cfg)]);
    assert!(
        e.contains("c.toml:2: nested about 100000 levels deep"),
        "{}",
        &e[..200.min(e.len())]
    );
    let deep = format!("name = \"d\"\nx = {}{}\n", "[".repeat(500), "]".repeat(500));
    std::fs::write(&cfg, deep).unwrap();
    let e = fails(&["check", s(&cfg)]);
    assert!(e.contains("c.toml:2:") && e.contains("nested"), "{e}");
}
