//! `merge` rebuilds a sweep's experiment from a shard's provenance record: for every
//! bundled config it must be the same experiment (resolved text, hash, cells in order),
//! and the resolved `config.toml` must read back as itself.

use std::path::Path;

use monoculus_experiments::Experiment;
use monoculus_experiments::results::Provenance;

fn configs(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            configs(&p, out);
        } else if p.extension().is_some_and(|x| x == "toml") {
            out.push(p);
        }
    }
}

#[test]
fn every_bundled_config_reads_back_as_itself() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let mut all = Vec::new();
    configs(&root, &mut all);
    assert!(all.len() >= 10, "{all:?}");
    for path in all {
        let exp =
            Experiment::load(&path, &[], &monoculus_experiments::Registry::builtin()).unwrap();
        let resolved = Experiment::parse(
            &exp.resolved,
            "config.toml",
            &exp.base,
            &[],
            &monoculus_experiments::Registry::builtin(),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(resolved.resolved, exp.resolved, "{}", path.display());
        let again = Provenance::new(&exp)
            .experiment("record", &monoculus_experiments::Registry::builtin())
            .unwrap();
        assert_eq!(again.resolved, exp.resolved, "{}", path.display());
        assert_eq!(again.hash, exp.hash);
        let keys = |e: &Experiment| e.cells.iter().map(|c| c.key.clone()).collect::<Vec<_>>();
        assert_eq!(keys(&again), keys(&exp), "{}", path.display());
    }
}
