//! The golden test: the exact outcomes of a few small sweeps, every algorithm under every
//! scheduler, in the plane and in space, with the target policies, the exact backend, the
//! error models and every initial shape. Each sweep's `runs.csv` without `wall_ms` and
//! `config_hash` hashes to the value in `tests/golden.txt` (the outcomes, and on a line
//! of their own the verdicts, younger than the outcomes' hashes); a change that moves any bit
//! of any result fails here. After a change that is meant to change results, regenerate
//! the file with `MONOCULUS_BLESS=1 cargo test -p monoculus-experiments --test golden`
//! and say why in the commit.

use std::collections::BTreeMap;
use std::path::Path;

use monoculus_experiments::{Experiment, run_experiment};

const SWEEPS: &[(&str, &str)] = &[
    (
        "plane_all_algorithms_all_schedulers",
        r#"
name = "g1"
seeds = 3
[swarm]
n = [7, 20]
init = "square"
side = 8.0
[algorithm]
name = ["converge_locality", "converge_quadrant", "converge_quadrant_termination", "center_of_gravity", "median", "angle_bisector"]
[scheduler]
kind = ["fsync", "ssync", "sequential", "async"]
p = 0.5
fairness = 3
idle = { kind = "uniform", min = 1, max = 4 }
compute = { kind = "uniform", min = 1, max = 3 }
move = { kind = "exponential", mean = 2.0 }
start = "random"
[stop]
max_rounds = 3000
"#,
    ),
    (
        "space_all_algorithms",
        r#"
name = "g2"
seeds = 2
[swarm]
n = [9, 24]
dim = 3
init = ["square", "disc"]
side = 6.0
[algorithm]
name = ["converge_locality", "converge_quadrant", "converge_quadrant_termination", "center_of_gravity"]
[scheduler]
kind = ["fsync", "async"]
idle = { kind = "uniform", min = 1, max = 3 }
[stop]
max_rounds = 3000
"#,
    ),
    (
        "targets_backends_shapes",
        r#"
name = "g3"
seeds = 3
[swarm]
n = 40
init = ["square", "disc", "line", "lattice", "clusters"]
side = 12.0
clusters = 3
[algorithm]
name = ["converge_locality", "converge_quadrant"]
target = ["random", "random_listing"]
[vision]
backend = ["index", "exact"]
[scheduler]
kind = ["fsync", "sequential"]
order = "random"
[stop]
max_rounds = 5000
"#,
    ),
    (
        "error_models",
        r#"
name = "g4"
seeds = 3
[swarm]
n = 30
init = "square"
side = 10.0
[algorithm]
name = ["converge_locality", "converge_quadrant"]
[errors]
flip_p = [0.0, 0.3]
flip_window = 0.25
angle_sigma = [0.0, 0.05]
step_factor = { kind = "uniform", min = 0.5, max = 1.5 }
non_rigid = { delta_min = 0.4 }
[stop]
max_rounds = 5000
"#,
    ),
];

/// Columns younger than the hashes of the outcomes, hashed on their own: `faulty` (the
/// faults tests check it) and the verdicts of 0.3.
const VERDICT_COLUMNS: [&str; 5] = ["stuck", "stopped_by", "goal", "final_radius", "faulty"];

/// 64-bit FNV-1a of the rows of runs.csv over the columns `keep` accepts.
fn hash_of(runs: &Path, keep: impl Fn(&str) -> bool) -> (String, usize) {
    let mut r = csv::Reader::from_path(runs).unwrap();
    let header = r.headers().unwrap().clone();
    let keep: Vec<usize> = (0..header.len()).filter(|&i| keep(&header[i])).collect();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |s: &str| {
        for b in s.bytes().chain([b'\n']) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    eat(&keep
        .iter()
        .map(|&i| &header[i])
        .collect::<Vec<_>>()
        .join(","));
    let mut rows = 0;
    for rec in r.records() {
        let rec = rec.unwrap();
        eat(&keep.iter().map(|&i| &rec[i]).collect::<Vec<_>>().join(","));
        rows += 1;
    }
    (format!("{h:016x}"), rows)
}

/// The outcomes: every column but `wall_ms`, `config_hash` and [`VERDICT_COLUMNS`].
fn outcome_hash(runs: &Path) -> (String, usize) {
    hash_of(runs, |c| {
        !matches!(c, "wall_ms" | "config_hash") && !VERDICT_COLUMNS.contains(&c)
    })
}

/// The verdicts: [`VERDICT_COLUMNS`] with `converged` and the seed.
fn verdict_hash(runs: &Path) -> (String, usize) {
    hash_of(runs, |c| {
        matches!(c, "seed" | "converged") || VERDICT_COLUMNS.contains(&c)
    })
}

#[test]
fn outcomes_are_bit_identical_to_the_checked_in_ones() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden.txt");
    let tmp = tempfile::tempdir().unwrap();
    let mut got = BTreeMap::new();
    for (name, text) in SWEEPS {
        let exp = Experiment::parse(
            text,
            name,
            tmp.path(),
            &[],
            &monoculus_experiments::Registry::builtin(),
        )
        .unwrap();
        let out = tmp.path().join(name);
        run_experiment(&exp, &out, Default::default(), &()).unwrap();
        let (hash, rows) = outcome_hash(&out.join("runs.csv"));
        assert_eq!(rows, exp.cells.len() * exp.seeds.len());
        got.insert(name.to_string(), format!("{hash} {rows}"));
        let (hash, rows) = verdict_hash(&out.join("runs.csv"));
        got.insert(format!("{name}/verdicts"), format!("{hash} {rows}"));
    }
    let text: String = got.iter().map(|(k, v)| format!("{k} {v}\n")).collect();
    if std::env::var_os("MONOCULUS_BLESS").is_some() {
        std::fs::write(&golden, &text).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&golden).expect("tests/golden.txt");
    assert_eq!(
        text, want,
        "results changed; if that is intended, regenerate with MONOCULUS_BLESS=1 and say why"
    );
}
