//! Shards, locks, merge, `--shard auto`, the Slurm scripts and stress sweeps, end to end
//! (the same scripts on a real Slurm: `scripts/slurm-ci.sh`, run by `.ci/run`).

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{csv_rows_without, ok, rows_without_wall, s, write_config};

const SWEEP: &str = r#"
name = "sweep"
seeds = 6

[swarm]
n = [8, 30]
init = "square"
side = 8.0

[algorithm]
name = ["converge_locality", "converge_quadrant"]
"#;

/// Runs that take a while (tens of milliseconds each), so that processes overlap.
const SLOW: &str = r#"
name = "slow"
seeds = 64

[swarm]
n = 1000
init = "square"
side = 40.0

[algorithm]
name = "converge_locality"
target = "random"
"#;

const BATCH_VARS: [&str; 14] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_JOB_ID",
    "SLURM_JOB_ID",
    "SLURM_CPUS_PER_TASK",
    "SGE_TASK_ID",
    "LSB_JOBINDEX",
    "PBS_ARRAY_INDEX",
    "PBS_ARRAYID",
    "JOB_ID",
    "LSB_JOBID",
];

/// `monoculus` with no batch-system variables but `env`.
fn command(args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_monoculus"));
    c.args(args);
    for v in BATCH_VARS {
        c.env_remove(v);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c
}

fn output(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let out = command(args, env).output().unwrap();
    let (o, e) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert!(!e.contains("panicked"), "{args:?} panicked: {e}");
    (out.status.code().unwrap_or(-1), o, e)
}

/// Runs `monoculus slurm`'s scripts as Slurm would: every array task, then the merge.
fn run_scripts(slurm_dir: &Path, tasks: usize) {
    for k in 0..tasks {
        let st = Command::new("bash")
            .arg(slurm_dir.join("array.sh"))
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap();
        assert!(st.success(), "task {k}");
    }
    let st = Command::new("bash")
        .arg(slurm_dir.join("merge.sh"))
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(st.success(), "merge");
}

/// The merged folder equals the whole run: runs.csv but wall_ms, and summary.csv.
fn assert_same_results(whole: &Path, merged: &Path) {
    assert_eq!(rows_without_wall(whole), rows_without_wall(merged));
    assert_eq!(
        csv_rows_without(&whole.join("runs.csv"), &["wall_ms"]),
        csv_rows_without(&merged.join("runs.csv"), &["wall_ms"]),
        "runs.csv in the same order"
    );
    assert_eq!(
        std::fs::read_to_string(whole.join("summary.csv")).unwrap(),
        std::fs::read_to_string(merged.join("summary.csv")).unwrap()
    );
    assert_eq!(
        std::fs::read_to_string(whole.join("config.toml")).unwrap(),
        std::fs::read_to_string(merged.join("config.toml")).unwrap()
    );
}

#[test]
fn shards_merge_into_the_whole_run_with_provenance() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let (whole, parts) = (tmp.path().join("whole"), tmp.path().join("parts"));
    ok(&["run", s(&cfg), "--out", s(&whole)]);
    for k in 0..4 {
        let out = ok(&[
            "run",
            s(&cfg),
            "--out",
            s(&parts),
            "--shard",
            &format!("{k}/4"),
        ]);
        assert!(out.contains(&format!("shard {k}/4: ran 6 runs")), "{out}");
        assert!(parts.join(format!("shards/{k}-of-4.csv")).exists());
    }
    assert!(!parts.join("runs.csv").exists());
    let merged = ok(&["merge", s(&parts)]);
    assert!(
        merged.contains("merged 24 of 24 runs from 4 shards"),
        "{merged}"
    );
    assert_same_results(&whole, &parts);
    // Provenance: the build, the config's hash, and every shard's process.
    let p = std::fs::read_to_string(parts.join("provenance.toml")).unwrap();
    let hash = &csv_rows_without(&parts.join("runs.csv"), &[])[0];
    let version = format!("monoculus_version = \"{}\"", env!("CARGO_PKG_VERSION"));
    assert!(p.contains(&version), "{p}");
    assert!(p.contains("git_commit = "), "{p}");
    assert!(
        p.contains(&format!("config_hash = \"{}\"", hash.last().unwrap())),
        "{p}"
    );
    for k in 0..4 {
        assert!(p.contains(&format!("shard = \"{k}/4\"")), "{p}");
    }
    assert!(p.contains("host = "), "{p}");
    // A shard rerun finds its runs done; a plain run finds the merged folder complete.
    let again = ok(&["run", s(&cfg), "--out", s(&parts), "--shard", "2/4"]);
    assert!(again.contains("ran 0 runs, 6 already done"), "{again}");
    let plain = ok(&["run", s(&cfg), "--out", s(&parts)]);
    assert!(plain.contains("ran 0 runs, 24 already done"), "{plain}");
}

#[test]
fn costly_cells_are_spread_over_all_shards() {
    let tmp = tempfile::tempdir().unwrap();
    // One seed, cells of growing n: shard k mod N would give both large cells to one.
    let cfg = write_config(
        tmp.path(),
        "name = \"spread\"\nseeds = 1\n[swarm]\nn = [4, 200, 5, 300]\ninit = \"square\"\nside = 5.0\n[algorithm]\nname = \"converge_locality\"\n",
    );
    let out = tmp.path().join("o");
    for k in 0..2 {
        ok(&[
            "run",
            s(&cfg),
            "--out",
            s(&out),
            "--shard",
            &format!("{k}/2"),
        ]);
    }
    let large: Vec<usize> = (0..2)
        .map(|k| {
            let f = out.join(format!("shards/{k}-of-2.csv"));
            let n = csv::Reader::from_path(&f)
                .unwrap()
                .headers()
                .unwrap()
                .iter()
                .position(|c| c == "n")
                .unwrap();
            csv_rows_without(&f, &[])
                .iter()
                .filter(|r| r[n].parse::<usize>().unwrap() >= 200)
                .count()
        })
        .collect();
    assert_eq!(large, vec![1, 1]);
}

#[test]
fn merge_names_the_missing_runs_of_each_shard() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "0/3"]);
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "1/3"]);
    // Shard 1 lost its last two rows, one of them cut short.
    let f = out.join("shards/1-of-3.csv");
    let text = std::fs::read_to_string(&f).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let n = lines.len();
    std::fs::write(
        &f,
        format!("{}\n{}", lines[..n - 2].join("\n"), &lines[n - 2][..12]),
    )
    .unwrap();
    let (code, _, err) = output(&["merge", s(&out)], &[]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("shard 1/3 (") && err.contains("2 of 8 runs missing"),
        "{err}"
    );
    assert!(
        err.contains("shard 2/3 (never started): 8 of 8 runs missing"),
        "{err}"
    );
    assert!(err.contains("a row cut short"), "{err}");
    assert!(
        err.contains("10 of 24 runs missing, in shards 1/3, 2/3"),
        "{err}"
    );
    assert!(!out.join("runs.csv").exists() && !out.join("summary.csv").exists());
    // --partial summarises what is there.
    let partial = ok(&["merge", s(&out), "--partial"]);
    assert!(partial.contains("merged 14 of 24 runs"), "{partial}");
    assert_eq!(csv_rows_without(&out.join("runs.csv"), &[]).len(), 14);
    // A plain run into a folder of unfinished shards is refused.
    let (code, _, err) = output(&["run", s(&cfg), "--out", s(&out)], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("holds shard files"), "{err}");
    // The shards resume (shard 1 repairs its cut line), then the merge is whole.
    let r1 = ok(&["run", s(&cfg), "--out", s(&out), "--shard", "1/3"]);
    assert!(r1.contains("ran 2 runs, 6 already done"), "{r1}");
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "2/3"]);
    let whole = tmp.path().join("whole");
    ok(&["run", s(&cfg), "--out", s(&whole)]);
    ok(&["merge", s(&out)]);
    assert_same_results(&whole, &out);
}

#[test]
fn merge_refuses_shards_of_another_config_or_build() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "0/2"]);
    ok(&["run", s(&cfg), "--out", s(&out), "--shard", "1/2"]);
    let record = out.join("shards/1-of-2.toml");
    let text = std::fs::read_to_string(&record).unwrap();
    let edited = text
        .lines()
        .map(|l| {
            if l.starts_with("git_commit") {
                "git_commit = \"0000000\"".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(&record, edited).unwrap();
    let (code, _, err) = output(&["merge", s(&out)], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("1-of-2.toml") && err.contains("commit 0000000"),
        "{err}"
    );
    // The shard itself refuses to continue rows of another build, unless told to redo.
    let (code, _, err) = output(&["run", s(&cfg), "--out", s(&out), "--shard", "1/2"], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("was written by monoculus"), "{err}");
    ok(&[
        "run",
        s(&cfg),
        "--out",
        s(&out),
        "--shard",
        "1/2",
        "--force",
    ]);
    ok(&["merge", s(&out)]);
    // Another config into the folder: refused, by a shard too.
    let (code, _, err) = output(
        &[
            "run",
            s(&cfg),
            "--out",
            s(&out),
            "--shard",
            "0/2",
            "--set",
            "seeds=2",
        ],
        &[],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("holds a different experiment"), "{err}");
    // Shards of two splits in one folder.
    let (code, _, err) = output(&["run", s(&cfg), "--out", s(&out), "--shard", "0/3"], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("split into 2 shards"), "{err}");
    let (code, _, err) = output(&["merge", s(&tmp.path().join("none"))], &[]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn rows_of_another_experiment_are_refused_when_config_toml_is_gone() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let out = tmp.path().join("o");
    ok(&[
        "run",
        s(&cfg),
        "--out",
        s(&out),
        "--set",
        "algorithm.name=converge_locality",
    ]);
    std::fs::remove_file(out.join("config.toml")).unwrap();
    let (code, _, err) = output(
        &[
            "run",
            s(&cfg),
            "--out",
            s(&out),
            "--set",
            "algorithm.name=converge_quadrant",
        ],
        &[],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("runs.csv:2: a row of another experiment"),
        "{err}"
    );
}

#[test]
fn a_second_process_on_a_shard_or_folder_is_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SLOW);
    let out = tmp.path().join("o");
    let mut first = command(
        &[
            "run",
            s(&cfg),
            "--out",
            s(&out),
            "--shard",
            "0/2",
            "--threads",
            "1",
        ],
        &[],
    )
    .stdout(Stdio::null())
    .stderr(Stdio::null())
    .spawn()
    .unwrap();
    // Wait until it holds its shard.
    let lock = out.join("shards/0-of-2.lock");
    let start = Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |t| t.is_empty()) {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "the shard never started"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let (code, _, err) = output(&["run", s(&cfg), "--out", s(&out), "--shard", "0/2"], &[]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("0-of-2.csv: in use by pid"), "{err}");
    // Another shard may run beside it; a plain run, --force or a merge may not.
    for args in [
        vec!["run", s(&cfg), "--out", s(&out)],
        vec!["run", s(&cfg), "--out", s(&out), "--force"],
        vec!["merge", s(&out)],
    ] {
        let (code, _, err) = output(&args, &[]);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains("in use by shard 0/2 (pid"), "{args:?}: {err}");
    }
    first.kill().unwrap();
    first.wait().unwrap();
    // Killed: the lock is gone with it.
    ok(&[
        "run",
        s(&cfg),
        "--out",
        s(&out),
        "--shard",
        "0/2",
        "--threads",
        "1",
    ]);
}

#[test]
fn two_plain_runs_into_one_folder_are_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SLOW);
    let out = tmp.path().join("o");
    let mut first = command(&["run", s(&cfg), "--out", s(&out), "--threads", "1"], &[])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = out.join(".monoculus.lock");
    let start = Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |t| t.is_empty()) {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "the run never started"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let (code, _, err) = output(&["run", s(&cfg), "--out", s(&out), "--force"], &[]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("in use by pid") && err.contains("on host"),
        "{err}"
    );
    first.kill().unwrap();
    first.wait().unwrap();
}

#[test]
fn eight_shards_started_at_once_one_killed_and_rerun_merge_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SLOW);
    let out = tmp.path().join("o");
    let mut children: Vec<_> = (0..8)
        .map(|k| {
            command(
                &[
                    "run",
                    s(&cfg),
                    "--out",
                    s(&out),
                    "--shard",
                    &format!("{k}/8"),
                    "--threads",
                    "1",
                ],
                &[],
            )
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
        })
        .collect();
    // Kill shard 5 once it has written a row or two.
    let f5 = out.join("shards/5-of-8.csv");
    let start = Instant::now();
    while std::fs::read_to_string(&f5).map_or(0, |t| t.lines().count()) < 2
        && start.elapsed() < Duration::from_secs(30)
    {
        std::thread::sleep(Duration::from_millis(5));
    }
    children[5].kill().unwrap();
    for (k, c) in children.iter_mut().enumerate() {
        let status = c.wait().unwrap();
        if k != 5 {
            let mut err = String::new();
            std::io::Read::read_to_string(c.stderr.as_mut().unwrap(), &mut err).unwrap();
            assert!(status.success(), "shard {k}/8: {err}");
        }
    }
    let rerun = ok(&["run", s(&cfg), "--out", s(&out), "--shard", "5/8"]);
    let ran = common::reported(&rerun.replace("ran ", "ran="), "ran");
    assert!(ran > 0 && ran < 8, "killed mid-sweep, resumed: {rerun}");
    ok(&["merge", s(&out)]);
    let whole = tmp.path().join("whole");
    ok(&["run", s(&cfg), "--out", s(&whole)]);
    assert_same_results(&whole, &out);
}

#[test]
fn shard_auto_reads_the_job_array() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let out = tmp.path().join("o");
    // --array=10-16:2: tasks 10, 12, 14, 16 are shards 0..3 of 4.
    for id in ["10", "12", "14", "16"] {
        let env = [
            ("SLURM_ARRAY_JOB_ID", "77"),
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_MIN", "10"),
            ("SLURM_ARRAY_TASK_MAX", "16"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_CPUS_PER_TASK", "1"),
        ];
        let (code, o, e) = output(&["run", s(&cfg), "--out", s(&out), "--shard", "auto"], &env);
        assert_eq!(code, 0, "{e}");
        let k = (id.parse::<usize>().unwrap() - 10) / 2;
        assert!(o.contains(&format!("shard {k}/4: ran 6 runs")), "{o}");
        let record = std::fs::read_to_string(out.join(format!("shards/{k}-of-4.toml"))).unwrap();
        assert!(record.contains(&format!("job = \"77_{id}\"")), "{record}");
    }
    ok(&["merge", s(&out)]);
    let (code, _, e) = output(&["run", s(&cfg), "--out", s(&out), "--shard", "auto"], &[]);
    assert_eq!(code, 2);
    assert!(e.contains("--shard auto: not in a job array"), "{e}");
    let (code, _, e) = output(
        &["run", s(&cfg), "--out", s(&out)],
        &[("SLURM_CPUS_PER_TASK", "many")],
    );
    assert_eq!(code, 2);
    assert!(e.contains("SLURM_CPUS_PER_TASK=many"), "{e}");
    let (code, _, e) = output(&["run", s(&cfg), "--threads", "100000"], &[]);
    assert_eq!(code, 2);
    assert!(e.contains("--threads 100000: at most"), "{e}");
}

#[test]
fn slurm_scripts_run_the_shards_and_the_merge() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SWEEP);
    let out = tmp.path().join("o");
    let printed = ok(&[
        "slurm",
        s(&cfg),
        "--shards",
        "3",
        "--out",
        s(&out),
        "--partition",
        "short",
        "--time",
        "00:10:00",
        "--mem",
        "1G",
        "--account",
        "lab",
        "--cpus-per-task",
        "2",
        "--sbatch",
        "--qos=low",
        "--set",
        "seeds=5",
        "--progress",
        "300",
    ]);
    assert!(printed.contains("sbatch --parsable"), "{printed}");
    assert!(printed.contains("--dependency=afterok:"), "{printed}");
    let array = std::fs::read_to_string(out.join("slurm/array.sh")).unwrap();
    for line in [
        "#SBATCH --array=0-2",
        "#SBATCH --partition=short",
        "#SBATCH --time=00:10:00",
        "#SBATCH --mem=1G",
        "#SBATCH --account=lab",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --qos=low",
        "--shard \"${SLURM_ARRAY_TASK_ID}/3\"",
        "--set seeds=5",
        "--progress 300",
    ] {
        assert!(array.contains(line), "{line} not in {array}");
    }
    assert!(
        out.join("slurm/logs").is_dir(),
        "the log folder exists before submission"
    );
    let merge = std::fs::read_to_string(out.join("slurm/merge.sh")).unwrap();
    assert!(
        merge.contains(&format!("merge {}", out.display())),
        "{merge}"
    );
    // The scripts themselves, run as Slurm would run each task.
    run_scripts(&out.join("slurm"), 3);
    let whole = tmp.path().join("whole");
    ok(&["run", s(&cfg), "--out", s(&whole), "--set", "seeds=5"]);
    assert_same_results(&whole, &out);
    // Bad arguments.
    let (code, _, e) = output(&["slurm", s(&cfg), "--shards", "0", "--out", s(&out)], &[]);
    assert_eq!(code, 2, "{e}");
    let (code, _, e) = output(&["slurm", "--shards", "2", "--out", s(&out)], &[]);
    assert_eq!(code, 2, "{e}");
    let (code, _, e) = output(
        &[
            "slurm",
            s(&cfg),
            "--shards",
            "2",
            "--out",
            s(&out),
            "--set",
            "seeds=2",
        ],
        &[],
    );
    assert_eq!(code, 2, "{e}");
    assert!(e.contains("holds a different experiment"), "{e}");
}

#[test]
fn stress_sweeps_write_one_row_per_measurement_and_shard() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("stress.csv");
    let args = [
        "stress",
        "--n",
        "100,400",
        "--threads",
        "1,2",
        "--rounds",
        "2",
        "--csv",
        s(&csv),
    ];
    let (code, o, e) = output(&args, &[]);
    assert_eq!(code, 0, "{e}");
    assert!(
        o.lines().last().unwrap().starts_with("activations_per_s="),
        "{o}"
    );
    let rows = csv_rows_without(&csv, &[]);
    assert_eq!(rows.len(), 4);
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    for col in [
        "n",
        "threads",
        "algorithm",
        "scheduler",
        "round_s_min",
        "round_s_median",
        "round_s_max",
        "activations_per_s",
        "peak_memory_mb",
        "host",
    ] {
        assert!(h.iter().any(|c| c == col), "{col} in {h:?}");
    }
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let got: Vec<(String, String)> = rows
        .iter()
        .map(|r| (r[col("n")].clone(), r[col("threads")].clone()))
        .collect();
    let want: Vec<(String, String)> = [("100", "1"), ("100", "2"), ("400", "1"), ("400", "2")]
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    assert_eq!(got, want);
    for r in &rows {
        // 2 rounds of n activations each, at a positive rate.
        let n: f64 = r[col("n")].parse().unwrap();
        assert_eq!(r[col("activations")].parse::<f64>().unwrap(), 2.0 * n);
        assert!(r[col("activations_per_s")].parse::<f64>().unwrap() > 0.0);
    }
    // Rerun: every measurement is there already.
    let (_, _, e) = output(&args, &[]);
    assert_eq!(e.matches("already measured").count(), 4, "{e}");
    // Sharded, then merged.
    let sharded = tmp.path().join("sharded.csv");
    for k in 0..3 {
        let shard = format!("{k}/3");
        let (code, _, e) = output(
            &[
                "stress",
                "--n",
                "100,400",
                "--threads",
                "1,2",
                "--rounds",
                "2",
                "--csv",
                s(&sharded),
                "--shard",
                &shard,
            ],
            &[],
        );
        assert_eq!(code, 0, "{e}");
    }
    assert!(tmp.path().join("sharded.0-of-3.csv").exists());
    ok(&["merge", s(&sharded)]);
    let merged = csv_rows_without(&sharded, &[]);
    let keys = |rows: &[Vec<String>]| -> Vec<Vec<String>> {
        rows.iter()
            .map(|r| {
                ["measurement", "n", "threads", "activations"]
                    .iter()
                    .map(|c| r[col(c)].clone())
                    .collect()
            })
            .collect()
    };
    assert_eq!(keys(&merged), keys(&rows));
    // Under a Slurm task, --threads defaults to its CPUs.
    let one = tmp.path().join("one.csv");
    let (code, _, e) = output(
        &["stress", "--n", "50", "--rounds", "1", "--csv", s(&one)],
        &[("SLURM_CPUS_PER_TASK", "1")],
    );
    assert_eq!(code, 0, "{e}");
    assert_eq!(csv_rows_without(&one, &[])[0][col("threads")], "1");
    let (code, _, e) = output(
        &["stress", "--n", "50", "--rounds", "1", "--shard", "0/2"],
        &[],
    );
    assert_eq!(code, 2, "{e}");
    assert!(e.contains("needs --csv"), "{e}");
}

#[test]
fn slurm_stress_writes_the_stress_array() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("st");
    ok(&[
        "slurm",
        "--stress",
        "--shards",
        "2",
        "--out",
        s(&out),
        "--",
        "--n",
        "100,200",
        "--rounds",
        "1",
        "--threads",
        "1",
    ]);
    let array = std::fs::read_to_string(out.join("slurm/array.sh")).unwrap();
    assert!(
        array.contains(" stress --n 100,200 --rounds 1 --threads 1 --csv "),
        "{array}"
    );
    run_scripts(&out.join("slurm"), 2);
    assert_eq!(csv_rows_without(&out.join("stress.csv"), &[]).len(), 2);
    let (code, _, e) = output(
        &[
            "slurm",
            "--stress",
            "--shards",
            "2",
            "--out",
            s(&out),
            "--",
            "--bogus",
        ],
        &[],
    );
    assert_eq!(code, 2, "{e}");
    assert!(e.contains("--stress options"), "{e}");
    let (code, _, e) = output(
        &[
            "slurm",
            "--stress",
            "--shards",
            "2",
            "--out",
            s(&out),
            "--progress",
            "60",
            "--",
            "--n",
            "100",
            "--rounds",
            "1",
        ],
        &[],
    );
    assert_eq!(code, 2, "{e}");
    assert!(e.contains("--progress"), "{e}");
}

#[test]
fn merge_rebuilds_configs_with_files_overrides_and_keys_out_of_schema_order() {
    let tmp = tempfile::tempdir().unwrap();
    let sub = tmp.path().join("cfgs");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(sub.join("pts.csv"), "x,y\n0,0\n3,0\n0,3\n3,3\n1.5,1.5\n").unwrap();
    // The swept keys are written algorithm first, swarm second: the resolved config.toml
    // orders them by the schema, the cells keep the order written.
    let cfg = sub.join("c.toml");
    std::fs::write(
        &cfg,
        "name = \"files\"\nseeds = 3\n[algorithm]\nname = [\"converge_locality\", \"converge_quadrant\"]\nstep = [1.0, 0.5]\n[swarm]\ninit = \"file\"\nfile = \"pts.csv\"\nside = [8.0, 9.0]\n",
    )
    .unwrap();
    let (whole, parts) = (tmp.path().join("whole"), tmp.path().join("parts"));
    let set = ["--set", "stop.max_rounds=500"];
    let mut args = vec!["run", s(&cfg), "--out", s(&whole)];
    args.extend(set);
    ok(&args);
    for k in 0..2 {
        let shard = format!("{k}/2");
        let mut args = vec!["run", s(&cfg), "--out", s(&parts), "--shard", &shard];
        args.extend(set);
        ok(&args);
    }
    // The config file may change or vanish after the shards ran: merge needs only the folder
    // (and the positions file).
    std::fs::write(&cfg, "garbage").unwrap();
    ok(&["merge", s(&parts)]);
    assert_same_results(&whole, &parts);
}
