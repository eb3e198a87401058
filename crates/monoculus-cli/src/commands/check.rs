use super::{ConfigArgs, Failure};

#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    config: ConfigArgs,
}

pub fn check(args: CheckArgs) -> Result<(), Failure> {
    let exp = args.config.load()?;
    let runs = exp.cells.len() * exp.seeds.len();
    println!(
        "{}: {} cells x {} seeds = {} runs",
        exp.name,
        exp.cells.len(),
        exp.seeds.len(),
        runs
    );
    for cell in &exp.cells {
        let c = cell.sim_config(0);
        println!(
            "cell {}: {} | {} {} n={} | stop {} (max_rounds {})",
            cell.index,
            if cell.key.is_empty() { "-" } else { &cell.key },
            cell.algorithm().name(),
            c.scheduler.name(),
            cell.n(),
            c.stop.criterion.name(),
            c.stop.max_rounds
        );
    }
    Ok(())
}
