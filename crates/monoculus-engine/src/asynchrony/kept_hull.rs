//! [`KeptHull`]: the hull of a set of points that gains and loses points one at a time,
//! kept across ticks.

pub(crate) use super::boxes::InnerBoxes;
use super::boxes::{in_boxes, inner_boxes, lost_ground, may_be_in, outer_box};
use super::roster::Roster;
use super::shape::{in_disc, inner_disc};
use crate::IndexPoint;

/// The hull of a set of points, each known by an id, that gains and loses points one at
/// a time (ASYNC's committed points, its robots at rest), kept so that a tick costs
/// about its events rather than a pass over the set.
///
/// When the hull is taken over the whole set (at the start, and whenever what is kept
/// no longer shows the hull), a *core* is chosen: the hull of a sample of the points,
/// leaving out the outermost few percent. Points strictly inside the core are not kept;
/// the others are, by id, and the hull is that of the kept points. It is the hull of
/// the whole set as long as the core lies strictly inside it, for then every point not
/// kept does too, and an exact chain keeps no interior point: the vertex sequence, and
/// every measure taken from it, is the same to the bit (checked against the full
/// computation at every tick in debug builds). Removing a point that may be a vertex
/// makes the hull be taken again over the kept points (a few percent of the set), and
/// only if the core then leaves it over the whole set.
///
/// Where the set's hull has fewer than three vertices (a line of robots), or in space,
/// every point is kept.
#[derive(Clone, Debug)]
pub(crate) struct KeptHull<P> {
    /// The core, counter-clockwise; empty where nothing is left out.
    core: Vec<P>,
    /// A disc and boxes inside the core: the cheap first tests.
    core_disc: (P, f64),
    core_boxes: InnerBoxes<P>,
    /// The core's bounding box (in the plane): a point outside is not inside.
    core_bounds: Option<(P, P)>,
    /// Counts the cores chosen (what was classified against the core must be again when
    /// it changes).
    generation: u64,
    /// Counts the times the hull shrank (what was found inside it must be looked at
    /// again).
    shrinks: u64,
    /// Where the hull lost ground at its last shrink (see [`KeptHull::lost`]).
    lost: Vec<(P, P)>,
    /// Counts the times the hull was taken (see [`KeptHull::taken`]).
    taken: u64,
    /// The points not strictly inside the core, by id.
    kept: Roster<P>,
    /// The hull of the kept points (once `ready`, unless `shrunk`).
    hull: Vec<P>,
    /// A disc and boxes inside `hull`.
    hull_disc: (P, f64),
    hull_boxes: InnerBoxes<P>,
    /// The bounding box of `hull` (in the plane).
    hull_bounds: Option<(P, P)>,
    /// Points kept outside `hull` since it was taken.
    grown: Vec<P>,
    /// Whether a point that may be a vertex of `hull` was removed.
    shrunk: bool,
    /// Whether the core and the kept points are set up.
    ready: bool,
    /// How many times the fraction of the points left outside the core is doubled: a
    /// core that the hull soon leaves (a swarm shrinking fast) makes the next one
    /// deeper, one that lasts makes it shallower again.
    depth: u32,
    /// Times the hull changed since the core was chosen.
    asked: u32,
}

/// A core that lasts fewer changes of the hull than this makes the next one deeper...
const SHORT_LIVED: u32 = 16;
/// ...one that lasts more than this, shallower.
const LONG_LIVED: u32 = 256;
/// The deepest a core is made: the fraction left outside doubled this many times.
const DEEPEST: u32 = 3;

/// The fraction of the points left outside the core: 1/32, but at least 256 of them,
/// doubled `depth` times.
fn outside_fraction(n: usize, depth: u32) -> f64 {
    ((256.0 / n.max(1) as f64).max(1.0 / 32.0) * f64::from(1u32 << depth)).min(1.0)
}

/// Points sampled to choose the core.
const SAMPLE: usize = 4096;

impl<P: IndexPoint> KeptHull<P> {
    /// For points known by ids; nothing is set up until the first
    /// [`KeptHull::vertices`].
    pub(crate) fn new() -> Self {
        KeptHull {
            core: Vec::new(),
            core_disc: inner_disc(&[]),
            core_boxes: [None; 3],
            core_bounds: None,
            generation: 0,
            shrinks: 0,
            lost: Vec::new(),
            taken: 0,
            kept: Roster::sparse(),
            hull: Vec::new(),
            hull_disc: inner_disc(&[]),
            hull_boxes: [None; 3],
            hull_bounds: None,
            grown: Vec::new(),
            shrunk: false,
            ready: false,
            depth: 0,
            asked: 0,
        }
    }

    /// Whether `p` is certainly strictly inside the core (exact orientations).
    pub(crate) fn in_core(&self, p: P) -> bool {
        in_boxes(&self.core_boxes, p)
            || (may_be_in(self.core_bounds, p)
                && (in_disc(self.core_disc, p) || P::strictly_inside(&self.core, p)))
    }

    /// The boxes inside the core that [`KeptHull::in_core`] tries first.
    pub(crate) fn core_boxes(&self) -> &InnerBoxes<P> {
        &self.core_boxes
    }

    /// The boxes inside the hull that [`KeptHull::in_hull`] tries first.
    pub(crate) fn hull_boxes(&self) -> &InnerBoxes<P> {
        &self.hull_boxes
    }

    /// The core (empty where there is none).
    pub(crate) fn core(&self) -> &[P] {
        &self.core
    }

    /// Counts the cores chosen so far.
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// Counts the times the hull was taken again because a point that may have been a
    /// vertex left.
    pub(crate) fn shrinks(&self) -> u64 {
        self.shrinks
    }

    /// Counts the times the hull was taken, over the kept points or the whole set: the
    /// same count, the same vertices.
    pub(crate) fn taken(&self) -> u64 {
        self.taken
    }

    /// Closed boxes (lowest corner, highest corner) that hold every point strictly
    /// inside the hull before its last shrink and not strictly inside it after: each
    /// covers a stretch of the old hull cut off by a chord between two vertices it
    /// kept (see [`lost_ground`]).
    pub(crate) fn lost(&self) -> &[(P, P)] {
        &self.lost
    }

    /// The hull as last taken (the set's, after [`KeptHull::vertices`]).
    pub(crate) fn hull(&self) -> &[P] {
        &self.hull
    }

    /// Whether `p` is certainly strictly inside the hull as last taken (it only grew
    /// since, unless a point left since).
    pub(crate) fn in_hull(&self, p: P) -> bool {
        in_boxes(&self.hull_boxes, p)
            || (may_be_in(self.hull_bounds, p)
                && (in_disc(self.hull_disc, p) || P::strictly_inside(&self.hull, p)))
    }

    /// The set gains point `p`, by `id` (not in the set).
    pub(crate) fn insert(&mut self, id: u32, p: P) {
        if !self.ready || self.in_core(p) {
            return;
        }
        self.kept.insert(id, p);
        if !(self.shrunk || self.in_hull(p)) {
            self.grown.push(p);
        }
    }

    /// The set loses the point of `id`.
    pub(crate) fn remove(&mut self, id: u32) {
        if !self.ready {
            return;
        }
        if let Some(p) = self.kept.take(id)
            && !self.shrunk
            && !self.in_hull(p)
        {
            self.shrunk = true;
        }
    }

    /// The point of `from` is now known by `to` (not in the set).
    pub(crate) fn rekey(&mut self, from: u32, to: u32) {
        if let Some(p) = self.kept.take(from) {
            self.kept.insert(to, p);
        }
    }

    /// The vertices of the set's hull (as [`HullGeometry::hull_vertices`] gives them).
    /// `all` lists every point of the set with its id (a pass made as often as needed),
    /// read only when the hull must be taken over the whole set.
    ///
    /// [`HullGeometry::hull_vertices`]: monoculus_core::geometry::HullGeometry::hull_vertices
    pub(crate) fn vertices<I: Iterator<Item = (u32, P)>>(&mut self, all: impl Fn() -> I) -> &[P] {
        let changed = !self.ready || self.shrunk || !self.grown.is_empty();
        if !changed {
            return &self.hull;
        }
        self.taken += 1;
        if self.ready && self.shrunk {
            self.shrinks += 1;
            let kept = &self.kept;
            let before = std::mem::replace(
                &mut self.hull,
                P::hull_vertices(&P::hull_candidates_of(|| kept.iter().map(|&(_, p)| p))),
            );
            self.lost = lost_ground(&before, &self.hull);
            // Without a core every point is kept: the hull is the set's.
            self.ready = self.core.iter().all(|&q| P::strictly_inside(&self.hull, q));
        } else if self.ready && !self.grown.is_empty() {
            // The core is still inside: the hull only grew.
            self.grown.extend_from_slice(&self.hull);
            self.hull = P::hull_vertices(&self.grown);
        }
        if !self.ready {
            if self.generation > 0 {
                if self.asked < SHORT_LIVED {
                    self.depth = (self.depth + 1).min(DEEPEST);
                } else if self.asked > LONG_LIVED {
                    self.depth = self.depth.saturating_sub(1);
                }
            }
            self.asked = 0;
            self.rebuild(&all);
        }
        self.asked = self.asked.saturating_add(1);
        self.shrunk = false;
        self.grown.clear();
        self.hull_disc = inner_disc(&self.hull);
        self.hull_boxes = inner_boxes(&self.hull);
        self.hull_bounds = outer_box(&self.hull);
        &self.hull
    }

    /// The hull over the whole set, a new core, the points outside it kept.
    fn rebuild<I: Iterator<Item = (u32, P)>>(&mut self, all: &impl Fn() -> I) {
        self.hull = P::hull_vertices(&P::hull_candidates_of(|| all().map(|(_, p)| p)));
        self.core = if P::DIM == 2 && self.hull.len() >= 3 {
            self.choose_core(all)
        } else {
            Vec::new()
        };
        self.core_disc = inner_disc(&self.core);
        self.core_boxes = inner_boxes(&self.core);
        self.core_bounds = outer_box(&self.core);
        self.generation += 1;
        self.kept.clear();
        for (id, p) in all() {
            if !self.in_core(p) {
                self.kept.insert(id, p);
            }
        }
        // Without a core every point is kept, and the hull is theirs.
        self.ready = true;
    }

    /// The hull of a sample of the points, all but the outermost few percent by their
    /// gauge (how far out toward the hull each lies, from the mean of its vertices).
    fn choose_core<I: Iterator<Item = (u32, P)>>(&self, all: &impl Fn() -> I) -> Vec<P> {
        let hull = &self.hull;
        let h = hull.len();
        let centre = hull.iter().fold(P::zero(), |c, &v| c + v) * (1.0 / h as f64);
        // Each edge's outward normal and the extent of the hull along it.
        let edges: Vec<(f64, f64, f64)> = (0..h)
            .map(|i| {
                let (a, b) = (hull[i], hull[(i + 1) % h]);
                let (nx, ny) = (b.axis(1) - a.axis(1), a.axis(0) - b.axis(0));
                let reach = (a.axis(0) - centre.axis(0)) * nx + (a.axis(1) - centre.axis(1)) * ny;
                (nx, ny, reach)
            })
            .collect();
        let gauge = |p: P| {
            let (x, y) = (p.axis(0) - centre.axis(0), p.axis(1) - centre.axis(1));
            edges
                .iter()
                .map(|&(nx, ny, reach)| (x * nx + y * ny) / reach)
                .fold(0.0, f64::max)
        };
        let n = all().count();
        let stride = n.div_ceil(SAMPLE).max(1);
        let mut sample: Vec<(f64, P)> = all().step_by(stride).map(|(_, p)| (gauge(p), p)).collect();
        let outside = ((sample.len() as f64 * outside_fraction(n, self.depth)).ceil() as usize)
            .min(sample.len());
        let inside = sample.len() - outside;
        if inside < 3 {
            return Vec::new();
        }
        sample.select_nth_unstable_by(inside - 1, |a, b| a.0.total_cmp(&b.0));
        let core = P::hull_vertices(&sample[..inside].iter().map(|&(_, p)| p).collect::<Vec<_>>());
        if core.len() < 3 { Vec::new() } else { core }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::boxes::in_box;
    use super::{KeptHull, inner_boxes, lost_ground};
    use glam::DVec2;
    use monoculus_core::geometry::HullGeometry;
    use monoculus_core::rng::Stream;

    /// `n` points each: random in a square, a lattice `width` points wide, on a line,
    /// and stacked (many at each point of a small lattice).
    fn sets(rng: &mut Stream, n: usize, width: usize) -> Vec<(&'static str, Vec<DVec2>)> {
        vec![
            (
                "random",
                (0..n)
                    .map(|_| DVec2::new(rng.uniform_in(-5.0, 5.0), rng.uniform_in(-5.0, 5.0)))
                    .collect(),
            ),
            (
                "lattice",
                (0..n)
                    .map(|k| DVec2::new((k % width) as f64, (k / width) as f64))
                    .collect(),
            ),
            (
                "line",
                (0..n).map(|k| DVec2::new(k as f64 * 0.1, 2.0)).collect(),
            ),
            (
                "stacked",
                (0..n)
                    .map(|k| DVec2::new((k % 7) as f64, (k % 5) as f64))
                    .collect(),
            ),
        ]
    }

    /// Points come and go (moved, as robots do, or dropped and added back), a few at a
    /// time: after each batch the kept hull is the hull of the whole set, vertex for
    /// vertex, on random, lattice, collinear and co-located sets, with the core taken
    /// again over the set whenever the kept points no longer show it.
    #[test]
    fn the_kept_hull_is_the_hull_of_the_set() {
        let mut rng = Stream::new(11, 0, 0, 0);
        let n = 600;
        let sets = sets(&mut rng, n, 25);
        for (name, mut points) in sets {
            let mut kept = KeptHull::new();
            let mut present = vec![true; n];
            let mut rebuilds = 0;
            for round in 0..120 {
                for _ in 0..(1 + rng.below(12)) {
                    let k = rng.below(n);
                    if present[k] {
                        kept.remove(k as u32);
                        present[k] = false;
                    } else {
                        // Back somewhere: near where it was, or far out, or onto another.
                        points[k] = match rng.below(3) {
                            0 => points[k] * 0.97,
                            1 => points[k] * 1.5,
                            _ => points[rng.below(n)],
                        };
                        kept.insert(k as u32, points[k]);
                        present[k] = true;
                    }
                }
                let set: Vec<(u32, DVec2)> = (0..n)
                    .filter(|&k| present[k])
                    .map(|k| (k as u32, points[k]))
                    .collect();
                let before = kept.generation();
                let got = kept.vertices(|| set.iter().copied()).to_vec();
                rebuilds += usize::from(kept.generation() != before);
                let all: Vec<DVec2> = set.iter().map(|&(_, p)| p).collect();
                assert_eq!(got, DVec2::hull_vertices(&all), "{name} round {round}");
            }
            assert!(rebuilds < 60, "{name}: the core is kept most of the time");
        }
    }

    /// Convex polygons to hold boxes: the hulls of the test sets, of points on a circle,
    /// of a square with its corners cut, of a thin sliver, and a triangle.
    pub(crate) fn polygons(rng: &mut Stream) -> Vec<(&'static str, Vec<DVec2>)> {
        let mut polygons: Vec<(&'static str, Vec<DVec2>)> = sets(rng, 300, 20)
            .into_iter()
            .map(|(name, points)| (name, DVec2::hull_vertices(&points)))
            .collect();
        let circle: Vec<DVec2> = (0..40)
            .map(|k| DVec2::from_angle(f64::from(k) * std::f64::consts::TAU / 40.0) * 3.0)
            .collect();
        let cut: Vec<DVec2> = [
            (1.0, 0.0),
            (9.0, 0.0),
            (10.0, 1.0),
            (10.0, 9.0),
            (9.0, 10.0),
        ]
        .into_iter()
        .chain([(1.0, 10.0), (0.0, 9.0), (0.0, 1.0)])
        .map(|(x, y)| DVec2::new(x, y))
        .collect();
        let sliver = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(100.0, 0.5),
            DVec2::new(0.0, 1.0),
        ];
        let triangle = vec![
            DVec2::new(-2.0, -1.0),
            DVec2::new(3.0, -1.0),
            DVec2::new(0.5, 4.0),
        ];
        for (name, points) in [("circle", circle), ("cut square", cut), ("sliver", sliver)]
            .into_iter()
            .chain([("triangle", triangle)])
        {
            polygons.push((name, DVec2::hull_vertices(&points)));
        }
        polygons
    }

    /// Every box `inner_boxes` gives lies strictly inside its polygon: its corners, its
    /// edges and random points in it pass the exact test; degenerate polygons get none;
    /// a polygon with its corners cut gets all three (the cross beside the first).
    #[test]
    fn inner_boxes_lie_strictly_inside() {
        let mut rng = Stream::new(14, 0, 0, 0);
        for (name, poly) in polygons(&mut rng) {
            let boxes = inner_boxes(&poly);
            if poly.len() < 3 {
                assert_eq!(boxes, [None; 3], "{name}");
                continue;
            }
            if matches!(name, "cut square" | "random") {
                assert!(boxes.iter().all(Option::is_some), "{name}: {boxes:?}");
            }
            for (lo, hi) in boxes.into_iter().flatten() {
                let on_edges = (0..=16).flat_map(|k| {
                    let t = f64::from(k) / 16.0;
                    let x = (lo.x + (hi.x - lo.x) * t).clamp(lo.x, hi.x);
                    let y = (lo.y + (hi.y - lo.y) * t).clamp(lo.y, hi.y);
                    [(x, lo.y), (x, hi.y), (lo.x, y), (hi.x, y)]
                });
                let within =
                    (0..200).map(|_| (rng.uniform_in(lo.x, hi.x), rng.uniform_in(lo.y, hi.y)));
                for (x, y) in on_edges.chain(within) {
                    let q = DVec2::new(x, y);
                    assert!(in_box(Some((lo, hi)), q));
                    assert!(
                        DVec2::strictly_inside(&poly, q),
                        "{name}: {q} of {lo}..{hi}"
                    );
                }
            }
        }
    }

    /// Where a hull loses ground: every point strictly inside the hull before points
    /// left and outside the boxes `lost_ground` gives is strictly inside the hull after
    /// (the exact test on both), for random, lattice, collinear and stacked sets losing
    /// a few points at a time, their outermost ones among them, tried at random points,
    /// at the set's own points, and on the chords between the vertices kept.
    #[test]
    fn a_point_outside_the_lost_ground_stays_strictly_inside() {
        let mut rng = Stream::new(12, 0, 0, 0);
        let n = 300;
        let sets = sets(&mut rng, n, 20);
        let mut tested = 0;
        for (name, points) in sets {
            let mut present = vec![true; n];
            for round in 0..60 {
                let set = |present: &[bool]| -> Vec<DVec2> {
                    (0..n).filter(|&k| present[k]).map(|k| points[k]).collect()
                };
                let before = DVec2::hull_vertices(&set(&present));
                // A few points leave, often vertices of the hull.
                for _ in 0..(1 + rng.below(4)) {
                    let k = if rng.below(2) == 0 && !before.is_empty() {
                        let v = before[rng.below(before.len())];
                        (0..n).find(|&k| present[k] && points[k] == v).unwrap_or(0)
                    } else {
                        rng.below(n)
                    };
                    present[k] = false;
                }
                if present.iter().filter(|&&p| p).count() < 10 {
                    present.iter_mut().for_each(|p| *p = true);
                }
                let after = DVec2::hull_vertices(&set(&present));
                let lost = lost_ground(&before, &after);
                let mut tries: Vec<DVec2> = points.clone();
                let (lo, hi) = monoculus_core::metrics::bounds(&points);
                tries.extend(
                    (0..400).map(|_| {
                        DVec2::new(rng.uniform_in(lo.x, hi.x), rng.uniform_in(lo.y, hi.y))
                    }),
                );
                for (a, b) in after.iter().zip(after.iter().cycle().skip(1)) {
                    tries.extend((1..8).map(|t| a.lerp(*b, f64::from(t) / 8.0)));
                }
                for p in tries {
                    let outside_lost = !lost.iter().any(|&boxed| in_box(Some(boxed), p));
                    if DVec2::strictly_inside(&before, p) && outside_lost {
                        tested += 1;
                        assert!(
                            DVec2::strictly_inside(&after, p),
                            "{name} round {round}: {p} left the hull outside {lost:?}"
                        );
                    }
                }
            }
        }
        assert!(tested > 10_000, "{tested} points tried");
    }
}
