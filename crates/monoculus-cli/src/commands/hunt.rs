use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use monoculus_experiments::Registry;
use monoculus_experiments::config::SchedulerKind;
use monoculus_experiments::hunt::{FILES, FolderWriter, Hunt, HuntOptions, HuntReport, Progress};
use monoculus_experiments::results::num;

use super::{ConfigArgs, Failure, check_paths, pick_cell, thread_pool};

#[derive(clap::Args, Debug)]
pub struct HuntArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// The folder of the counterexample: positions.csv, schedule.csv, reproduce.toml,
    /// replay.html and summary.json.
    #[arg(long)]
    out: PathBuf,
    /// Which cell of a sweep (default: the config must have one cell).
    #[arg(long)]
    cell: Option<usize>,
    /// Worker threads (default: all cores). With a budget of evaluations the result does
    /// not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

pub fn hunt(args: HuntArgs, registry: &Registry) -> Result<(), Failure> {
    let exp = args.config.load(registry)?;
    let cell = pick_cell(&exp, args.cell, &args.config.config)?;
    let file = args.config.config.display().to_string();
    let hunt = Hunt::new(&exp, cell, &file)?;
    let mut paths = args.config.paths(&exp);
    for f in FILES {
        paths.output("--out", &args.out.join(f));
    }
    check_paths(&paths)?;
    let pool = thread_pool(args.threads)?;
    let html = |replay: &monoculus_experiments::replay::Replay, path: &std::path::Path| {
        monoculus_plot::write_replay_html(replay, path).map_err(|e| e.to_string())
    };
    // A signal stops the hunt, which then writes its best (marked interrupted, not
    // shrunk); the process exits with status 130 once that is done (when `graceful` is
    // dropped). The best so far is also written as it changes, at most 2 s behind.
    let graceful = monoculus_experiments::output::Graceful::enter();
    let writer = FolderWriter::new(&args.out, &hunt, registry, Some(&html));
    let last_line: Mutex<Option<Instant>> = Mutex::new(None);
    let quiet = args.quiet;
    let on_progress = |p: &Progress| {
        writer.on_progress();
        let mut last = last_line.lock().expect("not poisoned");
        if quiet || last.is_some_and(|t| t.elapsed() < Duration::from_secs(1)) {
            return;
        }
        *last = Some(Instant::now());
        eprintln!(
            "hunt: {}: {} evaluations ({:.0}/s), best score {}{}, {:.1}s",
            p.phase,
            p.evaluations,
            p.evaluations as f64 / p.seconds.max(1e-9),
            p.best.map_or("-".into(), num),
            if p.found { " (broken)" } else { "" },
            p.seconds
        );
    };
    let report = pool.install(|| {
        hunt.run(&HuntOptions {
            interrupt: Some(graceful.flag()),
            on_progress: Some(&on_progress),
            on_best: Some(&|r: &HuntReport| writer.on_best(r)),
        })
    });
    writer.finish(&report).map_err(|e| {
        Failure::Other(anyhow::anyhow!(
            "{}: {e}",
            monoculus_experiments::one_line(&args.out.display().to_string())
        ))
    })?;
    if let Some(first) = &report.first_failure {
        eprintln!(
            "warning: {} of the hunt's runs failed (they score nothing); the first: {first}",
            report.failures
        );
    }
    let unit = if cell.spec.scheduler.kind == SchedulerKind::Async {
        "epoch"
    } else {
        "round"
    };
    outln!("{}", describe(&exp.name, &report, unit));
    outln!(
        "wrote {}; replay: {} run {} --out RESULTS",
        args.out.display(),
        super::bin_name(),
        args.out.join("reproduce.toml").display()
    );
    drop(graceful);
    Ok(())
}

/// One line: what was found, after how much search.
/// `unit`: what the run counts (round, or epoch under ASYNC).
pub fn describe(name: &str, report: &HuntReport, unit: &str) -> String {
    let searched = format!(
        "{} evaluations ({} shrinking, {} generations) in {:.1}s",
        report.evaluations, report.shrink_evaluations, report.generations, report.seconds
    );
    let searched = if report.interrupted {
        format!("{searched}, interrupted")
    } else {
        searched
    };
    let property = report.property.name();
    match &report.best {
        Some(b) if report.property == monoculus_experiments::config::Property::Slow => format!(
            "{name}: slow: worst found: {} {unit}s{}{} (n = {}); {searched}",
            b.evaluation.rounds,
            // Under ASYNC the run counts epochs already.
            if unit == "epoch" || b.evaluation.epochs == b.evaluation.rounds {
                String::new()
            } else {
                format!(", {} epochs", b.evaluation.epochs)
            },
            if b.evaluation.converged {
                ""
            } else {
                ", not converged"
            },
            b.candidate.len()
        ),
        Some(b) if b.evaluation.violated => format!(
            "{name}: {property}: broken in {unit} {} by n = {}{}; {searched}",
            b.evaluation.round,
            b.candidate.len(),
            if report.shrunk {
                " (shrunk)"
            } else {
                " (not shrunk)"
            }
        ),
        Some(b) => format!(
            "{name}: {property}: not broken; best score {}; {searched}",
            num(b.evaluation.score)
        ),
        None => format!("{name}: {property}: no run completed; {searched}"),
    }
}
