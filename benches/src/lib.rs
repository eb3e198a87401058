//! Seeded fixtures shared by the benchmarks (built outside the timed loops).

use glam::DVec2;
use monoculus_core::algorithms::AlgorithmKind;
use monoculus_core::init::{InitShape, generate};
use monoculus_engine::SimConfig;

/// `n` robots uniform in a square of density 1 (side sqrt(n)), as `monoculus stress`.
pub fn unit_density(n: usize, seed: u64) -> Vec<DVec2> {
    generate(
        &InitShape::Square {
            side: (n as f64).sqrt(),
        },
        n,
        seed,
    )
}

/// `n` robots on a lattice of spacing about 1 (heavy occlusion).
pub fn lattice(n: usize) -> Vec<DVec2> {
    generate(
        &InitShape::Lattice {
            side: (n as f64).sqrt(),
        },
        n,
        0,
    )
}

/// The paper's parameters (b = 1, c = 2), FSYNC, default stop criterion.
pub fn paper_config(kind: AlgorithmKind, seed: u64) -> SimConfig {
    SimConfig::paper(kind, seed, 1_000_000)
}

/// A swarm as late in a large ConvergeLocality run (measured at round 215 of
/// `configs/bench/locality_1e5.toml`): 95% of the robots uniform in a disc of
/// radius 1.8, all within c = 2 of most others, and 5% stragglers uniform in the
/// annulus of radii 2 and 20. Most robots then see a few percent of the swarm far, so
/// their 32 uniform draws often miss.
pub fn late_locality(n: usize, seed: u64) -> Vec<DVec2> {
    use monoculus_core::rng::Stream;
    let mut rng = Stream::new(seed, 0x1a7e, 0, 0);
    (0..n)
        .map(|k| {
            let (r_lo, r_hi) = if k % 20 == 0 { (2.0, 20.0) } else { (0.0, 1.8) };
            // Uniform in the annulus: the square of the radius is uniform.
            let r = rng.uniform_in(r_lo * r_lo, r_hi * r_hi).sqrt();
            let a = rng.uniform() * std::f64::consts::TAU;
            DVec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}
