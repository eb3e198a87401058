//! docs/configuration.md's reference blocks are configs: the block of every key is a valid
//! config whose every live key is at its default (it resolves as a config that gives only
//! the required keys), its commented examples are valid where they stand alone, and the
//! `[hunt]` block is a valid hunt whose live keys are the defaults too.

use std::path::Path;

use monoculus_experiments::{Experiment, Registry};

/// The `toml` blocks of the page, in order.
fn blocks() -> Vec<String> {
    let page = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/configuration.md");
    let text = std::fs::read_to_string(page).unwrap();
    text.split("```toml\n")
        .skip(1)
        .map(|b| b[..b.find("```").unwrap()].to_string())
        .collect()
}

fn parse(text: &str) -> Experiment {
    let dir = tempfile::tempdir().unwrap();
    Experiment::parse(
        text,
        "configuration.md",
        dir.path(),
        &[],
        &Registry::builtin(),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

const REQUIRED: &str = "name = \"ld-vs-n\"\n[swarm]\nn = 10\ninit = \"square\"\n[algorithm]\nname = \"converge_locality\"\n";

#[test]
fn the_block_of_every_key_is_a_config_of_defaults() {
    let all = &blocks()[0];
    let (exp, required) = (parse(all), parse(REQUIRED));
    // What a run is made of: the same.
    assert_eq!(
        format!("{:?}", exp.cells[0].sim_config(0)),
        format!("{:?}", required.cells[0].sim_config(0)),
        "a live key of the reference block is not at its default"
    );
    // The resolved config too, but for the defaults the resolved text leaves implicit
    // (they follow from b, or are unlimited), which the block states.
    let implicit = ["eps_pos = ", "eps_axis = ", "range = "];
    let explicit: Vec<&str> = exp
        .resolved
        .lines()
        .filter(|l| !implicit.iter().any(|k| l.starts_with(k)))
        .collect();
    assert_eq!(
        explicit.join("\n"),
        required.resolved.trim_end(),
        "a live key of the reference block is not at its default"
    );
}

#[test]
fn its_commented_examples_are_valid() {
    let all = &blocks()[0];
    // Each commented `key = value` uncommented alone (the ones that need a file, an
    // algorithm with parameters, or another key beside them are tried below).
    let standalone = ["spread", "fairness", "non_rigid"];
    for key in standalone {
        let line = format!("# {key} = ");
        assert!(all.contains(&line), "{key} is in the block");
        parse(&all.replacen(&line, &format!("{key} = "), 1));
    }
    // The faults section, crash and byzantine.
    let faults = all
        .replace("# [faults]", "[faults]")
        .replace("# kind = \"crash\"", "kind = \"crash\"")
        .replace("# count = 3", "count = 3")
        .replace("# at = 0", "at = 0");
    assert!(parse(&faults).cells[0].spec.faults.is_some());
}

#[test]
fn the_hunt_block_is_a_hunt_of_defaults() {
    let hunt = &blocks()[1];
    let exp = parse(&format!("{REQUIRED}{hunt}"));
    let minimal = parse(&format!(
        "{REQUIRED}[hunt]\nproperty = \"hull_grows\"\nevaluations = 20000\n"
    ));
    assert_eq!(exp.cells[0].spec.hunt, minimal.cells[0].spec.hunt);
    for key in ["above", "n_min", "n_max", "seconds", "perturb", "max_ticks"] {
        let line = format!("# {key} = ");
        assert!(hunt.contains(&line), "{key} is in the hunt block");
        parse(&format!(
            "{REQUIRED}{}",
            hunt.replacen(&line, &format!("{key} = "), 1)
        ));
    }
}
