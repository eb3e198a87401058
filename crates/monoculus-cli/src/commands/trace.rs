use std::io::Write;
use std::path::PathBuf;

use glam::{DVec2, DVec3};
use monoculus_engine::{IndexPoint, RunOutcome, Simulation};
use monoculus_experiments::Cell;
use monoculus_experiments::config::SchedulerKind;
use monoculus_experiments::results::num;

use monoculus_experiments::output::AtomicFile;

use super::{ConfigArgs, Failure, check_paths, pick_cell, thread_pool};

/// The positions file of a trace: `<out stem>.positions.csv`.
pub fn positions_path(out: &std::path::Path) -> PathBuf {
    out.with_extension("positions.csv")
}

#[derive(clap::Args, Debug)]
pub struct TraceArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// The seed.
    #[arg(long)]
    seed: u64,
    /// Output CSV, one row per round (with its wall time in ms).
    #[arg(long)]
    out: PathBuf,
    /// Also write every robot's position per round to `<out stem>.positions.csv`
    /// (columns round, robot, x, y, and light, the colour's name, for an algorithm with
    /// lights).
    #[arg(long)]
    positions: bool,
    /// Also write the robots activated in each round to FILE (columns round, robot):
    /// a schedule that `scheduler.kind = "file"` replays exactly. Round schedulers only.
    #[arg(long, value_name = "FILE")]
    schedule: Option<PathBuf>,
    /// ASYNC: also write every phase duration the run used to FILE (columns robot,
    /// cycle, phase, ticks): the form of `scheduler.durations`, which replays the run
    /// exactly, whatever the config's distributions.
    #[arg(long, value_name = "FILE")]
    durations: Option<PathBuf>,
    /// Which cell of a sweep (default: the config must have one cell).
    #[arg(long)]
    cell: Option<usize>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

pub fn trace(args: TraceArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
    let exp = args.config.load(registry)?;
    let cell = pick_cell(&exp, args.cell, &args.config.config)?;
    if args.schedule.is_some() && cell.spec.scheduler.kind == SchedulerKind::Async {
        return Err(Failure::Input(
            "--schedule: lists the rounds of a round scheduler, and ASYNC has no rounds of activations"
                .into(),
        ));
    }
    if args.durations.is_some() && cell.spec.scheduler.kind != SchedulerKind::Async {
        return Err(Failure::Input(
            "--durations: lists the phases of an ASYNC run, and this run's scheduler has rounds, not phases (--schedule writes those)"
                .into(),
        ));
    }
    let mut paths = args.config.paths(&exp);
    paths.output("--out", &args.out);
    if let Some(d) = &args.durations {
        paths.output("--durations", d);
    }
    if args.positions {
        paths.output("--positions", &positions_path(&args.out));
    }
    if let Some(s) = &args.schedule {
        paths.output("--schedule", s);
    }
    check_paths(&paths)?;
    let pool = thread_pool(args.threads)?;
    let outcome = pool.install(|| match cell.dim() {
        3 => trace_in::<DVec3>(cell, &args),
        _ => trace_in::<DVec2>(cell, &args),
    })?;
    if let Some(f) = &outcome.failure {
        return Err(Failure::Other(anyhow::anyhow!(
            "the run failed: {f}; {} holds its rounds before the failure",
            args.out.display()
        )));
    }
    outln!(
        "rounds={} converged={} stuck={} stopped_by={} goal={} moves={} final_diameter={} hull_growth_rounds={}",
        outcome.rounds,
        outcome.converged,
        outcome.stuck(),
        outcome.stopped_by.name(),
        outcome.goal.name(),
        outcome.moves,
        num(outcome.final_diameter),
        outcome.hull_growth_rounds
    );
    Ok(())
}

/// A text field of a CSV row, quoted if it must be.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Runs the cell, writing one row per round (and the positions with `--positions`).
fn trace_in<P: IndexPoint>(cell: &Cell, args: &TraceArgs) -> Result<RunOutcome, Failure> {
    let axes = &["x", "y", "z"][..P::DIM];
    let measure = if P::DIM == 3 {
        "hull_volume"
    } else {
        "hull_area"
    };
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    // Every file whole or not at all: written beside its name and renamed once the run
    // has ended (an error or a signal leaves the files that were there).
    let mut out = AtomicFile::create(&args.out)?;
    let extents: Vec<String> = axes.iter().map(|a| format!("extent_{a}")).collect();
    writeln!(
        out,
        "round,robots,activated,moving,{measure},diameter,{},wall_ms",
        extents.join(",")
    )?;
    // An algorithm with lights: each robot's colour, by name, in a column `light`.
    let palette = cell.algorithm().lights();
    let mut pos_out = if args.positions {
        let mut f = AtomicFile::create(&positions_path(&args.out))?;
        let light = if palette.is_empty() { "" } else { ",light" };
        writeln!(f, "round,robot,{}{light}", axes.join(","))?;
        Some(f)
    } else {
        None
    };
    let mut schedule_out = match &args.schedule {
        Some(path) => {
            let mut f = AtomicFile::create(path)?;
            writeln!(f, "round,robot")?;
            Some(f)
        }
        None => None,
    };
    let robots = cell.n();
    let mut io_error: Option<std::io::Error> = None;
    let mut sim = Simulation::<P>::new(
        cell.sim_config(args.seed),
        cell.initial_positions(args.seed),
    )
    .map_err(|e| Failure::Other(e.into()))?;
    // Wall time of each round (of the setup for round 0), without the writing.
    let mut last = std::time::Instant::now();
    let outcome = sim.run_with(|r| {
        let wall_ms = last.elapsed().as_secs_f64() * 1e3;
        let mut write = || -> std::io::Result<()> {
            let ext: Vec<String> = r.extents.iter().map(|&e| num(e)).collect();
            writeln!(
                out,
                "{},{robots},{},{},{},{},{},{:.3}",
                r.round,
                r.activated,
                r.moving,
                num(r.hull),
                num(r.diameter),
                ext.join(","),
                wall_ms
            )?;
            if let Some(f) = pos_out.as_mut() {
                let lights = r.lights();
                for (i, p) in r.positions.iter().enumerate() {
                    let c: Vec<String> = (0..P::DIM).map(|k| num(p.axis(k))).collect();
                    match lights.get(i) {
                        Some(&l) => {
                            let name = palette.get(usize::from(l)).map_or("", String::as_str);
                            writeln!(f, "{},{},{},{}", r.round, i, c.join(","), csv_field(name))?
                        }
                        None => writeln!(f, "{},{},{}", r.round, i, c.join(","))?,
                    }
                }
            }
            if let Some(f) = schedule_out.as_mut() {
                for robot in r.activated_robots() {
                    writeln!(f, "{},{robot}", r.round)?;
                }
            }
            Ok(())
        };
        if io_error.is_none()
            && let Err(e) = write()
        {
            io_error = Some(e);
        }
        last = std::time::Instant::now();
    });
    if let Some(e) = io_error {
        return Err(e.into());
    }
    let durations_out = match &args.durations {
        Some(path) => {
            let used = monoculus_engine::asynchrony::Durations::new(sim.drawn_durations())
                .map_err(|e| Failure::Other(anyhow::anyhow!("the run's durations: {e}")))?;
            let mut f = AtomicFile::create(path)?;
            f.write_all(monoculus_experiments::durations::durations_csv(&used).as_bytes())?;
            Some(f)
        }
        None => None,
    };
    for f in [Some(out), pos_out, schedule_out, durations_out]
        .into_iter()
        .flatten()
    {
        f.commit()?;
    }
    Ok(outcome)
}
