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
