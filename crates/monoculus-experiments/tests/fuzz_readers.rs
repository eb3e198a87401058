//! Generated hostile inputs for every reader of user files: mutated configs, positions
//! CSVs, results rows, stress CSVs and provenance records. Whatever the bytes, a reader
//! returns a value or a one-line error; it never panics. Seeded, and bounded in count and
//! time, so that CI runs it on every push.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::{Duration, Instant};

use monoculus_experiments::Experiment;
use monoculus_experiments::positions::parse_positions;
use monoculus_experiments::results::{Provenance, read_rows, read_stress};

/// A small seeded generator (splitmix64).
struct Gen(u64);

impl Gen {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Pieces a hostile user (or a cut file) puts where they do not belong.
const TOKENS: &[&str] = &[
    "=",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "\"",
    "'",
    ",",
    ".",
    "#",
    "\n",
    "\r\n",
    " ",
    "-1",
    "0",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "NaN",
    "99999999999999999999",
    "3.5",
    "true",
    "maybe",
    "1.2.3",
    "\"x\"",
    "[swarm]",
    "[algorithm]",
    "[scheduler]",
    "[stop]",
    "n",
    "seeds",
    "name",
    "side",
    "init",
    "\"file\"",
    "\"clusters\"",
    "clusters = 1000000000",
    "dim = 3",
    "kind = \"async\"",
    "[1, 1]",
    "[]",
    "\u{0}",
    "é",
    "\u{feff}",
    "robot",
    "round",
    "config_hash",
    "4294967296",
    "18446744073709551616",
    "x,y",
    "\"../x\"",
    "\"\"",
];

fn mutate(g: &mut Gen, text: &str) -> String {
    let mut s: Vec<char> = text.chars().collect();
    for _ in 0..1 + g.below(4) {
        let at = g.below(s.len() + 1);
        match g.below(6) {
            0 if !s.is_empty() => {
                let end = (at + 1 + g.below(12)).min(s.len());
                s.drain(at.min(end)..end);
            }
            1 | 2 => {
                let t = TOKENS[g.below(TOKENS.len())];
                s.splice(at..at, t.chars());
            }
            3 => {
                // Duplicate a line.
                let lines: Vec<String> = s
                    .iter()
                    .collect::<String>()
                    .lines()
                    .map(String::from)
                    .collect();
                if !lines.is_empty() {
                    let k = g.below(lines.len());
                    let mut l = lines.clone();
                    l.insert(k, lines[k].clone());
                    s = l.join("\n").chars().collect();
                }
            }
            4 => s.truncate(at),
            _ => {
                if !s.is_empty() {
                    let k = at.min(s.len() - 1);
                    s[k] = TOKENS[g.below(TOKENS.len())].chars().next().unwrap_or('x');
                }
            }
        }
    }
    s.into_iter().collect()
}

fn one_line(e: &str, input: &str) {
    assert!(
        !e.contains('\n') && !e.is_empty(),
        "not one line: {e:?}\nfor input:\n{input}"
    );
}

/// Runs `f` on each of `cases` inputs (stopping early after `limit`), asserting no panic.
fn fuzz(name: &str, cases: usize, limit: Duration, mut f: impl FnMut(&mut Gen)) {
    let start = Instant::now();
    let mut g = Gen(0x6d6f_6e6f_6375_6c75 ^ name.len() as u64);
    for k in 0..cases {
        if start.elapsed() > limit {
            eprintln!("{name}: {k} cases in {limit:?}");
            return;
        }
        f(&mut g);
    }
}

fn configs() -> Vec<(String, std::path::PathBuf)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let mut out = Vec::new();
    let mut stack = vec![root];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                out.push((
                    std::fs::read_to_string(&p).unwrap(),
                    p.parent().unwrap().to_path_buf(),
                ));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn mutated_configs_parse_or_fail_in_one_line() {
    let sources = configs();
    fuzz("config", 20000, Duration::from_secs(20), |g| {
        let (text, base) = &sources[g.below(sources.len())];
        let input = mutate(g, text);
        let sets: Vec<String> = if g.below(4) == 0 {
            vec![mutate(g, "swarm.n=10")]
        } else {
            Vec::new()
        };
        let got = catch_unwind(AssertUnwindSafe(|| {
            Experiment::parse(
                &input,
                "c.toml",
                base,
                &sets,
                &monoculus_experiments::Registry::builtin(),
            )
        }));
        match got {
            Err(_) => panic!("parse panicked on:\n{input}\nwith --set {sets:?}"),
            Ok(Err(e)) => one_line(&e.to_string(), &input),
            Ok(Ok(exp)) => assert!(!exp.cells.is_empty()),
        }
    });
}

#[test]
fn mutated_positions_parse_or_fail_in_one_line() {
    let good = "x,y,z\n0,0,0\n1.5,2,-3\n1e3,4,5\n-2,0.25,1\n";
    fuzz("positions", 10000, Duration::from_secs(10), |g| {
        let input = mutate(g, good);
        match catch_unwind(|| parse_positions(&input, "p.csv")) {
            Err(_) => panic!("positions panicked on:\n{input}"),
            Ok(Err(e)) => one_line(&e.to_string(), &input),
            Ok(Ok(p)) => assert!(!p.rows.is_empty()),
        }
    });
}

#[test]
fn mutated_result_files_read_or_fail_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "name = \"f\"\nseeds = 3\n[swarm]\nn = [4, 6]\ninit = \"square\"\nside = 4.0\n[algorithm]\nname = \"converge_locality\"\n";
    let exp = Experiment::parse(
        text,
        "f.toml",
        tmp.path(),
        &[],
        &monoculus_experiments::Registry::builtin(),
    )
    .unwrap();
    let out = tmp.path().join("o");
    monoculus_experiments::run_experiment(&exp, &out, Default::default(), &()).unwrap();
    let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let provenance = std::fs::read_to_string(out.join("provenance.toml")).unwrap();
    let stress = "measurement,measurements,n,threads,algorithm,scheduler,backend,timing,init,seed,rounds,setup_s,total_s,round_s_min,round_s_median,round_s_max,activations,activations_per_s,peak_memory_mb,host,job,monoculus_version,git_commit\n0,1,100,1,converge_locality,fsync,index,,square,1,2,0.1,0.2,0.1,0.1,0.1,200,1000,12,h,,0.1.0,abc\n";
    let file = tmp.path().join("f.csv");
    fuzz("results", 5000, Duration::from_secs(20), |g| {
        let (which, good) = match g.below(3) {
            0 => ("runs", runs.as_str()),
            1 => ("provenance", provenance.as_str()),
            _ => ("stress", stress),
        };
        let input = mutate(g, good);
        std::fs::write(&file, &input).unwrap();
        let got = catch_unwind(AssertUnwindSafe(|| -> Result<(), String> {
            match which {
                "runs" => {
                    let found = read_rows(&file).map_err(|e| e.to_string())?;
                    found.check(&exp, &file).map_err(|e| e.to_string())?;
                }
                "provenance" => {
                    Provenance::read(&file).map_err(|e| e.to_string())?;
                }
                _ => {
                    read_stress(&file).map_err(|e| e.to_string())?;
                }
            }
            Ok(())
        }));
        match got {
            Err(_) => panic!("{which} reader panicked on:\n{input}"),
            Ok(Err(e)) => one_line(&e, &input),
            Ok(Ok(())) => {}
        }
    });
}
