//! How the C allocator (glibc's, on Linux) serves large blocks.

/// Blocks of 2 MiB and more are mapped from the system and returned to it when freed.
///
/// Left alone, glibc raises that threshold to the size of the largest mapped block freed
/// so far (up to 32 MiB), so that once the band grid of an ASYNC run, made afresh at every
/// tick with Looks (arrays of 2.6 to 16 MB at 10^6 robots), has been freed once, its
/// arrays come from the heap, which they leave fragmented: one ASYNC epoch at 10^6
/// peaked at 299 MB resident, 277 MB with the threshold held at 3 MiB, 272-273 MB at
/// 2 MiB; a late epoch, whose crowded core's cells make arrays of 2.6 MB, 306 MB at
/// 3 MiB and 297 MB at 2 MiB (see docs/performance.md). At 128 KiB one epoch peaked at
/// 263 MB, but then the grids of 10^5 robots (arrays under 2 MB, remade every few ticks
/// late in an x100 run) were mapped afresh at every remake, and unmapping them stalled
/// both threads: smaller blocks stay in the heap.
/// A threshold set in the environment (`MALLOC_MMAP_THRESHOLD_`) is left as it is.
/// Called first in `main`, before any other thread runs.
pub fn map_large_blocks() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    if std::env::var_os("MALLOC_MMAP_THRESHOLD_").is_none() {
        // SAFETY: `mallopt` sets a parameter of the allocator and has no other
        // precondition; no other thread is allocating yet. One of the workspace's four
        // unsafe blocks (the others: `prefetch`, the AVX2 walk and the SSE2 filter of few
        // robots).
        #[allow(unsafe_code, reason = "setting a parameter of the C allocator")]
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, 2 << 20);
        }
    }
}
