use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use monoculus_experiments::shard::{Shard, job_id};
use monoculus_experiments::{RunOptions, run_experiment};

use super::{ConfigArgs, Failure, env_var, thread_pool};

#[derive(clap::Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// Results folder (default: results/<experiment name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: SLURM_CPUS_PER_TASK if set, else all cores). Results do
    /// not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Run only shard I of N (0 <= I < N), into its own file DIR/shards/I-of-N.csv; `auto`
    /// reads I and N from the job array's environment (Slurm, SGE, LSF).
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
    /// Start over: discard the results already in the folder (with --shard: the shard's).
    #[arg(long)]
    force: bool,
}

/// `--shard I/N` or `--shard auto`.
pub fn parse_shard(s: &str) -> Result<Shard, Failure> {
    if s.trim() == "auto" {
        Shard::from_env(&env_var).map_err(Failure::Input)
    } else {
        Shard::parse(s).map_err(Failure::Input)
    }
}

pub fn run(args: RunArgs) -> Result<(), Failure> {
    let exp = args.config.load()?;
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    let out = args
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&exp.name));
    let pool = thread_pool(args.threads)?;
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:30}] {pos}/{len} runs  {elapsed_precise} ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(exp.name.clone());
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let report = pool.install(|| {
        run_experiment(
            &exp,
            &out,
            RunOptions {
                force: args.force,
                shard,
                job: job_id(&env_var),
            },
            &progress,
        )
    })?;
    bar.finish_and_clear();
    if report.dropped_duplicates > 0 {
        eprintln!(
            "warning: {}: dropped {} duplicated rows",
            report.rows_path.display(),
            report.dropped_duplicates
        );
    }
    match shard {
        None => {
            outln!(
                "{}: ran {} runs, {} already done, into {}",
                exp.name,
                report.ran,
                report.skipped,
                out.display()
            );
            print_summary(&out.join("summary.csv"))?;
        }
        Some(s) => outln!(
            "{}: shard {s}: ran {} runs, {} already done, into {}; when every shard is done: monoculus merge {}",
            exp.name,
            report.ran,
            report.skipped,
            report.rows_path.display(),
            out.display()
        ),
    }
    Ok(())
}

fn print_summary(path: &std::path::Path) -> Result<(), Failure> {
    out!(
        "{}",
        super::table::render(path, super::table::Format::Text)?
    );
    Ok(())
}
