//! Slot arithmetic shared by the layout and the walk: clamped slots, narrowing bounds,
//! cheap index conversions.

/// The slot of width `1 / inv` starting at `origin` that holds `v`, clamped to
/// `0..=last` (truncation equals floor here: negative values and NaN give 0). Signed
/// conversion of a clamped value: a third of the instructions of `as usize`.
#[inline]
pub(super) fn slot(v: f64, origin: f64, inv: f64, last: f64) -> usize {
    clamped((v - origin) * inv, last)
}

/// The slot holding `k` in units of slots, clamped to `0..=last` (see [`slot`]).
#[inline]
pub(super) fn clamped(k: f64, last: f64) -> usize {
    within(k, last) as i64 as usize
}

/// `k` clamped to `[0, last]` (a NaN gives 0).
#[inline(always)]
pub(super) fn within(k: f64, last: f64) -> f64 {
    let k = if k > 0.0 { k } else { 0.0 };
    if k < last { k } else { last }
}

/// `b` if it is above `a`, else `a`: a bound only ever narrowed, never by a NaN (and
/// cheaper than `f64::max`, which must pick the number out of a NaN either side).
#[inline(always)]
pub(super) fn raise(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// `b` if it is below `a`, else `a` (see [`raise`]).
#[inline(always)]
pub(super) fn lower(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// `i` as a float, for grid indices (at most a few times the number of robots, far
/// below 2^32): a cheaper conversion than from `usize`.
#[inline]
pub(super) fn float(i: usize) -> f64 {
    debug_assert!(i <= u32::MAX as usize);
    f64::from(i as u32)
}
