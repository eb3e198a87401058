//! The cheap tests a robot passes before the exact predicate: [`Filter`] in double
//! precision and [`Line`] in single precision, with the proof of its rounding bound.

/// Robots tested at once by the line filter of [`SegmentGrid::blocked`] (a chunk may
/// run past a slice into the next robots: a false alarm, never a miss).
pub(super) const LANES: usize = 8;

/// The cheap test of [`SegmentGrid::blocked`] on stored coordinates.
pub(super) struct Filter {
    /// The observer, relative to the swarm's corner.
    pub(super) origin: [f64; 2],
    /// The line of sight.
    pub(super) d: [f64; 2],
    pub(super) slack: f64,
    pub(super) along_max: f64,
    pub(super) band: f64,
    /// The line's length.
    pub(super) len: f64,
    pub(super) single: bool,
    pub(super) line: Line,
}

impl Filter {
    #[inline(always)]
    pub(super) fn near(&self, &[x, y]: &[f32; 2]) -> bool {
        self.near_at(f64::from(x), f64::from(y))
    }

    /// [`Filter::near`] for a point given relative to the swarm's corner in double
    /// precision (a robot's position rather than its stored point: the same test, with
    /// no rounding of its own to allow for).
    #[inline(always)]
    pub(super) fn near_at(&self, x: f64, y: f64) -> bool {
        let (rx, ry) = (x - self.origin[0], y - self.origin[1]);
        let [dx, dy] = self.d;
        let along = rx * dx + ry * dy;
        !self.single
            | ((along > -self.slack)
                & (along < self.along_max)
                & ((rx * dy - ry * dx).abs() <= self.band))
    }

    /// [`Filter::near`] for a robot that may be up to `reach` from its stored point
    /// (`along` and the cross product each move by at most `reach` times the line's
    /// length).
    #[inline(always)]
    pub(super) fn near_within(&self, &[x, y]: &[f32; 2], reach: f32) -> bool {
        let (rx, ry) = (f64::from(x) - self.origin[0], f64::from(y) - self.origin[1]);
        let [dx, dy] = self.d;
        let room = f64::from(reach) * self.len * (1.0 + 1e-9);
        let along = rx * dx + ry * dy;
        !self.single
            | ((along > -self.slack - room)
                & (along < self.along_max + room)
                & ((rx * dy - ry * dx).abs() <= self.band + room))
    }
}

/// The first test of [`SegmentGrid::blocked`]: whether a stored point lies within `w`
/// of the line of sight, in single precision, in chunks of [`LANES`] robots (four times
/// the robots per instruction of the double-precision [`Filter`]).
///
/// The point at distance `d` from the line gives `|n . s - c| <= d` for the exact unit
/// normal `n` and offset `c`. Rounding `n` and `c` to single precision moves that by at
/// most `u (|s_x| + |s_y| + |c|)` (u = 2^-24, stored coordinates are relative to the
/// swarm's corner so `|s| <= extent`), and evaluating it in single precision by at
/// most `3 u (|s_x| + |s_y| + |c|)` more (fused or not). A blocker lies within `tol`
/// of the segment, its stored point within `tol + 2 err` of the line; `w` adds
/// `8 u (extent + |c| + 1 ulp)` to that.
pub(super) struct Line {
    pub(super) n: [f32; 2],
    pub(super) c: f32,
    pub(super) w: f32,
    /// Whether the bound holds (finite, not degenerate); else every robot passes.
    pub(super) sound: bool,
}

impl Line {
    /// The line through `origin` along `d` of length `len`; `w` bounds the distance of
    /// a stored blocker to it; `extent` bounds |s_x| + |s_y| for stored points.
    pub(super) fn new(origin: [f64; 2], d: [f64; 2], len: f64, w: f64, extent: f64) -> Self {
        let n = [d[1] / len, -d[0] / len];
        let c = n[0] * origin[0] + n[1] * origin[1];
        let u = 2f64.powi(-24);
        // `n` is a unit vector up to a few ulps of double precision, covered by the
        // factor on `w`.
        // The last factor also leaves room for rounding a sum `w + reach`
        // ([`Line::any_within`]).
        let w = (w * (1.0 + 1e-12) + 8.0 * u * (extent + c.abs()) * (1.0 + 1e-6)) * (1.0 + 1e-6);
        let sound = len > 0.0 && (extent + c.abs() + w).is_finite() && extent < 1e30 && w < 1e30;
        Line {
            n: [n[0] as f32, n[1] as f32],
            c: c as f32,
            w: w as f32,
            sound,
        }
    }

    /// Whether some point of `coords[s0..s1]` other than those at the two `ends` (the
    /// places of the observer and the observed in the layout, if found there) may lie
    /// within `w` of the line. Reads whole chunks of
    /// [`LANES`] (the padding), so may raise a false alarm.
    #[inline(always)]
    pub(super) fn any(&self, coords: &[[f32; 2]], s0: usize, s1: usize, ends: [u32; 2]) -> bool {
        if !self.sound {
            return s0 < s1;
        }
        let ([nx, ny], c, w) = (self.n, self.c, self.w);
        let mut s = s0;
        while s < s1 {
            let Some(chunk) = coords.get(s..s + LANES) else {
                return true;
            };
            let near = |&[x, y]: &[f32; 2]| (nx * x + ny * y - c).abs() <= w;
            // The ends pass only in the first and last slices: told apart there, when
            // a chunk has passed, rather than in every chunk.
            let mut hit = false;
            for p in chunk {
                hit |= near(p);
            }
            if hit
                && (s as u32..)
                    .zip(chunk)
                    .any(|(at, p)| near(p) && at != ends[0] && at != ends[1])
            {
                return true;
            }
            s += LANES;
        }
        false
    }

    /// For robots that may each be up to their `reach` (same places as `coords`) from
    /// their stored points: calls `test` with every place of `s0..s1` (but the two
    /// `ends`) whose disc may come within `w` of the line, until it returns `true`;
    /// whether it did. A reach is stored rounded up with room for the rounding of the
    /// single-precision sum `w + reach`, which `w` also leaves. Chunks of [`LANES`] are
    /// tested at once, and only the places that pass are handed on.
    #[inline(always)]
    pub(super) fn any_within(
        &self,
        coords: &[[f32; 2]],
        reach: &[f32],
        s0: usize,
        s1: usize,
        ends: [u32; 2],
        mut test: impl FnMut(usize) -> bool,
    ) -> bool {
        if !self.sound {
            return (s0..s1).any(test);
        }
        let ([nx, ny], c, w) = (self.n, self.c, self.w);
        let mut s = s0;
        while s < s1 {
            let (Some(chunk), Some(room)) = (
                coords
                    .get(s..s + LANES)
                    .and_then(|c| <&[[f32; 2]; LANES]>::try_from(c).ok()),
                reach
                    .get(s..s + LANES)
                    .and_then(|r| <&[f32; LANES]>::try_from(r).ok()),
            ) else {
                return (s..s1).any(test);
            };
            let near = |lane: usize| {
                let [x, y] = chunk[lane];
                (nx * x + ny * y - c).abs() <= w + room[lane]
            };
            // One branch-free pass gives the lanes that pass, then those are handed on
            // one by one (the ends, which pass only in the first and last slices, told
            // apart there).
            let mut passed = 0u32;
            for lane in 0..LANES {
                passed |= u32::from(near(lane)) << lane;
            }
            passed &= (1 << LANES.min(s1 - s)) - 1;
            while passed != 0 {
                let lane = passed.trailing_zeros() as usize;
                passed &= passed - 1;
                let at = (s + lane) as u32;
                if at != ends[0] && at != ends[1] && test(s + lane) {
                    return true;
                }
            }
            s += LANES;
        }
        false
    }
}
