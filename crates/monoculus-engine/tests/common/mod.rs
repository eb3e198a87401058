//! Fixtures shared by the engine's tests.
#![allow(dead_code, missing_docs, reason = "each test binary uses a subset")]

use glam::DVec2;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

pub fn config(kind: AlgorithmKind, scheduler: SchedulerSpec, seed: u64) -> SimConfig {
    SimConfig {
        scheduler,
        ..SimConfig::paper(kind, seed, 20_000)
    }
}

pub fn square(n: usize, side: f64, seed: u64) -> Vec<DVec2> {
    generate(&InitShape::Square { side }, n, seed)
}

/// Random, lattice, collinear (horizontal and diagonal) and co-located configurations.
pub fn zoo(seed: u64) -> Vec<(&'static str, Vec<DVec2>)> {
    let mut s = Stream::new(seed, 99, 0, 0);
    let diagonal: Vec<DVec2> = (0..40).map(|_| DVec2::splat(s.uniform() * 10.0)).collect();
    let mut stacked = square(30, 5.0, seed);
    stacked.extend_from_slice(&stacked.clone()[..10]);
    stacked.push(stacked[0] + DVec2::new(1e-10, 0.0));
    // (More robots than a sight answers without its grid, as every configuration here.)
    let mut rays = vec![DVec2::ZERO];
    for k in 1..10 {
        for dir in [
            DVec2::new(1.0, 0.0),
            DVec2::new(0.6, 0.8),
            DVec2::new(-1.0, 3.0).normalize(),
        ] {
            rays.push(dir * k as f64 * 0.7);
        }
    }
    // A converging swarm's late shape: a dense core, every robot of it in one bin,
    // some co-located, and a few stragglers far out.
    let mut core: Vec<DVec2> = square(150, 0.1, seed)
        .into_iter()
        .map(|p| p + DVec2::splat(5.0))
        .collect();
    core.extend_from_slice(&core.clone()[..4]);
    for (x, y) in [
        (-15.0, -15.0),
        (25.0, -15.0),
        (25.0, 25.0),
        (-15.0, 25.0),
        (5.0, 25.0),
    ] {
        core.push(DVec2::new(x, y));
    }
    vec![
        ("random", square(120, 10.0, seed)),
        ("core", core),
        (
            "lattice",
            generate(&InitShape::Lattice { side: 6.0 }, 49, seed),
        ),
        ("line", generate(&InitShape::Line { side: 10.0 }, 40, seed)),
        ("diagonal", diagonal),
        ("stacked", stacked),
        ("rays", rays),
        (
            "clusters",
            generate(
                &InitShape::Clusters {
                    side: 10.0,
                    clusters: 3,
                    spread: 0.3,
                },
                90,
                seed,
            ),
        ),
    ]
}
