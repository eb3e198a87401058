//! What a machine can hold: bounds checked before anything is allocated, so that a huge
//! `n`, `seeds` or sweep is refused with a message instead of a crash.

/// The most cells one experiment may have (the product of its lists' lengths).
pub const MAX_CELLS: usize = 1_000_000;
/// The most runs (cells x seeds) one experiment may have: what one machine can sort and
/// summarise at the end of a sweep (about [`BYTES_PER_RESULT`] a run: 14.5 GB at this
/// maximum, checked against the machine's memory by [`check_results`]).
pub const MAX_RUNS: u64 = 10_000_000;
/// Memory per run's row, kept by a sweep to be sorted and summarised when it ends
/// (measured: 286 MB peak for a sweep of 2 x 10^5 runs).
pub const BYTES_PER_RESULT: u64 = 1450;
/// The largest config file read, bytes (8 MiB): a config of 5 x 10^4 list values is
/// under 1 MB.
pub const MAX_CONFIG_BYTES: u64 = 8 << 20;
/// Resident memory per robot of one run, bytes: positions, per-robot state and the
/// spatial index (measured peaks: about 235 B per robot at 10^6 and 10^7 robots).
pub const BYTES_PER_ROBOT: u64 = 256;
/// Resident memory of one run beside its robots, bytes.
pub const BYTES_PER_RUN: u64 = 16 << 20;

/// The memory one run of `n` robots needs, bytes (saturating).
pub fn run_bytes(n: u64) -> u64 {
    n.saturating_mul(BYTES_PER_ROBOT)
        .saturating_add(BYTES_PER_RUN)
}

/// This machine's memory (`MemTotal` of /proc/meminfo), bytes, where known; read once
/// (a sweep checks every cell against it).
pub fn machine_bytes() -> Option<u64> {
    static MEMORY: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    *MEMORY.get_or_init(|| {
        let info = std::fs::read_to_string("/proc/meminfo").ok()?;
        let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kb * 1024)
    })
}

/// `bytes` for people: 1.5 GB, 230 MB, 12 kB.
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    for (unit, size) in [("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)] {
        if b >= size {
            return format!("{:.1} {unit}", b / size);
        }
    }
    format!("{bytes} B")
}

/// The memory the results of `runs` runs need when they are read back, bytes.
pub fn results_bytes(runs: u64) -> u64 {
    runs.saturating_mul(BYTES_PER_RESULT)
}

/// Checks that the results of `runs` runs fit in this machine's memory when read back
/// (at the end of a sweep, and by `merge`).
pub fn check_results(runs: u64) -> Result<(), String> {
    if let Some(have) = machine_bytes()
        && results_bytes(runs) > have / 2
    {
        return Err(format!(
            "{runs} runs: their results need about {} when the sweep ends (sorted and summarised); this machine has {}: split the experiment",
            human(results_bytes(runs)),
            human(have)
        ));
    }
    Ok(())
}

/// Checks that one run of `n` robots fits in this machine's memory (and in the engine's
/// robot indices); the message says how much it needs and what the machine has.
pub fn check_robots(n: u64) -> Result<(), String> {
    if n > monoculus_engine::MAX_ROBOTS as u64 {
        return Err(format!(
            "{n} robots: at most {} robots in one run",
            monoculus_engine::MAX_ROBOTS
        ));
    }
    if let Some(have) = machine_bytes() {
        let need = run_bytes(n);
        if need > have {
            return Err(format!(
                "{n} robots need about {} for one run; this machine has {}",
                human(need),
                human(have)
            ));
        }
    }
    Ok(())
}

/// The most robots a hunt searches (each candidate is a whole run).
pub const MAX_HUNT_ROBOTS: usize = 10_000;

/// The most candidates a hunt keeps side by side.
pub const MAX_HUNT_POPULATION: usize = 4096;

/// The longest SSYNC schedule a hunt searching subsets keeps (`stop.max_rounds`).
pub const MAX_HUNT_SCHEDULE: u64 = 100_000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_swarms_are_refused_with_the_memory_they_need() {
        assert!(check_robots(1000).is_ok());
        let e = check_robots(u64::MAX).unwrap_err();
        assert!(e.contains("at most"), "{e}");
        if machine_bytes().is_some() {
            let e = check_robots(1 << 31).unwrap_err();
            assert!(
                e.contains("need about 549.8 GB") && e.contains("this machine has"),
                "{e}"
            );
        }
        assert_eq!(human(2_300_000_000), "2.3 GB");
        assert_eq!(run_bytes(u64::MAX), u64::MAX);
    }
}
