use std::time::Instant;

use glam::DVec2;
use monoculus_core::algorithms::AlgorithmKind;
use monoculus_core::init::{InitShape, generate};
use monoculus_engine::{SimConfig, Simulation};

use super::{Failure, thread_pool};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    /// Uniform in a square of side sqrt(n) (density 1).
    Square,
    /// A sqrt(n) x sqrt(n) lattice of spacing about 1 (heavy occlusion).
    Lattice,
}

#[derive(clap::Args, Debug)]
pub struct StressArgs {
    /// Number of robots.
    #[arg(long)]
    n: usize,
    /// FSYNC rounds to time.
    #[arg(long)]
    rounds: u64,
    /// Algorithm.
    #[arg(long, default_value = "converge_locality")]
    algorithm: String,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Start configuration.
    #[arg(long, value_enum, default_value = "square")]
    init: Shape,
}

/// Peak resident memory of this process in MB (Linux), if known.
fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Times FSYNC rounds of one algorithm on a swarm of density 1 and reports the engine's
/// throughput; the last line is `activations_per_s=<number>`.
pub fn stress(args: StressArgs) -> Result<(), Failure> {
    if args.n == 0 || args.rounds == 0 {
        return Err(Failure::Input("--n and --rounds must be at least 1".into()));
    }
    let kind = AlgorithmKind::ALL
        .into_iter()
        .find(|k| k.name() == args.algorithm)
        .ok_or_else(|| {
            let names: Vec<&str> = AlgorithmKind::ALL.iter().map(|k| k.name()).collect();
            Failure::Input(format!(
                "--algorithm {}: expected one of {}",
                args.algorithm,
                names.join(", ")
            ))
        })?;
    let pool = thread_pool(args.threads)?;
    let side = (args.n as f64).sqrt();
    let shape = match args.init {
        Shape::Square => InitShape::Square { side },
        Shape::Lattice => InitShape::Lattice { side },
    };
    let setup = Instant::now();
    let start: Vec<DVec2> = generate(&shape, args.n, args.seed);
    let config = SimConfig::paper(kind, args.seed, u64::MAX);
    let mut sim = Simulation::new(config, start).map_err(|e| Failure::Input(e.to_string()))?;
    eprintln!(
        "stress: {} robots, {} FSYNC rounds of {}, {} threads (setup {:.2} s)",
        args.n,
        args.rounds,
        kind.name(),
        pool.current_num_threads(),
        setup.elapsed().as_secs_f64()
    );
    let mut total = 0.0;
    let mut activations = 0u64;
    for round in 1..=args.rounds {
        let t = Instant::now();
        let (moving, activated) = pool.install(|| {
            sim.step();
            sim.round_counts()
        });
        let dt = t.elapsed().as_secs_f64();
        total += dt;
        activations += activated;
        println!(
            "round {round}: {:.3} s, {activated} activations, {moving} moved",
            dt
        );
    }
    println!(
        "rounds={} total_s={:.3} mean_round_s={:.4}",
        args.rounds,
        total,
        total / args.rounds as f64
    );
    if let Some(mb) = peak_rss_mb() {
        println!("peak_memory_mb={mb:.0}");
    }
    println!("activations_per_s={:.0}", activations as f64 / total);
    Ok(())
}
