//! Bad input: one line naming the file, line and key, exit status 2, never a panic.

mod common;

use common::{fails, monoculus};

const GOOD: &str = "name = \"x\"\nseeds = 2\n\n[swarm]\nn = 10\ninit = \"square\"\nside = 10.0\n\n[algorithm]\nname = \"converge_locality\"\nstep = 1.0\nlocality = 2.0\n";

fn config_error(text: &str) -> (String, String) {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap().to_string();
    let e = fails(&["check", &p]);
    // `run` reports the same error before touching the output folder.
    let out = tmp.path().join("out");
    assert_eq!(fails(&["run", &p, "--out", out.to_str().unwrap()]), e);
    assert!(!out.exists());
    (e.replace(&p, "bad.toml"), p)
}

fn one_line(e: &str) -> &str {
    assert_eq!(e.lines().count(), 1, "one line: {e}");
    e.trim_end()
}

#[test]
fn the_good_config_passes() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let out = monoculus(&["check", path.to_str().unwrap()]);
    assert!(out.status.success());
    // check reports the memory a run needs: 10 robots at 256 bytes each plus 16 MiB.
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("memory: about 16.8 MB per run (n = 10)"),
        "{text}"
    );
}

#[test]
fn unknown_key() {
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = 10.0\nsidee = 3"));
    let e = one_line(&e);
    assert!(
        e.starts_with("error: bad.toml:8: swarm.sidee: unknown field `sidee`"),
        "{e}"
    );
    let (e, _) = config_error(&format!("{GOOD}\n[stopp]\nmax_rounds = 3\n"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:14: stopp: unknown field `stopp`"),
        "{e}"
    );
}

#[test]
fn wrong_type() {
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = \"ten\""));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: invalid type: string \"ten\""),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = [10, \"x\"]"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: invalid type"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("\"converge_locality\"", "\"converge_everything\""));
    assert!(
        one_line(&e).starts_with(
            "error: bad.toml:10: algorithm.name: `converge_everything` is not a registered algorithm; registered are converge_locality, converge_quadrant, converge_quadrant_termination, center_of_gravity, median, angle_bisector"
        ),
        "{e}"
    );
}

#[test]
fn out_of_range_values() {
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = 0"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:5: swarm.n: must be at least 1"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = [10, 0]"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:5: swarm.n: must be at least 1"
    );
    let (e, _) = config_error(&GOOD.replace("step = 1.0", "step = 0.0"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:11: algorithm.step: must be positive, got 0"
    );
    let (e, _) = config_error(&GOOD.replace("step = 1.0", "step = -2"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:11: algorithm.step:"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = -1.0"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:7: swarm.side:"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = []"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: empty list"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10\n", ""));
    assert!(
        one_line(&e).starts_with("error: bad.toml:4: swarm.n: missing"),
        "{e}"
    );
    for range in ["0.0", "-3.0", "nan"] {
        let (e, _) = config_error(&format!("{GOOD}\n[vision]\nrange = {range}\n"));
        assert!(
            one_line(&e).starts_with("error: bad.toml:15: vision.range: must be positive"),
            "{range}: {e}"
        );
    }
    let (e, _) = config_error(&GOOD.replace("seeds = 2", "seeds = 0"));
    assert!(one_line(&e).starts_with("error: bad.toml:2: seeds:"), "{e}");
    let (e, _) = config_error(&GOOD.replace("init = \"square\"", "init = \"square\"\ndim = 7"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:7: swarm.dim:"),
        "{e}"
    );
}

#[test]
fn syntax_error_names_the_line() {
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = = 10.0"));
    assert!(one_line(&e).starts_with("error: bad.toml:7:"), "{e}");
}

#[test]
fn locality_below_twice_the_step_warns() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("warn.toml");
    std::fs::write(&path, GOOD.replace("locality = 2.0", "locality = 1.5")).unwrap();
    let out = monoculus(&["check", path.to_str().unwrap()]);
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("warning:") && stderr.contains(":12: algorithm.locality: c = 1.5 < 2b = 2"),
        "{stderr}"
    );
}

#[test]
fn missing_and_malformed_position_files() {
    let (e, _) = config_error(
        &GOOD
            .replace(
                "init = \"square\"",
                "init = \"file\"\nfile = \"nowhere.csv\"",
            )
            .replace("n = 10\n", ""),
    );
    let e = one_line(&e);
    assert!(
        e.starts_with("error: bad.toml:6: swarm.file: ") && e.contains("nowhere.csv: cannot read"),
        "{e}"
    );
    let (e, _) = config_error(
        &GOOD
            .replace("init = \"square\"", "init = \"file\"")
            .replace("n = 10\n", ""),
    );
    assert!(
        one_line(&e).starts_with("error: bad.toml:4: swarm.file: init = \"file\" needs swarm.file"),
        "{e}"
    );
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("p.csv");
    std::fs::write(&csv, "x,y\n0,0\n1,oops\n").unwrap();
    let e = fails(&["look", csv.to_str().unwrap(), "--robot", "0"]);
    assert!(
        one_line(&e).ends_with("p.csv:3: column y: `oops` is not a finite number"),
        "{e}"
    );
    std::fs::write(&csv, "x,y\n0,0\n1,1\n").unwrap();
    let e = fails(&["look", csv.to_str().unwrap(), "--robot", "5"]);
    assert!(one_line(&e).contains("--robot 5:"), "{e}");
}

#[test]
fn bad_arguments() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let p = path.to_str().unwrap();
    let e = fails(&["run", p, "--shard", "3/3"]);
    assert!(one_line(&e).contains("--shard 3/3"), "{e}");
    let e = fails(&["run", p, "--threads", "0"]);
    assert!(one_line(&e).contains("--threads"), "{e}");
    let e = fails(&["check", p, "--set", "swarm.n"]);
    assert!(one_line(&e).contains("--set: expected KEY=VALUE"), "{e}");
    let e = fails(&["check", p, "--set", "swarm.n=0"]);
    assert_eq!(one_line(&e), "error: --set: swarm.n: must be at least 1");
    let e = fails(&["check", p, "--set", "swarm.bogus=1"]);
    assert!(
        one_line(&e).starts_with("error: --set: swarm.bogus: unknown field"),
        "{e}"
    );
    fails(&["check", "/nonexistent/config.toml"]);
    // clap's own message (with its usage) for an unknown command: status 2 all the same.
    assert_eq!(monoculus(&["frobnicate"]).status.code(), Some(2));
}

/// GOOD with `line` put in place of the line starting with the same key, or added.
fn with(key_line: &str) -> String {
    let key = key_line.split('=').next().unwrap().trim();
    let same = |l: &&str| l.split('=').next().unwrap().trim() == key;
    let mut lines: Vec<String> = GOOD.lines().map(String::from).collect();
    match GOOD.lines().position(|l| same(&l)) {
        Some(k) => lines[k] = key_line.to_string(),
        None => lines.push(key_line.to_string()),
    }
    lines.join("\n") + "\n"
}

#[test]
fn seeds_say_what_they_expect() {
    for bad in ["-3", "\"three\"", "3.5", "true"] {
        let (e, _) = config_error(&with(&format!("seeds = {bad}")));
        assert!(
            one_line(&e).starts_with("error: bad.toml:2: seeds: expected a count of seeds"),
            "{e}"
        );
        assert!(e.contains(&format!("got {}", bad)), "{e}");
    }
    let (e, _) = config_error(&with("seeds = [1, -2]"));
    assert!(
        one_line(&e).contains("seeds: seed 1 of the list is -2"),
        "{e}"
    );
    let (e, _) = config_error(&with("seeds = [1, 1, 2]"));
    assert!(
        one_line(&e).contains("seeds: seed 1 is listed twice"),
        "{e}"
    );
}

#[test]
fn duplicate_cells_and_keys_and_huge_integers_name_their_key() {
    let (e, _) = config_error(&with("n = [10, 20, 10]"));
    assert!(
        one_line(&e).contains("bad.toml:5: swarm.n: the list has 10 twice"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10\n", "n = 10\nn = 11\n"));
    assert!(
        one_line(&e).contains("bad.toml:6: swarm.n: duplicate key `n`"),
        "{e}"
    );
    let (e, _) = config_error(&with("n = 99999999999999999999"));
    assert!(
        one_line(&e).contains("bad.toml:5: swarm.n: integer too large"),
        "{e}"
    );
    let (e, _) = config_error(&with("max_rounds = -1").replace("max_rounds", "[stop]\nmax_rounds"));
    assert!(one_line(&e).contains("stop.max_rounds"), "{e}");
}

#[test]
fn sizes_beyond_the_machine_are_refused_before_allocating() {
    let (e, _) = config_error(&with("seeds = 1000000000000"));
    assert!(
        one_line(&e).contains("seeds: 1000000000000 seeds x 1 cells: at most"),
        "{e}"
    );
    let (e, _) = config_error(&with("n = 1000000000000"));
    assert!(
        one_line(&e).contains("swarm.n: 1000000000000 robots: at most"),
        "{e}"
    );
    let (e, _) = config_error(&with("n = 4000000000"));
    assert!(
        one_line(&e).contains("robots need about 1.0 TB for one run; this machine has"),
        "{e}"
    );
    let (e, _) = config_error(
        &with("init = \"clusters\"").replace("side = 10.0", "side = 10.0\nclusters = 100000000000"),
    );
    assert!(
        one_line(&e).contains("swarm.clusters: 100000000000 clusters for 10 robots"),
        "{e}"
    );
    let e = fails(&["stress", "--n", "1000000000000", "--rounds", "1"]);
    assert!(
        one_line(&e).contains("--n 1000000000000: 1000000000000 robots: at most"),
        "{e}"
    );
    let e = fails(&[
        "stress",
        "--n",
        "10",
        "--rounds",
        "1",
        "--threads",
        "100000",
    ]);
    assert!(
        one_line(&e).contains("--threads 100000: at most 1024"),
        "{e}"
    );
}

#[test]
fn the_seven_dimension_sweep_is_too_large() {
    // 10^7 cells: refused by the cell limit, not by running out of memory.
    let lists: String = (0..7)
        .map(|k| {
            format!(
                "x{k} = [{}]",
                (0..10)
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
        .collect::<Vec<_>>()
        .join("\n");
    let text = format!("name = \"x\"\n[sweep]\n{lists}\n");
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("c.toml");
    std::fs::write(&p, text).unwrap();
    let e = fails(&["check", p.to_str().unwrap()]);
    assert!(one_line(&e).contains("more than 1000000 cells"), "{e}");
}

#[test]
fn huge_coordinates_are_fails() {
    let (e, _) = config_error(&with("side = 1e308"));
    assert!(
        one_line(&e).contains(
            "swarm.side: must be at most 1e100 (so that squares cannot overflow), got 1e308"
        ),
        "{e}"
    );
    let (e, _) = config_error(&with("step = 1e200"));
    assert!(one_line(&e).contains("algorithm.step"), "{e}");
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.csv"), "x,y\n0,0\n1e200,1\n").unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(
        &cfg,
        GOOD.replace(
            "n = 10\ninit = \"square\"",
            "init = \"file\"\nfile = \"p.csv\"",
        ),
    )
    .unwrap();
    let e = fails(&["check", cfg.to_str().unwrap()]);
    assert!(
        one_line(&e).contains("p.csv:3: column x: `1e200` is larger than 1e100"),
        "{e}"
    );
    let e = fails(&[
        "look",
        tmp.path().join("p.csv").to_str().unwrap(),
        "--robot",
        "0",
    ]);
    assert!(one_line(&e).contains("`1e200`"), "{e}");
}

#[test]
fn names_are_plain_file_names() {
    for (bad, why) in [
        ("\"../../x\"", "names a path"),
        ("\"/tmp/abs\"", "names a path"),
        ("\"\"", "is empty"),
        ("\".hidden\"", "starts with a dot"),
        ("[\"a\", \"b\"]", "not a list"),
    ] {
        let (e, _) = config_error(&with(&format!("name = {bad}")));
        assert!(one_line(&e).contains("bad.toml:1: name: "), "{e}");
        assert!(e.contains(why), "{bad}: {e}");
    }
}

#[test]
fn set_errors_are_blamed_on_the_set_argument() {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("good.toml");
    std::fs::write(&p, GOOD).unwrap();
    let p = p.to_str().unwrap();
    for (set, key) in [
        ("bogus.x=5", "bogus"),
        ("swarm.bogus=3", "swarm.bogus"),
        ("swarm.n=-4", "swarm.n"),
        ("seeds=three", "seeds"),
    ] {
        let e = fails(&["check", p, "--set", set]);
        assert!(
            one_line(&e).starts_with(&format!("error: --set: {key}: ")),
            "{set}: {e}"
        );
    }
}

#[test]
fn bad_schedule_files_name_their_file_and_line() {
    let tmp = tempfile::tempdir().unwrap();
    let with_schedule = |csv: &str| {
        std::fs::write(tmp.path().join("s.csv"), csv).unwrap();
        let text = format!("{GOOD}\n[scheduler]\nkind = \"file\"\nfile = \"s.csv\"\n");
        let cfg = tmp.path().join("bad.toml");
        std::fs::write(&cfg, text).unwrap();
        let e = fails(&["check", cfg.to_str().unwrap()]);
        one_line(&e)
            .replace(cfg.to_str().unwrap(), "bad.toml")
            .replace(tmp.path().join("s.csv").to_str().unwrap(), "s.csv")
    };
    for (csv, expected) in [
        (
            "round,robot\n1,0\n1,10\n",
            "s.csv:3: robot 10, but the swarm has 10 robots (numbered from 0)",
        ),
        (
            "round,robot\n2,0\n1,1\n",
            "s.csv:3: round 1 after round 2: rounds must increase",
        ),
        (
            "round,robot\n1,3\n1,3\n",
            "s.csv:3: robot 3 is listed twice in round 1",
        ),
        (
            "round,robot\n0,1\n",
            "s.csv:2: round 0: rounds are numbered from 1",
        ),
        (
            "round,robot\n1,x\n",
            "s.csv:2: column robot: `x` is not a robot index (0, 1, ...)",
        ),
        (
            "round;robot\n1;1\n",
            "s.csv:1: header must name columns round and robot, got `round;robot`",
        ),
    ] {
        let e = with_schedule(csv);
        assert_eq!(
            e,
            format!("error: bad.toml:16: scheduler.file: {expected}"),
            "{csv}"
        );
    }
    let cfg = tmp.path().join("bad.toml");
    std::fs::write(&cfg, format!("{GOOD}\n[scheduler]\nkind = \"file\"\n")).unwrap();
    let e = fails(&["check", cfg.to_str().unwrap()]);
    assert!(
        one_line(&e).ends_with(
            "bad.toml:15: scheduler.kind: kind = \"file\" needs scheduler.file, a CSV with header round,robot"
        ),
        "{e}"
    );
    std::fs::write(
        &cfg,
        format!("{GOOD}\n[scheduler]\nkind = \"ssync\"\nfile = \"s.csv\"\n"),
    )
    .unwrap();
    let e = fails(&["check", cfg.to_str().unwrap()]);
    assert!(
        one_line(&e).ends_with(
            "bad.toml:16: scheduler.file: a schedule file is read only with kind = \"file\", not \"ssync\""
        ),
        "{e}"
    );
}

#[test]
fn bad_fault_keys_are_named() {
    let faults = |body: &str| config_error(&format!("{GOOD}\n[faults]\n{body}\n")).0;
    for (body, expected) in [
        (
            "kind = \"crash\"",
            "bad.toml:15: faults.kind: [faults] needs count (robots) or fraction (of the robots)",
        ),
        (
            "kind = \"crash\"\ncount = 10",
            "bad.toml:16: faults.count: 10 faulty robots of 10: at least one robot must be correct",
        ),
        (
            "kind = \"crash\"\ncount = 1\nfraction = 0.5",
            "bad.toml:17: faults.fraction: give count or fraction, not both",
        ),
        (
            "kind = \"byzantine\"\nfraction = 1.5",
            "bad.toml:16: faults.fraction: must be in [0, 1], got 1.5",
        ),
        (
            "kind = \"crash\"\ncount = 1\nat = \"random\"",
            "bad.toml:17: faults.at: at = \"random\" needs until, the last round a crash may start",
        ),
        (
            "kind = \"crash\"\ncount = 1\nuntil = 5",
            "bad.toml:17: faults.until: until is read only with at = \"random\"",
        ),
        (
            "kind = \"crash\"\ncount = 1\nrule = \"away\"",
            "bad.toml:17: faults.rule: a rule is for byzantine robots; crashed robots stay",
        ),
        (
            "kind = \"byzantine\"\ncount = 1\nat = 3",
            "bad.toml:17: faults.at: crash rounds are for crashed robots; byzantine robots move at every activation",
        ),
    ] {
        let e = faults(body);
        assert_eq!(one_line(&e), format!("error: {expected}"), "{body}");
    }
    let e = faults("kind = \"lazy\"\ncount = 1");
    assert!(
        one_line(&e).starts_with("error: bad.toml:15: faults.kind"),
        "{e}"
    );
    let e = faults("kind = \"byzantine\"\ncount = 1\nrule = \"north\"");
    assert!(
        one_line(&e).starts_with("error: bad.toml:17: faults.rule"),
        "{e}"
    );
}

#[test]
fn bad_adversary_keys_are_named() {
    let (e, _) = config_error(&format!(
        "{GOOD}\n[scheduler]\nkind = \"adversary\"\nfairness = 0\n"
    ));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:16: scheduler.fairness: must be at least 1 (1: every robot every round)"
    );
    let (e, _) = config_error(&format!(
        "{}\n[scheduler]\nkind = \"adversary\"\n",
        GOOD.replace("side = 10.0", "side = 10.0\ndim = 3")
    ));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:16: scheduler.kind: the adversary compares hull perimeters: the plane only (dim = 2)"
    );
    let (e, _) = config_error(&format!(
        "{GOOD}\n[scheduler]\nkind = \"adversary\"\nobjective = \"fast\"\n"
    ));
    assert!(
        one_line(&e).starts_with("error: bad.toml:16: scheduler.objective"),
        "{e}"
    );
}

#[test]
fn a_negative_robot_radius_is_fails() {
    let (e, _) = config_error(&format!("{GOOD}\n[vision]\nrobot_radius = -0.5\n"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:15: vision.robot_radius: must be non-negative, got -0.5"
    );
}

#[test]
fn bad_durations_files_name_their_file_and_line() {
    let tmp = tempfile::tempdir().unwrap();
    let with_durations = |csv: &str, scheduler: &str| {
        std::fs::write(tmp.path().join("d.csv"), csv).unwrap();
        let text = format!("{GOOD}\n[scheduler]\n{scheduler}\ndurations = \"d.csv\"\n");
        let cfg = tmp.path().join("bad.toml");
        std::fs::write(&cfg, text).unwrap();
        let e = fails(&["check", cfg.to_str().unwrap()]);
        one_line(&e)
            .replace(cfg.to_str().unwrap(), "bad.toml")
            .replace(tmp.path().join("d.csv").to_str().unwrap(), "d.csv")
    };
    let asynchronous = "kind = \"async\"";
    for (csv, expected) in [
        (
            "robot,cycle,phase,ticks\n1,0,move,3\n10,0,move,3\n",
            "d.csv:3: robot 10, but the swarm has 10 robots (numbered from 0)",
        ),
        (
            "robot,cycle,phase,ticks\n1,4,move,3\n1,4,move,5\n",
            "d.csv:3: the move phase of robot 1's cycle 4 is given twice (first on line 2)",
        ),
        (
            "robot,cycle,phase,ticks\n1,4,look,3\n",
            "d.csv:2: column phase: `look` is not idle, compute or move",
        ),
        (
            "robot,cycle,phase,ticks\n1,4,idle,0\n",
            "d.csv:2: column ticks: `0` is not a whole number of ticks from 1 to 2^40",
        ),
        (
            "robot,cycle,phase,ticks\n1,-4,idle,2\n",
            "d.csv:2: column cycle: `-4` is not a cycle number (0, 1, ...)",
        ),
        (
            "robot,cycle,ticks\n1,4,2\n",
            "d.csv:1: header must name columns robot, cycle, phase and ticks, got `robot,cycle,ticks`",
        ),
        (
            "robot,cycle,phase,ticks\n2,0,compute,3\n3,0,idle,3\n",
            "d.csv:3: robot 3's cycle 0 has no idle phase: with scheduler.start = \"together\" every robot Looks at tick 0 (give cycle 0 an idle phase only with start = \"random\")",
        ),
    ] {
        let e = with_durations(csv, asynchronous);
        assert_eq!(
            e,
            format!("error: bad.toml:16: scheduler.durations: {expected}"),
            "{csv}"
        );
    }
    // With robots starting at random, cycle 0 has an Idle phase.
    let fine = "robot,cycle,phase,ticks\n3,0,idle,3\n";
    std::fs::write(tmp.path().join("d.csv"), fine).unwrap();
    let cfg = tmp.path().join("good.toml");
    std::fs::write(
        &cfg,
        format!(
            "{GOOD}\n[scheduler]\nkind = \"async\"\nstart = \"random\"\ndurations = \"d.csv\"\n"
        ),
    )
    .unwrap();
    assert!(
        monoculus(&["check", cfg.to_str().unwrap()])
            .status
            .success()
    );
    let e = with_durations(fine, "kind = \"ssync\"");
    assert_eq!(
        e,
        "error: bad.toml:16: scheduler.durations: durations are given only with kind = \"async\", not \"ssync\""
    );
}
