use std::path::PathBuf;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use monoculus_experiments::shard::{Shard, job_id};
use monoculus_experiments::{Progress, RunOptions, RunProgress, run_experiment};

use monoculus_experiments::results::folder_outputs;

use super::{ConfigArgs, Failure, check_paths, env_var, thread_pool};

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
    /// Also print a line to stderr for each running run at most every SECONDS (the round
    /// or epoch it has reached, its diameter, its time), and one when it ends: for long
    /// runs and batch jobs' logs, where no progress bar is drawn.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    progress: Option<Duration>,
}

pub(super) fn parse_seconds(s: &str) -> Result<Duration, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x <= 1e9 => Ok(Duration::from_secs_f64(x)),
        _ => Err(format!("`{s}` is not a positive number of seconds")),
    }
}

/// The bar (on a terminal) and the `--progress` lines.
struct Reporter {
    bar: ProgressBar,
    name: String,
    /// `--progress`.
    lines: Option<Duration>,
}

/// `1h02m03s`, `2m03s`, `3.4s`.
fn clock(d: Duration) -> String {
    let s = d.as_secs();
    match s {
        0..60 => format!("{:.1}s", d.as_secs_f64()),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m{:02}s", s / 3600, s / 60 % 60, s % 60),
    }
}

impl Reporter {
    fn say(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    fn where_at(&self, at: &RunProgress<'_>) -> String {
        let cell = if at.cell.is_empty() {
            String::new()
        } else {
            format!(" {}", at.cell)
        };
        format!(
            "{}{cell} seed {}: {} {}, diameter {:.6}, {}",
            self.name,
            at.seed,
            at.unit,
            at.round,
            at.diameter,
            clock(at.elapsed)
        )
    }
}

impl Progress for Reporter {
    fn runs(&self, done: usize, pending: usize) {
        self.bar.set_length(pending as u64);
        self.bar.set_position(done as u64);
    }

    fn interval(&self) -> Option<Duration> {
        // On a terminal the bar shows the latest run's state every second.
        match (self.lines, self.bar.is_hidden()) {
            (Some(every), _) => Some(every),
            (None, false) => Some(Duration::from_secs(1)),
            (None, true) => None,
        }
    }

    fn round(&self, at: &RunProgress<'_>) {
        if !self.bar.is_hidden() {
            self.bar.set_message(format!(
                "{}: seed {} {} {}",
                self.name, at.seed, at.unit, at.round
            ));
        }
        if self.lines.is_some() {
            self.say(self.where_at(at));
        }
    }

    fn finished(&self, at: &RunProgress<'_>, outcome: &monoculus_engine::RunOutcome) {
        if self.lines.is_some() {
            let how = if outcome.converged {
                "converged"
            } else if outcome.stuck() {
                "stuck"
            } else {
                "stopped"
            };
            self.say(format!("{} ({how})", self.where_at(at)));
        }
    }
}

/// `--shard I/N` or `--shard auto`.
pub fn parse_shard(s: &str) -> Result<Shard, Failure> {
    if s.trim() == "auto" {
        Shard::from_env(&env_var).map_err(Failure::Input)
    } else {
        Shard::parse(s).map_err(Failure::Input)
    }
}

pub fn run(args: RunArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
    let exp = args.config.load(registry)?;
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    let out = args
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&exp.name));
    let mut paths = args.config.paths(&exp);
    for (label, file) in folder_outputs(&out, shard) {
        paths.output(label, &file);
    }
    check_paths(&paths)?;
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
    let progress = Reporter {
        bar,
        name: exp.name.clone(),
        lines: args.progress,
    };
    let report = pool.install(|| {
        run_experiment(
            &exp,
            &out,
            RunOptions {
                force: args.force,
                shard,
                job: job_id(&env_var),
                interrupt: None,
            },
            &progress,
        )
    })?;
    progress.bar.finish_and_clear();
    if report.dropped_duplicates > 0 {
        eprintln!(
            "warning: {}: dropped {} duplicated rows",
            report.rows_path.display(),
            report.dropped_duplicates
        );
    }
    let failed = &report.failed;
    match shard {
        None => {
            outln!(
                "{}: ran {}, {} already done, into {}",
                exp.name,
                monoculus_experiments::counted(report.ran, "run"),
                report.skipped,
                out.display()
            );
            print_summary(&out.join("summary.csv"))?;
        }
        Some(s) => outln!(
            "{}: shard {s}: ran {}, {} already done, into {}; when every shard is done: {} merge {}",
            exp.name,
            monoculus_experiments::counted(report.ran, "run"),
            report.skipped,
            report.rows_path.display(),
            super::bin_name(),
            out.display()
        ),
    }
    if let Some((cell, seed, message)) = failed.first() {
        let cell = if cell.is_empty() { "-" } else { cell };
        return Err(Failure::Other(anyhow::anyhow!(
            "{} of {} runs failed (recorded in {}, not in the results; the others are): cell {cell}, seed {seed}: {}",
            failed.len(),
            report.total,
            report.failures_path.display(),
            monoculus_experiments::one_line(message)
        )));
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
