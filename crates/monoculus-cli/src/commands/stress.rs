use std::path::PathBuf;
use std::time::Instant;

use glam::DVec2;
use monoculus_core::init::{InitShape, generate};
use monoculus_engine::AlgorithmBox;
use monoculus_engine::{
    AsyncSpec, AsyncStart, SchedulerSpec, SightBackend, SimConfig, Simulation, TickDist,
};
use monoculus_experiments::Registry;
use monoculus_experiments::results::{
    Attempt, GIT_COMMIT, StressLog, StressRow, VERSION, host_name, quantile, stress_shard_path,
};
use monoculus_experiments::shard::{Shard, balance, job_id};

use super::run::parse_shard;
use super::{Failure, MAX_THREADS, env_var, thread_pool, threads_wanted};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    /// Uniform in a square of side sqrt(n) (density 1).
    Square,
    /// A sqrt(n) x sqrt(n) lattice of spacing about 1 (heavy occlusion).
    Lattice,
}

impl Shape {
    fn name(self) -> &'static str {
        match self {
            Shape::Square => "square",
            Shape::Lattice => "lattice",
        }
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Backend {
    /// The band grid in the plane, the R-tree in space.
    Index,
    /// An R-tree in the plane too.
    Rtree,
    /// Brute force from the definition.
    Exact,
}

impl Backend {
    fn name(self) -> &'static str {
        match self {
            Backend::Index => "index",
            Backend::Rtree => "rtree",
            Backend::Exact => "exact",
        }
    }

    fn engine(self) -> SightBackend {
        match self {
            Backend::Index => SightBackend::Index,
            Backend::Rtree => SightBackend::Rtree,
            Backend::Exact => SightBackend::Exact,
        }
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Sched {
    /// Fully synchronous rounds.
    Fsync,
    /// Continuous time: per-robot cycles of random durations; a "round" is an epoch.
    Async,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    /// Every robot Looks at tick 0.
    Together,
    /// Every robot starts Idle for one idle draw.
    Random,
}

#[derive(clap::Args, Debug)]
pub struct StressArgs {
    /// Number of robots; a list (`--n 10000,100000`) measures each.
    #[arg(long, value_delimiter = ',', required = true)]
    n: Vec<usize>,
    /// FSYNC rounds to time.
    #[arg(long)]
    rounds: u64,
    /// Algorithm.
    #[arg(long, default_value = "converge_locality")]
    algorithm: String,
    /// Worker threads (default: SLURM_CPUS_PER_TASK if set, else all cores); a list
    /// (`--threads 1,2,4`) measures each.
    #[arg(long, value_delimiter = ',')]
    threads: Vec<usize>,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Start configuration.
    #[arg(long, value_enum, default_value = "square")]
    init: Shape,
    /// Visibility backend: index (the band grid in the plane, an R-tree in space),
    /// rtree (an R-tree in the plane too) or exact (brute force).
    #[arg(long, value_enum, default_value = "index")]
    backend: Backend,
    /// Scheduler: fsync rounds, or async epochs (the shortest spans in which every robot
    /// completed a cycle).
    #[arg(long, value_enum, default_value = "fsync")]
    scheduler: Sched,
    /// ASYNC Idle durations in ticks: fixed:T, uniform:MIN:MAX or exp:MEAN (default
    /// uniform:1:10).
    #[arg(long)]
    idle: Option<String>,
    /// ASYNC Compute durations (default uniform:1:5).
    #[arg(long)]
    compute: Option<String>,
    /// ASYNC Move durations (default exp:4).
    #[arg(long = "move")]
    motion: Option<String>,
    /// ASYNC start (default random).
    #[arg(long, value_enum)]
    start: Option<Start>,
    /// Append one row per measurement to this CSV (resumable: measurements already in it
    /// are skipped).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Measure only shard I of N of the measurements (`auto`: from the job array), into
    /// the CSV's shard file (stress.csv -> stress.I-of-N.csv); needs --csv.
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
}

/// Peak resident memory of this process in MB (Linux), if known.
fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Resets the peak resident memory to the current (Linux), so that each measurement of a
/// sweep reports its own peak.
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// One measurement: n robots, t threads.
struct Plan {
    measurement: usize,
    n: usize,
    threads: Option<usize>,
}

/// Times FSYNC rounds of one algorithm on a swarm of density 1 and reports the engine's
/// throughput; for each measurement the last line is `activations_per_s=<number>`.
pub fn stress(args: StressArgs, registry: &Registry) -> Result<(), Failure> {
    if args.n.contains(&0) || args.rounds == 0 {
        return Err(Failure::Input("--n and --rounds must be at least 1".into()));
    }
    for &n in &args.n {
        monoculus_experiments::limits::check_robots(n as u64)
            .map_err(|m| Failure::Input(format!("--n {n}: {m}")))?;
    }
    // The algorithm with its default parameters.
    let kind = registry
        .get(&args.algorithm)
        .ok_or_else(|| {
            Failure::Input(format!(
                "--algorithm {}: expected one of {}",
                monoculus_experiments::shown(&args.algorithm),
                registry.names().join(", ")
            ))
        })?
        .make(&toml::Table::new())
        .map_err(|e| {
            Failure::Input(format!(
                "--algorithm {}: its parameters have no defaults: {} {}",
                args.algorithm, e.key, e.message
            ))
        })?
        .0;
    let threads: Vec<Option<usize>> = if args.threads.is_empty() {
        vec![threads_wanted(None)?]
    } else {
        args.threads
            .iter()
            .map(|&t| threads_wanted(Some(t)))
            .collect::<Result<_, _>>()?
    };
    let timing = async_timing(&args)?;
    let shard: Option<Shard> = args.shard.as_deref().map(parse_shard).transpose()?;
    if shard.is_some() && args.csv.is_none() {
        return Err(Failure::Input(
            "--shard: needs --csv FILE (each shard writes its own file beside it)".into(),
        ));
    }
    let mut plans = Vec::new();
    for &n in &args.n {
        for &t in &threads {
            plans.push(Plan {
                measurement: plans.len(),
                n,
                threads: t,
            });
        }
    }
    let measurements = plans.len();
    if let Some(s) = shard {
        let costs: Vec<f64> = plans
            .iter()
            .map(|p| (p.n as f64).powf(1.5) / p.threads.unwrap_or(1).min(MAX_THREADS) as f64)
            .collect();
        let of = balance(&costs, s.count);
        plans = plans
            .into_iter()
            .zip(of)
            .filter(|&(_, k)| k == s.index)
            .map(|(p, _)| p)
            .collect();
    }
    let job = job_id(&env_var);
    let log = match &args.csv {
        None => None,
        Some(path) => {
            let path = match shard {
                Some(s) => stress_shard_path(path, s),
                None => path.clone(),
            };
            let who = Attempt::this_process(shard.map(|s| s.to_string()), job.clone()).describe();
            Some(StressLog::open(&path, &who)?)
        }
    };
    for plan in plans {
        let pool = thread_pool(plan.threads)?;
        let mut row = StressRow {
            measurement: plan.measurement,
            measurements,
            n: plan.n,
            threads: pool.current_num_threads(),
            algorithm: kind.name().into(),
            scheduler: if timing.is_some() { "async" } else { "fsync" }.into(),
            backend: args.backend.name().into(),
            timing: timing.as_ref().map_or_else(String::new, timing_label),
            init: args.init.name().into(),
            seed: args.seed,
            rounds: args.rounds,
            setup_s: 0.0,
            total_s: 0.0,
            round_s_min: 0.0,
            round_s_median: 0.0,
            round_s_max: 0.0,
            activations: 0,
            activations_per_s: 0.0,
            peak_memory_mb: None,
            host: host_name(),
            job: job.clone(),
            monoculus_version: VERSION.into(),
            git_commit: GIT_COMMIT.into(),
        };
        if log.as_ref().is_some_and(|l| l.done.contains(&row.key())) {
            eprintln!(
                "stress: n={} threads={}: already measured, skipped",
                row.n, row.threads
            );
            continue;
        }
        reset_peak_rss();
        measure(
            &kind,
            args.init,
            args.backend,
            timing.as_ref(),
            &pool,
            &mut row,
        )?;
        if let Some(l) = &log {
            l.append(&row)?;
        }
    }
    Ok(())
}

/// The ASYNC timing of `--scheduler async` (its options refused otherwise).
fn async_timing(args: &StressArgs) -> Result<Option<AsyncSpec>, Failure> {
    let given = args.idle.is_some()
        || args.compute.is_some()
        || args.motion.is_some()
        || args.start.is_some();
    if args.scheduler == Sched::Fsync {
        if given {
            return Err(Failure::Input(
                "--idle, --compute, --move and --start need --scheduler async".into(),
            ));
        }
        return Ok(None);
    }
    let dist = |flag: &str, v: &Option<String>, default: &str| {
        TickDist::parse(v.as_deref().unwrap_or(default))
            .map_err(|m| Failure::Input(format!("--{flag} {m}")))
    };
    Ok(Some(AsyncSpec {
        idle: dist("idle", &args.idle, "uniform:1:10")?,
        compute: dist("compute", &args.compute, "uniform:1:5")?,
        motion: dist("move", &args.motion, "exp:4")?,
        start: match args.start.unwrap_or(Start::Random) {
            Start::Together => AsyncStart::Together,
            Start::Random => AsyncStart::Random,
        },
        durations: None,
    }))
}

fn timing_label(t: &AsyncSpec) -> String {
    format!(
        "idle={} compute={} move={} start={}",
        t.idle.label(),
        t.compute.label(),
        t.motion.label(),
        match t.start {
            AsyncStart::Together => "together",
            AsyncStart::Random => "random",
        }
    )
}

/// Builds the swarm and times the rounds (ASYNC: epochs), filling `row`'s figures.
fn measure(
    kind: &AlgorithmBox,
    init: Shape,
    backend: Backend,
    timing: Option<&AsyncSpec>,
    pool: &rayon::ThreadPool,
    row: &mut StressRow,
) -> Result<(), Failure> {
    let side = (row.n as f64).sqrt();
    let shape = match init {
        Shape::Square => InitShape::Square { side },
        Shape::Lattice => InitShape::Lattice { side },
    };
    let setup = Instant::now();
    let start: Vec<DVec2> = generate(&shape, row.n, row.seed);
    // The cap is the rounds measured: stress steps them itself, and ASYNC checks
    // that its clock cannot overflow within the cap.
    let mut config = SimConfig::paper(kind.clone(), row.seed, row.rounds.max(1));
    config.backend = backend.engine();
    if let Some(t) = timing {
        config.scheduler = SchedulerSpec::Async(t.clone());
    }
    let mut sim = Simulation::new(config, start).map_err(|e| Failure::Input(e.to_string()))?;
    row.setup_s = setup.elapsed().as_secs_f64();
    eprintln!(
        "stress: {} robots, {} {} of {}, {} threads (setup {:.2} s)",
        row.n,
        row.rounds,
        if timing.is_some() {
            "ASYNC epochs"
        } else {
            "FSYNC rounds"
        },
        kind.name(),
        row.threads,
        row.setup_s
    );
    let mut times = Vec::with_capacity(row.rounds.min(1 << 16) as usize);
    for round in 1..=row.rounds {
        let t = Instant::now();
        if timing.is_some() {
            let (tick0, epochs0) = sim.async_progress().expect("an ASYNC run");
            let before = sim.activations();
            pool.install(|| {
                while sim.async_progress().is_some_and(|(_, e)| e == epochs0) {
                    sim.step();
                }
            });
            let dt = t.elapsed().as_secs_f64();
            let (tick, _) = sim.async_progress().expect("an ASYNC run");
            let activated = sim.activations() - before;
            times.push(dt);
            row.activations += activated;
            outln!(
                "epoch {round}: {dt:.3} s, {activated} activations, {} ticks",
                tick - tick0
            );
            continue;
        }
        let (moving, activated) = pool.install(|| {
            sim.step();
            sim.round_counts()
        });
        let dt = t.elapsed().as_secs_f64();
        times.push(dt);
        row.activations += activated;
        outln!("round {round}: {dt:.3} s, {activated} activations, {moving} moved");
    }
    row.total_s = times.iter().sum();
    row.round_s_min = times.iter().copied().fold(f64::INFINITY, f64::min);
    row.round_s_max = times.iter().copied().fold(0.0, f64::max);
    row.round_s_median = quantile(&times, 0.5);
    row.activations_per_s = row.activations as f64 / row.total_s;
    row.peak_memory_mb = peak_rss_mb().map(|m| m.round());
    outln!(
        "rounds={} total_s={:.3} mean_round_s={:.4}",
        row.rounds,
        row.total_s,
        row.total_s / row.rounds as f64
    );
    if let Some(mb) = row.peak_memory_mb {
        outln!("peak_memory_mb={mb:.0}");
    }
    outln!("activations_per_s={:.0}", row.activations_per_s);
    Ok(())
}
