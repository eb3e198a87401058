//! Lines of sight: whether any robot blocks the view from robot i to robot j, walked band
//! by band along the line's major axis.

use monoculus_core::vision::{VisionParams, blocks};

use super::super::{IndexPoint, Locate, Tube};
use super::SegmentGrid;
use super::bands::Bands;
use super::crossing::{Crossing, Track};
use super::filter::{Filter, Line};
use super::prefetch::prefetch;
use super::slots::{lower, raise};

impl SegmentGrid {
    /// Whether some robot other than `i` and `j` blocks the view from `positions[i]` to
    /// `positions[j]`, every robot's position being within `drift` of the point the grid
    /// was built over (0 for a grid over `positions` themselves; for a
    /// [moving](SegmentGrid::moving) grid, the largest reach, each robot being within its
    /// own).
    pub fn blocked<P: IndexPoint, L: Locate<P> + ?Sized>(
        &self,
        positions: &L,
        i: usize,
        j: usize,
        v: &VisionParams,
        drift: f64,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above), all `blocked_avx2` needs. One
            // of the workspace's four unsafe blocks (the others: `prefetch`, the SSE2
            // filter of few robots and the C allocator's threshold set in the command
            // line).
            #[allow(
                unsafe_code,
                reason = "calling code compiled for a detected CPU feature"
            )]
            return unsafe { self.blocked_avx2(positions, i, j, v, drift) };
        }
        self.walk::<false, _, _>(positions, i, j, v, drift)
    }

    /// [`Self::walk`] compiled for AVX2: the line filter tests eight robots per
    /// instruction instead of four (measured: see docs/performance.md).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn blocked_avx2<P: IndexPoint, L: Locate<P> + ?Sized>(
        &self,
        positions: &L,
        i: usize,
        j: usize,
        v: &VisionParams,
        drift: f64,
    ) -> bool {
        self.walk::<true, _, _>(positions, i, j, v, drift)
    }

    /// The body of [`Self::blocked`]; `FLOOR` where rounding down is one instruction
    /// (compiled for AVX2).
    #[inline(always)]
    pub(super) fn walk<const FLOOR: bool, P: IndexPoint, L: Locate<P> + ?Sized>(
        &self,
        positions: &L,
        i: usize,
        j: usize,
        v: &VisionParams,
        drift: f64,
    ) -> bool {
        let (p, q) = (positions.at(i), positions.at(j));
        let tube = Tube::new(p, q, v.eps_ang, 0.0);
        // Every blocker lies within `tube.tolerance()` of the segment (the blocking cone
        // and room for rounding in the exact test), so the point the grid holds for it
        // within `tube.tolerance() + drift`: the bins walked. A moving grid's filter
        // gives each robot its own reach; otherwise the filter allows the drift too.
        let reaching = !self.rows.reach.is_empty();
        let tol = tube.tolerance() + if reaching { 0.0 } else { drift };
        let tol_bins = tube.tolerance() + drift;
        let d = q - p;
        let len = d.length();
        let (px, py, dx, dy) = (p.axis(0), p.axis(1), d.axis(0), d.axis(1));
        // The filter below works on stored coordinates, each off by at most `rounding`
        // (plus double rounding of the shift to the swarm's corner): that moves `along`
        // and the cross product by at most `slack`.
        // A moving grid's discs may lie up to `drift` outside the box, their stored
        // centres rounded as coordinates that much larger.
        let err = self.rounding
            + 2.0 * drift * 2f64.powi(-24)
            + 8.0
                * f64::EPSILON
                * (px.abs() + py.abs() + self.lo[0].abs() + self.lo[1].abs() + len);
        let slack = 2.0 * err * (dx.abs() + dy.abs());
        let band = 2.0 * tol * len + slack;
        // A blocker lies strictly between p and q along the line; the grid's point for
        // it up to `drift` before or beyond (a moving grid: its own reach).
        let slack = slack + if reaching { 0.0 } else { drift * len };
        let along_max = len * len + slack;
        let (rpx, rpy) = (px - self.lo[0], py - self.lo[1]);
        // Walk the bands running along the major axis `a`.
        let g = if dx.abs() >= dy.abs() {
            &self.rows
        } else {
            &self.columns
        };
        // Read only before the first filter pass (below): asked for now, the two
        // places (random robots, a cache and TLB miss each at 10^6) arrive while the
        // first batch of bands is laid out.
        prefetch(&g.place[i]);
        prefetch(&g.place[j]);
        let (a, b) = (g.run, 1 - g.run);
        let (pa, pb, da, db) = (p.axis(a), p.axis(b), d.axis(a), d.axis(b));
        // The grid's point for a blocker lies within `tol_bins` of the segment, so
        // within `tol_bins` of its extent on either axis. Band by band: a point at
        // distance t from the line, at angle phi to the major axis, lies along that
        // axis within t / |sin phi| of where the line is at the band's edges widened by
        // `tol_b` across it, for `tol_b = t / |cos phi|` (at most sqrt 2 t): twice the
        // tube's tolerance (room for rounding), and the drift with that factor.
        let secant = len / da.abs();
        let tol_b = 2.0 * (tol_bins - drift) + drift * secant * (1.0 + 1e-9);
        let (a_lo, a_hi) = (pa.min(pa + da) - tol_bins, pa.max(pa + da) + tol_bins);
        let (b_lo, b_hi) = (pb.min(pb + db) - tol_b, pb.max(pb + db) + tol_b);
        // Rounding in the inverse below is covered by this much room on the major axis.
        let scale = pa
            .abs()
            .max((pa + da).abs())
            .max(pb.abs())
            .max((pb + db).abs())
            + len;
        let steep = db.abs() * 1e12 >= da.abs();
        let track = Track {
            pa,
            pb,
            inv_slope: da / db,
            tol_b,
            scale,
        };
        // Cheap filter: within twice the tube's radius of the line, strictly between p
        // and q (widened by the rounding of stored coordinates).
        let extent = self.hi[0] - self.lo[0] + self.hi[1] - self.lo[1] + 2.0 * drift;
        let filter = Filter {
            origin: [rpx, rpy],
            d: [dx, dy],
            slack,
            along_max,
            band,
            len,
            single: self.single,
            line: Line::new([rpx, rpy], [dx, dy], len, tol + 2.0 * err, extent),
        };
        let near = |c: &[f32; 2]| filter.near(c);
        // The ends lie on the line: the line filter leaves out their places in the
        // layout (for a robot that moved since, its old place), sparing an exact pass
        // over the first and last slices without reading which robot each place holds.
        let mut ends = None;
        // Bands are taken a batch at a time: first where the line crosses each, then
        // its slice's bounds, then its robots, each step prefetching what the next one
        // reads, so that the cache misses of a batch overlap instead of adding up; and
        // the next batch is laid out before this one's robots are read, so that its
        // slices' bounds arrive meanwhile.
        const BATCH: usize = 32;
        let (mut bins, mut slices) = ([(0usize, 0usize); BATCH], [(0usize, 0usize); BATCH]);
        for (nested, part) in g.parts.iter().enumerate() {
            let (mut a_lo, mut a_hi, mut b_lo, mut b_hi) = (a_lo, a_hi, b_lo, b_hi);
            if nested > 0 {
                // Only the stretch of the segment within `tol_bins` of the part's box
                // can pass a grid point of it that close (with room for rounding).
                let room = 1e-9
                    * (scale
                        + part.origin[0].abs()
                        + part.origin[1].abs()
                        + part.top[0].abs()
                        + part.top[1].abs());
                let w = tol_bins * (1.0 + 1e-9) + room;
                let t = clip((0.0, 1.0), pa, da, part.origin[0] - w, part.top[0] + w);
                let (t0, t1) = clip(t, pb, db, part.origin[1] - w, part.top[1] + w);
                if t0 > t1 {
                    continue;
                }
                let (a0, a1) = (pa + t0 * da, pa + t1 * da);
                let (b0, b1) = (pb + t0 * db, pb + t1 * db);
                a_lo = raise(a_lo, a0.min(a1) - tol_bins - room);
                a_hi = lower(a_hi, a0.max(a1) + tol_bins + room);
                b_lo = raise(b_lo, b0.min(b1) - tol_b - room);
                b_hi = lower(b_hi, b0.max(b1) + tol_b + room);
                if !part.meets(a_lo, a_hi, b_lo, b_hi) {
                    continue;
                }
            }
            let (r0, r1) = (part.band(b_lo), part.band(b_hi));
            // Where the line crosses each band, widened by `tol_b` (robots near a band
            // edge may sit in either band after rounding: `tol` includes room for it).
            let narrowed = (r0 < r1 && steep).then_some(&track);
            let crossing = Crossing::new(part, (r0, r1), (a_lo, a_hi), narrowed, nested > 0);
            let mut r = r0;
            let mut m = crossing.batch::<FLOOR>(&mut r, r1, part, &g.start, &mut bins);
            while m > 0 {
                for (slice, &(c0, c1)) in slices.iter_mut().zip(&bins[..m]) {
                    *slice = (g.start[c0] as usize, g.start[c1] as usize);
                    // A slice is a few robots: its first and last cache lines (the padding
                    // keeps both indices valid; the hardware streams longer slices).
                    prefetch(&g.coords[slice.0]);
                    prefetch(&g.coords[slice.1]);
                }
                let after = crossing.batch::<FLOOR>(&mut r, r1, part, &g.start, &mut bins);
                let batch = std::mem::replace(&mut m, after);
                if reaching {
                    let line = (p, q, i, j);
                    if self.any_reaching(g, &slices[..batch], &filter, positions, line, v) {
                        return true;
                    }
                    continue;
                }
                for &(s0, s1) in &slices[..batch] {
                    // Candidates are rare: one branch-free pass over the slice first.
                    let ends = *ends.get_or_insert_with(|| [g.place[i], g.place[j]]);
                    if !filter.line.any(&g.coords, s0, s1, ends) {
                        continue;
                    }
                    for s in s0..s1 {
                        // Which robot a place holds is read only for those that
                        // pass: in a large swarm a read of `items` is a cache miss of
                        // its own, and the single-precision pass, whose bound widens
                        // with the swarm's extent, lets through several slices a line
                        // where this test lets through about one robot (counted in
                        // docs/performance.md).
                        if !near(&g.coords[s]) {
                            continue;
                        }
                        let k = g.items[s] as usize;
                        if k != i && k != j && blocks(p, positions.at(k), q, v) {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }

    /// Whether a robot of `slices` (a batch of bands) of a moving grid's layout `g`
    /// blocks the view along `line` (from `p`, robot `i`, to `q`, robot `j`): those
    /// whose disc came near the line (the line filter, then the cheap test) are the
    /// candidates, asked where they are now, then by the cheap test and the exact one.
    /// Finding where a robot is reads its slot in the roster of robots in mid-move,
    /// its entry there and its settled point, one read leading to the next: in a swarm
    /// too large for the caches the candidates are held until the batch is filtered,
    /// those reads asked for meanwhile, so that their misses overlap.
    #[inline(always)]
    fn any_reaching<P: IndexPoint, L: Locate<P> + ?Sized>(
        &self,
        g: &Bands,
        slices: &[(usize, usize)],
        filter: &Filter,
        positions: &L,
        (p, q, i, j): (P, P, usize, usize),
        v: &VisionParams,
    ) -> bool {
        // The ends' places, which the line filter leaves out.
        let ends = [g.place[i], g.place[j]];
        let candidate = |s: usize| {
            let k = g.items[s] as usize;
            filter.near_within(&g.coords[s], g.reach[s]) && k != i && k != j
        };
        let found = |k: usize| {
            let r = positions.at(k);
            let (x, y) = (r.axis(0) - self.lo[0], r.axis(1) - self.lo[1]);
            filter.near_at(x, y) && blocks(p, r, q, v)
        };
        let (coords, reach) = (&g.coords, &g.reach);
        // Loops rather than iterator adaptors: called from the walk compiled for AVX2,
        // an adaptor's body may be compiled apart from it, without.
        if g.items.len() < HOLD_FROM {
            for &(s0, s1) in slices {
                let blocker = |s: usize| candidate(s) && found(g.items[s] as usize);
                if filter.line.any_within(coords, reach, s0, s1, ends, blocker) {
                    return true;
                }
            }
            return false;
        }
        let mut held = [0u32; HELD];
        let mut count = 0;
        let confirm = |robots: &[u32]| {
            for &k in robots {
                positions.prefetch_next(k as usize);
            }
            for &k in robots {
                if found(k as usize) {
                    return true;
                }
            }
            false
        };
        let mut hit = false;
        for &(s0, s1) in slices {
            let hold = |s: usize| {
                if candidate(s) {
                    let k = g.items[s];
                    positions.prefetch(k as usize);
                    held[count] = k;
                    count += 1;
                    if count == HELD {
                        hit = confirm(&held);
                        count = 0;
                    }
                }
                hit
            };
            if filter.line.any_within(coords, reach, s0, s1, ends, hold) {
                return true;
            }
        }
        count > 0 && confirm(&held[..count])
    }
}

/// The candidates a walk through a moving grid holds at once...
const HELD: usize = 64;
/// ...in a grid of at least this many robots (their positions and the roster of robots
/// in mid-move larger than a core's second-level cache; measured in
/// docs/performance.md).
pub(super) const HOLD_FROM: usize = 1 << 15;

/// The part of the parameter interval `t` (of `p + t d` on one axis) where the point is
/// within `[lo, hi]` on that axis (empty: start above end).
#[inline(always)]
fn clip(t: (f64, f64), p: f64, d: f64, lo: f64, hi: f64) -> (f64, f64) {
    if d == 0.0 {
        return if (lo <= p) & (p <= hi) { t } else { (1.0, 0.0) };
    }
    let (u0, u1) = ((lo - p) / d, (hi - p) / d);
    let (u0, u1) = if u1 < u0 { (u1, u0) } else { (u0, u1) };
    (raise(t.0, u0), lower(t.1, u1))
}
