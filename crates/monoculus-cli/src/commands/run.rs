use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use monoculus_experiments::{RunOptions, run_experiment};

use super::{ConfigArgs, Failure, thread_pool};

#[derive(clap::Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// Results folder (default: results/<experiment name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Run only the runs k (cell-major, then seed) with k mod N == I, as `I/N`, 0 <= I < N.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Start over: discard the results already in the folder.
    #[arg(long)]
    force: bool,
}

fn parse_shard(s: &str) -> Result<(usize, usize), Failure> {
    let bad = || Failure::Input(format!("--shard {s}: expected I/N with 0 <= I < N"));
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
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
            },
            &progress,
        )
    })?;
    bar.finish_and_clear();
    println!(
        "{}: ran {} runs, {} already done, into {}",
        exp.name,
        report.ran,
        report.skipped,
        out.display()
    );
    print_summary(&out.join("summary.csv"))?;
    Ok(())
}

fn print_summary(path: &std::path::Path) -> Result<(), Failure> {
    print!(
        "{}",
        super::table::render(path, super::table::Format::Text)?
    );
    Ok(())
}
