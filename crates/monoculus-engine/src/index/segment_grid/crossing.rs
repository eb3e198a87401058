//! [`Crossing`]: the bins a line of sight's walk reads in each band of a part, found
//! band after band by one multiply-add in units of the part's bins.

use super::bands::Part;
use super::prefetch::prefetch;
use super::slots::{clamped, float, lower, raise, within};

/// The line of sight as the walk sees it on the axes of a layout: along the run axis
/// `a` (its major axis) and across it `b`.
pub(super) struct Track {
    /// The observer's coordinates.
    pub(super) pa: f64,
    pub(super) pb: f64,
    /// `da / db`.
    pub(super) inv_slope: f64,
    /// How far across the run axis a band's edges are widened.
    pub(super) tol_b: f64,
    /// A bound on the coordinates' magnitudes (room for rounding).
    pub(super) scale: f64,
}

impl Track {
    /// Where the line crosses the edges of band `r` of `part` widened by `tol_b`, as
    /// offsets along the run axis from the observer (unsorted).
    #[inline]
    fn edges(&self, part: &Part, r: usize) -> (f64, f64) {
        let edge0 = part.origin[1] + float(r) * part.height - self.tol_b;
        let edge1 = part.origin[1] + float(r + 1) * part.height + self.tol_b;
        (
            (edge0 - self.pb) * self.inv_slope,
            (edge1 - self.pb) * self.inv_slope,
        )
    }
}

/// The bins of each band of one part that a walk reads: those meeting the stretch of
/// the run axis where the line, widened, crosses the band (a line across several
/// bands), within the line's extent on that axis.
///
/// The stretch of band `r` lies between the run-axis coordinates
/// `pa + (o_b + r h -+ tol_b - pb) da / db` (the band's widened edges), each an affine
/// function of `r`: kept in units of bins, `x0 + (r - r0) step` and that plus `width`,
/// one multiply-add a band rather than both edges computed afresh in coordinates and
/// then turned into bins (measured in docs/performance.md).
///
/// Exactness. Computed band by band, the lower bound is `pa + min(t0, t1) - room` with
/// `(t0, t1)` from [`Track::edges`] and `room = 64 eps (scale + |t0| + |t1|)` for the
/// rounding of those terms, and a blocker's coordinate is never below it (the walk's
/// bound, tested with blockers at the cone's edge next to bin corners); a coordinate
/// turned into bins by the rounded operations of `Part::bin` keeps its order. So the
/// walk misses no blocker if its bound in bins is never above that bound turned into
/// bins. Both are the same real number computed two ways from terms bounded by `m`
/// (below, in bins), each way with an error of at most 16 u m (u = 2^-53, about a
/// dozen roundings): the stretch is widened by 64 eps m = 128 u m on either side, and
/// `room` taken at its largest over the bands (the ends). The same holds of the upper
/// bound. A NaN or an infinite bound leaves the line's extent alone (every bin of it).
pub(super) struct Crossing {
    /// The first band walked.
    r0: usize,
    /// Whether the line crosses several bands, and is not too close to the run axis
    /// for its crossings to be computed (else the extent alone bounds each band).
    along: bool,
    /// The lower widened edge's crossing of band `r0`, in bins...
    x0: f64,
    /// ...and how far it moves a band.
    step: f64,
    /// The stretch of a band from that crossing: `[x + lo_off, x + hi_off]`.
    lo_off: f64,
    hi_off: f64,
    /// The line's extent on the run axis, in bins.
    lo: f64,
    hi: f64,
    /// Of a nested part, the top of its box in bins (a band crossed beside the box
    /// has no robot near the line); of the first, infinity.
    top: f64,
    /// Whether the part is nested (robots lie in its box).
    nested: bool,
    /// The last bin.
    last: f64,
}

impl Crossing {
    /// The bins a walk reads in bands `r0..=r1` of `part` for a line whose
    /// candidates lie within `[a_lo, a_hi]` on the run axis; `line` if the walk
    /// narrows each band to where the line crosses it.
    #[inline]
    pub(super) fn new(
        part: &Part,
        (r0, r1): (usize, usize),
        (a_lo, a_hi): (f64, f64),
        line: Option<&Track>,
        nested: bool,
    ) -> Self {
        // As `Part::bin` takes a coordinate before clamping, so that a robot at
        // `v >= a_lo` has a bin coordinate at least this one's.
        let bins = |v: f64| part.bin_at(v);
        let mut crossing = Crossing {
            r0,
            along: false,
            x0: 0.0,
            step: 0.0,
            lo_off: 0.0,
            hi_off: 0.0,
            lo: bins(a_lo),
            hi: bins(a_hi),
            top: bins(part.top[0]),
            nested,
            last: part.last[0],
        };
        let Some(line) = line else {
            return crossing;
        };
        let (t0, t1) = line.edges(part, r0);
        let (s0, s1) = line.edges(part, r1);
        let most = t0.abs().max(t1.abs()).max(s0.abs()).max(s1.abs());
        // The walk's room for rounding, at every band at most this.
        let room = 64.0 * f64::EPSILON * (line.scale + 2.0 * most) * (1.0 + 1e-9);
        let iw = part.inv_width;
        let is = line.inv_slope.abs();
        // Every term of either computation, in bins.
        let m = (is
            * (part.origin[1].abs() + float(r1 + 1) * part.height + line.tol_b + line.pb.abs())
            + line.pa.abs()
            + 2.0 * most
            + room
            + part.origin[0].abs())
            * iw;
        let room = room * iw * (1.0 + 1e-9) + 64.0 * f64::EPSILON * m;
        let width = (part.height + 2.0 * line.tol_b) * line.inv_slope * iw;
        crossing.along = true;
        crossing.x0 = bins(line.pa + t0);
        crossing.step = part.height * line.inv_slope * iw;
        crossing.lo_off = width.min(0.0) - room;
        crossing.hi_off = width.max(0.0) + room;
        crossing
    }

    /// The first and last bin the walk reads in band `r`, if any; `FLOOR` where
    /// rounding down is one instruction (see [`Crossing::bin`]).
    #[inline(always)]
    pub(super) fn bins<const FLOOR: bool>(&self, r: usize) -> Option<(usize, usize)> {
        let (mut lo, mut hi) = (self.lo, self.hi);
        if self.along {
            let x = self.x0 + float(r - self.r0) * self.step;
            lo = raise(lo, x + self.lo_off);
            hi = lower(hi, x + self.hi_off);
        }
        let beside = self.nested && ((hi < 0.0) | (lo > self.top));
        if lo <= hi && !beside {
            Some((self.bin::<FLOOR>(lo), self.bin::<FLOOR>(hi)))
        } else {
            None
        }
    }

    /// The bin of bin coordinate `k`, clamped to the part (a NaN gives 0): the same
    /// as [`clamped`]. With `FLOOR` (the walk compiled for AVX2, where rounding down is
    /// one instruction) without the saturating conversion's tests, the value being in
    /// range here; else (rounding down a call) through that conversion.
    #[inline(always)]
    fn bin<const FLOOR: bool>(&self, k: f64) -> usize {
        if !FLOOR {
            return clamped(k, self.last);
        }
        // Exact below 2^52: `whole + 2^52` holds `whole` in the low bits of its mantissa.
        const SHIFT: f64 = 4_503_599_627_370_496.0;
        let k = within(k, self.last);
        let bin = ((k.floor() + SHIFT).to_bits() - SHIFT.to_bits()) as usize;
        debug_assert_eq!(bin, clamped(k, self.last));
        bin
    }

    /// Lays out the next bands from `*r` on (up to `r1`): for each the bins the walk
    /// reads, as their first and one-past-last numbers in `start` (whose entries are
    /// asked for), until `bins` is full; how many.
    #[inline(always)]
    pub(super) fn batch<const FLOOR: bool>(
        &self,
        r: &mut usize,
        r1: usize,
        part: &Part,
        start: &[u32],
        bins: &mut [(usize, usize)],
    ) -> usize {
        let mut m = 0;
        while *r <= r1 && m < bins.len() {
            if let Some((c0, c1)) = self.bins::<FLOOR>(*r) {
                let row = part.row(*r);
                bins[m] = (row + c0, row + c1 + 1);
                prefetch(&start[bins[m].0]);
                prefetch(&start[bins[m].1]);
                m += 1;
            }
            *r += 1;
        }
        m
    }
}
