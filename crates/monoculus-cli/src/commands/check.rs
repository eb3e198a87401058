use monoculus_experiments::counted;
use monoculus_experiments::limits::{human, machine_bytes, results_bytes, run_bytes};

use super::{ConfigArgs, Failure};

#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    config: ConfigArgs,
}

pub fn check(args: CheckArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
    let exp = args.config.load(registry)?;
    let runs = exp.cells.len() * exp.seeds.len();
    outln!(
        "{}: {} x {} = {}",
        exp.name,
        counted(exp.cells.len(), "cell"),
        counted(exp.seeds.len(), "seed"),
        counted(runs, "run")
    );
    for cell in &exp.cells {
        let c = cell.sim_config(0);
        outln!(
            "cell {}: {} | {} {} n={} | stop {}, goal {} (max_rounds {})",
            cell.index,
            if cell.key.is_empty() { "-" } else { &cell.key },
            cell.algorithm().name(),
            c.scheduler.name(),
            cell.n(),
            c.stop.criterion.name(),
            c.stop.goal.name(),
            c.stop.max_rounds
        );
    }
    let largest = exp.cells.iter().map(|c| c.n()).max().unwrap_or(0) as u64;
    let per_run = run_bytes(largest);
    let at_once = rayon::current_num_threads().min(runs).max(1) as u64;
    let machine =
        machine_bytes().map_or_else(String::new, |m| format!("; this machine has {}", human(m)));
    outln!(
        "memory: about {} per run (n = {largest}), {} with {} at once, {} for the results when the sweep ends{machine}",
        human(per_run),
        human(per_run.saturating_mul(at_once)),
        counted(at_once as usize, "run"),
        human(results_bytes(runs as u64))
    );
    Ok(())
}
