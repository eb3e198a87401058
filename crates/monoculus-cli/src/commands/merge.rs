use std::collections::BTreeMap;
use std::path::PathBuf;

use monoculus_experiments::results::{MissingRuns, merge as merge_shards, merge_stress};
use monoculus_experiments::shard::job_id;

use super::{Failure, env_var};

#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// The results folder whose shards/ to merge; or a stress CSV (FILE.csv), whose shard
    /// files FILE.I-of-N.csv beside it to join into it.
    dir: PathBuf,
    /// Write runs.csv and summary.csv from the runs present even if some are missing.
    #[arg(long)]
    partial: bool,
}

/// "cell `n=20`: seeds 3, 7; cell `n=50`: seed 1" (at most a few cells, then a count).
fn describe(m: &MissingRuns, exp: &monoculus_experiments::Experiment) -> String {
    let mut by_cell: BTreeMap<usize, Vec<u64>> = BTreeMap::new();
    for r in &m.missing {
        by_cell.entry(r.cell).or_default().push(r.seed);
    }
    let mut parts: Vec<String> = by_cell
        .iter()
        .take(4)
        .map(|(&c, seeds)| {
            let key = &exp.cells[c].key;
            let shown: Vec<String> = seeds.iter().take(8).map(u64::to_string).collect();
            let more = if seeds.len() > 8 {
                format!(" and {} more", seeds.len() - 8)
            } else {
                String::new()
            };
            format!(
                "cell {} seed{} {}{more}",
                if key.is_empty() { "-" } else { key },
                if seeds.len() == 1 { "" } else { "s" },
                shown.join(", ")
            )
        })
        .collect();
    if by_cell.len() > 4 {
        parts.push(format!("and {} more cells", by_cell.len() - 4));
    }
    parts.join("; ")
}

fn merge_stress_csv(args: &MergeArgs) -> Result<(), Failure> {
    let m = merge_stress(&args.dir, args.partial)?;
    if m.total == 0 {
        return Err(Failure::Other(anyhow::anyhow!(
            "{}: its {} shard files hold no measurement yet",
            args.dir.display(),
            m.files.len()
        )));
    }
    if !m.missing.is_empty() {
        let shown: Vec<String> = m.missing.iter().map(usize::to_string).collect();
        eprintln!(
            "{}: measurements missing: {}",
            args.dir.display(),
            shown.join(", ")
        );
    }
    if !m.written {
        return Err(Failure::Other(anyhow::anyhow!(
            "{}: {} of {} measurements missing: rerun their shards (they resume), or merge what is there with --partial",
            args.dir.display(),
            m.missing.len(),
            m.total
        )));
    }
    outln!(
        "merged {} of {} measurements from {} shard files into {}",
        m.total - m.missing.len(),
        m.total,
        m.files.len(),
        args.dir.display()
    );
    Ok(())
}

pub fn merge(args: MergeArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
    if !args.dir.is_dir() && args.dir.extension().is_some_and(|e| e == "csv") {
        return merge_stress_csv(&args);
    }
    if !args.dir.is_dir() {
        return Err(Failure::Input(format!(
            "{}: not a results folder (nor a stress CSV, FILE.csv)",
            args.dir.display()
        )));
    }
    let report = merge_shards(&args.dir, args.partial, job_id(&env_var), registry)?;
    let exp = &report.experiment;
    for (file, line) in &report.cut_lines {
        eprintln!(
            "warning: {}:{line}: a row cut short (its task was killed mid-write), left out",
            file.display()
        );
    }
    for m in &report.missing {
        let file = m
            .file
            .as_ref()
            .map_or_else(|| "never started".to_string(), |f| f.display().to_string());
        eprintln!(
            "shard {} ({file}): {} of {} runs missing: {}",
            m.shard,
            m.missing.len(),
            m.assigned,
            describe(m, exp)
        );
    }
    let missing: usize = report.missing.iter().map(|m| m.missing.len()).sum();
    if !report.written {
        let shards: Vec<String> = report.missing.iter().map(|m| m.shard.to_string()).collect();
        return Err(Failure::Other(anyhow::anyhow!(
            "{}: {missing} of {} runs missing, in shard{} {}: rerun {} with `{} run CONFIG --out {} --shard I/N` (it resumes), or merge what is there with --partial",
            args.dir.display(),
            report.total,
            if shards.len() == 1 { "" } else { "s" },
            shards.join(", "),
            if shards.len() == 1 { "it" } else { "them" },
            super::bin_name(),
            args.dir.display()
        )));
    }
    outln!(
        "{}: merged {} of {} runs from {} into {}{}",
        exp.name,
        report.present,
        report.total,
        monoculus_experiments::counted(report.shards, "shard"),
        args.dir.join("runs.csv").display(),
        if missing > 0 {
            format!(" ({missing} missing: --partial)")
        } else {
            String::new()
        }
    );
    out!(
        "{}",
        super::table::render(&args.dir.join("summary.csv"), super::table::Format::Text)?
    );
    Ok(())
}
