//! Visibility queries, index building, the hull, one round per algorithm, a late round
//! of a large ConvergeLocality run, one small paper run, a stretch of ASYNC ticks.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use monoculus_benches::{late_locality, lattice, paper_config, unit_density};
use monoculus_core::algorithms::{AlgorithmKind, TargetPolicy};
use monoculus_core::init::{InitShape, generate};
use monoculus_core::vision::{Sight, VisionParams, visible_points_sweep_2d};
use monoculus_engine::{
    AsyncSpec, AsyncStart, IndexedSight, SchedulerSpec, SegmentGrid, Simulation, TickDist,
};
use std::hint::black_box;

fn queries(c: &mut Criterion) {
    let mut g = c.benchmark_group("visibility");
    for n in [1_000usize, 10_000, 100_000] {
        for (shape, pts) in [("uniform", unit_density(n, 1)), ("lattice", lattice(n))] {
            let sight = IndexedSight::new(pts.clone(), VisionParams::default());
            let pairs: Vec<(usize, usize)> = (0..256)
                .map(|k| ((k * 7919) % n, (k * 104_729 + 13) % n))
                .collect();
            g.bench_with_input(
                BenchmarkId::new(format!("sees/{shape}"), n),
                &pairs,
                |b, pairs| b.iter(|| pairs.iter().filter(|&&(i, j)| sight.sees(i, j)).count()),
            );
            if n <= 10_000 {
                g.bench_with_input(
                    BenchmarkId::new(format!("sweep/{shape}"), n),
                    &pts,
                    |b, pts| {
                        b.iter(|| {
                            visible_points_sweep_2d(pts, n / 2, &VisionParams::default()).len()
                        })
                    },
                );
            }
        }
    }
    g.finish();
}

fn index_build(c: &mut Criterion) {
    let mut g = c.benchmark_group("index");
    for n in [1_000usize, 10_000, 100_000] {
        let pts = unit_density(n, 2);
        g.bench_with_input(BenchmarkId::new("rtree_bulk_load", n), &pts, |b, pts| {
            b.iter(|| {
                // Force the lazily built R-tree with one nearest-neighbour query.
                let s = IndexedSight::new(black_box(pts.clone()), VisionParams::default());
                s.nearest_first(0).next()
            })
        });
        g.bench_with_input(BenchmarkId::new("segment_grid", n), &pts, |b, pts| {
            b.iter(|| SegmentGrid::new(black_box(pts)))
        });
        // The update of a late ConvergeQuadrant round: n / 100 robots moved inside the
        // box. A sight taken after the previous one keeps its grid (the moved robots
        // stale) against one built afresh; each answers one line of sight, which
        // needs the grid.
        let mut moved = pts.clone();
        for k in (0..n).step_by(100) {
            moved[k] = (moved[k] + moved[(k + 1) % n]) * 0.5;
        }
        let vision = VisionParams::default();
        let previous = || {
            let s = IndexedSight::new(pts.clone(), vision);
            s.sees(0, 1);
            s
        };
        g.bench_function(BenchmarkId::new("update_after_few_moved", n), |b| {
            b.iter_batched(
                previous,
                |prev| IndexedSight::after(prev, moved.clone(), vision).sees(0, n / 2),
                criterion::BatchSize::LargeInput,
            )
        });
        g.bench_function(BenchmarkId::new("rebuild_after_few_moved", n), |b| {
            b.iter_batched(
                previous,
                |prev| {
                    drop(prev);
                    IndexedSight::new(moved.clone(), vision).sees(0, n / 2)
                },
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

/// The per-round hull: the monotone chain over every point against the chain after the
/// throw-away step that drops points certainly interior (what a round uses).
fn hull(c: &mut Criterion) {
    use monoculus_core::geometry::{convex_hull_2d, convex_hull_2d_all};
    let mut g = c.benchmark_group("hull");
    for n in [10_000usize, 100_000] {
        let pts = unit_density(n, 5);
        g.bench_with_input(BenchmarkId::new("chain_all", n), &pts, |b, pts| {
            b.iter(|| convex_hull_2d_all(black_box(pts)).len())
        });
        g.bench_with_input(BenchmarkId::new("throw_away_first", n), &pts, |b, pts| {
            b.iter(|| convex_hull_2d(black_box(pts)).len())
        });
    }
    g.finish();
}

fn one_round(c: &mut Criterion) {
    let mut g = c.benchmark_group("round");
    g.sample_size(10);
    for kind in AlgorithmKind::ALL {
        // The baselines look at every visible robot (O(n^2) per round): small n only.
        let sizes: &[usize] = match kind {
            AlgorithmKind::CenterOfGravity
            | AlgorithmKind::Median
            | AlgorithmKind::AngleBisector => &[1_000],
            _ => &[1_000, 10_000, 100_000],
        };
        for &n in sizes {
            let pts = unit_density(n, 3);
            g.bench_with_input(BenchmarkId::new(kind.name(), n), &pts, |b, pts| {
                b.iter_batched(
                    || Simulation::new(paper_config(kind, 3), pts.clone()).unwrap(),
                    |mut sim| {
                        sim.step();
                        sim
                    },
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    g.finish();
}

/// One FSYNC ConvergeLocality round late in a large run (a dense core within c, a few
/// stragglers): where the 32 uniform draws miss, `random_listing` checks the view to
/// every far robot, the default `random` draws more (uniformly, then among the far
/// robots).
fn late_round(c: &mut Criterion) {
    let mut g = c.benchmark_group("late_round");
    g.sample_size(10);
    for (target, name, sizes) in [
        (
            TargetPolicy::RandomListing,
            "random_listing",
            &[10_000usize][..],
        ),
        (TargetPolicy::Random, "random", &[10_000, 100_000][..]),
    ] {
        for &n in sizes {
            let pts = late_locality(n, 6);
            let mut config = paper_config(AlgorithmKind::ConvergeLocality, 6);
            config.model.target = target;
            g.bench_with_input(BenchmarkId::new(name, n), &pts, |b, pts| {
                b.iter_batched(
                    || Simulation::new(config.clone(), pts.clone()).unwrap(),
                    |mut sim| {
                        sim.step();
                        sim
                    },
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    g.finish();
}

fn paper_run(c: &mut Criterion) {
    let mut g = c.benchmark_group("paper_run");
    g.sample_size(10);
    let pts: Vec<glam::DVec2> = generate(&InitShape::Square { side: 20.0 }, 200, 4);
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
    ] {
        g.bench_with_input(BenchmarkId::new(kind.name(), 200), &pts, |b, pts| {
            b.iter(|| {
                Simulation::new(paper_config(kind, 4), pts.clone())
                    .unwrap()
                    .run()
                    .rounds
            })
        });
    }
    g.finish();
}

/// One stretch of 20 ASYNC event ticks of ConvergeLocality (`target = "random"`) on a square
/// of density 1, after one epoch: coarse durations (idle U(1,10), compute U(1,5), move
/// Exp(4)) and the same x 100, whose ticks have few Looks each.
fn async_stretch(c: &mut Criterion) {
    let mut g = c.benchmark_group("async_stretch");
    g.sample_size(10);
    let coarse = AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 10 },
        compute: TickDist::Uniform { min: 1, max: 5 },
        motion: TickDist::Exponential { mean: 4.0 },
        start: AsyncStart::Random,
        durations: None,
    };
    let fine = AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 1000 },
        compute: TickDist::Uniform { min: 1, max: 500 },
        motion: TickDist::Exponential { mean: 400.0 },
        start: AsyncStart::Random,
        durations: None,
    };
    for n in [10_000usize, 100_000] {
        for (label, timing) in [("coarse", &coarse), ("x100", &fine)] {
            let pts = unit_density(n, 6);
            g.bench_function(BenchmarkId::new(label, n), |b| {
                b.iter_batched_ref(
                    || {
                        let mut cfg = paper_config(AlgorithmKind::ConvergeLocality, 6);
                        cfg.scheduler = SchedulerSpec::Async(timing.clone());
                        let mut sim = Simulation::new(cfg.clone(), pts.clone()).unwrap();
                        while sim.async_progress().is_some_and(|(_, e)| e == 0) {
                            sim.step();
                        }
                        sim
                    },
                    |sim| {
                        for _ in 0..20 {
                            sim.step();
                        }
                        sim.activations()
                    },
                    criterion::BatchSize::PerIteration,
                )
            });
        }
    }
    g.finish();
}

/// The plane's two indexes on the same questions: the band grid (the default) against
/// an rstar R-tree (`vision.backend = "rtree"`): 256 lines of sight, and one ConvergeLocality
/// round (index build included).
fn plane_backends(c: &mut Criterion) {
    use monoculus_engine::{SightBackend, SpaceIndex};
    let mut g = c.benchmark_group("plane_backends");
    g.sample_size(10);
    for n in [10_000usize, 100_000] {
        for (shape, pts) in [("uniform", unit_density(n, 1)), ("lattice", lattice(n))] {
            let pairs: Vec<(usize, usize)> = (0..256)
                .map(|k| ((k * 7919) % n, (k * 104_729 + 13) % n))
                .collect();
            let grid = IndexedSight::new(pts.clone(), VisionParams::default());
            let tree: IndexedSight<_, SpaceIndex<_>> =
                IndexedSight::with_index(pts.clone(), VisionParams::default());
            grid.sees(0, 1);
            tree.sees(0, 1);
            g.bench_with_input(
                BenchmarkId::new(format!("sees/grid/{shape}"), n),
                &pairs,
                |b, pairs| b.iter(|| pairs.iter().filter(|&&(i, j)| grid.sees(i, j)).count()),
            );
            g.bench_with_input(
                BenchmarkId::new(format!("sees/rtree/{shape}"), n),
                &pairs,
                |b, pairs| b.iter(|| pairs.iter().filter(|&&(i, j)| tree.sees(i, j)).count()),
            );
        }
        for (label, backend) in [
            ("grid", SightBackend::Index),
            ("rtree", SightBackend::Rtree),
        ] {
            let mut cfg = paper_config(AlgorithmKind::ConvergeLocality, 1);
            cfg.backend = backend;
            let pts = unit_density(n, 1);
            g.bench_function(BenchmarkId::new(format!("round/{label}"), n), |b| {
                b.iter_batched(
                    || Simulation::new(cfg.clone(), pts.clone()).unwrap(),
                    |mut sim| {
                        sim.step();
                        black_box(sim.positions().len())
                    },
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    queries,
    plane_backends,
    index_build,
    hull,
    one_round,
    late_round,
    paper_run,
    async_stretch
);
criterion_main!(benches);
