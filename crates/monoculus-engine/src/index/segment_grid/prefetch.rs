//! A prefetch hint.

/// Asks for the cache line holding `x` (a hint: no effect on results).
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is a hint that never faults, here on a valid reference. One of
    // the workspace's four unsafe blocks (the others call the AVX2 walk once the CPU is
    // known to have it, filter the lines of sight of few robots with SSE2 and set the C
    // allocator's threshold in the command line);
    // `unsafe_code = "deny"` everywhere else.
    #[allow(
        unsafe_code,
        unused_unsafe,
        reason = "a prefetch hint; the intrinsic is safe on newer compilers"
    )]
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}
