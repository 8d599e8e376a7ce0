//! How much memory a numeric factorisation may take, asked before it is allocated.
//!
//! Linux overcommits: a 10 GB factor allocates without complaint and the kernel's OOM killer ends
//! the process (SIGKILL, no message) once the factorisation has touched more pages than exist.
//! So the factor's size, known exactly from the symbolic analysis, is compared first with the
//! memory the kernel says is available (`MemAvailable` of /proc/meminfo: free memory plus what it
//! can reclaim without swapping), or with the limit the user sets in [`LIMIT_ENV`] (MB), and a
//! factor that cannot fit is a returned [`FeError::OutOfMemory`] (exit code 2), never an abort.

use crate::fe::error::{FeError, FeResult};

/// Environment variable holding a memory limit in MB (a positive number) that replaces the
/// kernel's available memory: to keep tactfab under a share of a machine used by others.
pub const LIMIT_ENV: &str = "TACTFAB_MEMORY_LIMIT_MB";

/// Factorisations needing less than this (bytes) are not checked \[choice\]: the plate ladder's
/// factors (up to ~5e6 entries, 40 MB) are factorised hundreds of times in a sweep, and a
/// system without this much free cannot run tactfab at all.
pub const CHECK_FROM_BYTES: u64 = 256 << 20;

/// Where a memory budget came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BudgetSource {
    /// [`LIMIT_ENV`].
    Limit,
    /// `MemAvailable` of /proc/meminfo.
    Available,
}

impl BudgetSource {
    /// As the error message names it.
    pub fn describe(self) -> &'static str {
        match self {
            BudgetSource::Limit => "the limit TACTFAB_MEMORY_LIMIT_MB sets",
            BudgetSource::Available => "available (MemAvailable of /proc/meminfo)",
        }
    }
}

/// The memory a factorisation may take (bytes) and where that figure came from; None where the
/// system does not say (not Linux) and no limit is set. A limit that is not a positive number of
/// MB is an error naming the variable.
pub fn budget() -> FeResult<Option<(u64, BudgetSource)>> {
    if let Some(bytes) = limit()? {
        return Ok(Some((bytes, BudgetSource::Limit)));
    }
    Ok(std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| mem_available_bytes(&s))
        .map(|b| (b, BudgetSource::Available)))
}

/// The limit [`LIMIT_ENV`] sets (bytes), None when it is unset; anything but a positive number
/// of MB is an error naming the variable.
pub fn limit() -> FeResult<Option<u64>> {
    let Some(v) = std::env::var_os(LIMIT_ENV) else {
        return Ok(None);
    };
    let text = v.to_string_lossy();
    match text.trim().parse::<f64>() {
        Ok(mb) if mb.is_finite() && mb > 0.0 && mb < 1e12 => Ok(Some((mb * 1048576.0) as u64)),
        _ => Err(FeError::MemoryLimit {
            value: text.into_owned(),
            hint: "set TACTFAB_MEMORY_LIMIT_MB to a positive number of MB, e.g. 4000, or unset \
                   it to use what the system has available",
        }),
    }
}

/// `MemAvailable` of a /proc/meminfo text (its value is in kB), bytes.
pub fn mem_available_bytes(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line.split_whitespace().skip(1);
    let kb: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") | None => kb.checked_mul(1024),
        Some(_) => None,
    }
}

/// Refuses `needed_bytes` for `what` when it exceeds `budget` (see [`budget`]); passes below
/// [`CHECK_FROM_BYTES`] or with no budget known.
pub fn check_fits(
    what: &str,
    needed_bytes: u64,
    budget: Option<(u64, BudgetSource)>,
) -> FeResult<()> {
    match budget {
        Some((have, source)) if needed_bytes >= CHECK_FROM_BYTES && needed_bytes > have => {
            Err(FeError::OutOfMemory {
                what: what.to_string(),
                needed_mb: needed_bytes.div_ceil(1 << 20),
                budget_mb: have >> 20,
                budget_source: source.describe(),
                hint: "use a coarser model or fewer levels (--max-levels), solve a symmetric \
                       part, free memory, or run on a larger machine",
            })
        }
        _ => Ok(()),
    }
}

/// [`check_fits`] against the current [`budget`] (read only for large factors).
pub fn ensure_fits(what: &str, needed_bytes: u64) -> FeResult<()> {
    if needed_bytes < CHECK_FROM_BYTES {
        return Ok(());
    }
    check_fits(what, needed_bytes, budget()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MEMINFO: &str = "MemTotal:       24000000 kB\nMemFree:         1000000 kB\n\
                           MemAvailable:   20000000 kB\nBuffers:          100000 kB\n";

    #[test]
    fn reads_mem_available_in_bytes() {
        assert_eq!(mem_available_bytes(MEMINFO), Some(20_000_000 * 1024));
        assert_eq!(mem_available_bytes("MemTotal: 5 kB\n"), None);
        assert_eq!(mem_available_bytes("MemAvailable: lots kB\n"), None);
        assert_eq!(mem_available_bytes("MemAvailable: 7 MB\n"), None);
    }

    #[test]
    fn refuses_only_what_does_not_fit() {
        let gb = 1u64 << 30;
        let avail = Some((4 * gb, BudgetSource::Available));
        assert!(check_fits("factor", 3 * gb, avail).is_ok());
        assert!(check_fits("factor", 4 * gb, avail).is_ok());
        let e = check_fits("the solid's Cholesky factor", 5 * gb, avail).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("5120 MB") && text.contains("4096 MB") && text.contains("MemAvailable"),
            "{text}"
        );
        assert!(matches!(e, FeError::OutOfMemory { .. }));
        // Small factors pass whatever the budget; no budget known passes.
        assert!(check_fits(
            "factor",
            CHECK_FROM_BYTES - 1,
            Some((0, BudgetSource::Limit))
        )
        .is_ok());
        assert!(check_fits("factor", 100 * gb, None).is_ok());
        let e = check_fits("factor", gb, Some((gb / 2, BudgetSource::Limit))).unwrap_err();
        assert!(e.to_string().contains("TACTFAB_MEMORY_LIMIT_MB"), "{e}");
    }
}
