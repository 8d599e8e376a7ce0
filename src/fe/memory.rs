//! How much memory a numeric factorisation may take, asked before it is allocated.
//!
//! Linux overcommits: a 10 GB factor allocates without complaint and the kernel's OOM killer ends
//! the process (SIGKILL, no message) once the factorisation has touched more pages than exist.
//! So the factor's size, known exactly from the symbolic analysis, is compared first with the
//! memory the kernel says is available (`MemAvailable` of /proc/meminfo: free memory plus what it
//! can reclaim without swapping), or with the limit the user sets in [`LIMIT_ENV`] (MB), and a
//! factor that cannot fit is a returned [`FeError::OutOfMemory`] (exit code 2), never an abort.
//!
//! Factorisations run side by side (the plate ladder solves a build's scenes in parallel), and the
//! kernel's figure does not show a factor until its pages are touched. So every large
//! factorisation is entered in a [`Ledger`] from its check until its factor is dropped: it must
//! fit beside the factorisations still under way (and, under a limit, beside every factor held),
//! not only alone. A factor that fits alone but not beside the others is refused too: waiting
//! would deadlock a rayon worker that stole the other's job.

use std::sync::{Mutex, MutexGuard};

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

/// Refuses `needed_bytes` for `what` when it exceeds `budget` (see [`budget`]) less `others_bytes`
/// that other factorisations take from it; passes below [`CHECK_FROM_BYTES`] or with no budget
/// known.
pub fn check_fits(
    what: &str,
    needed_bytes: u64,
    others_bytes: u64,
    budget: Option<(u64, BudgetSource)>,
) -> FeResult<()> {
    match budget {
        Some((have, source))
            if needed_bytes >= CHECK_FROM_BYTES
                && needed_bytes.saturating_add(others_bytes) > have =>
        {
            Err(FeError::OutOfMemory {
                what: what.to_string(),
                needed_mb: needed_bytes.div_ceil(1 << 20),
                budget_mb: have >> 20,
                budget_source: source.describe(),
                others_mb: others_bytes.div_ceil(1 << 20),
                hint: "use a coarser model or fewer levels (--max-levels), solve a symmetric \
                       part or fewer scenes at once, free memory, or run on a larger machine",
            })
        }
        _ => Ok(()),
    }
}

/// [`check_fits`] against the current [`budget`] (read only for large factors) beside what
/// [`LEDGER`] holds, without entering it: for a symbolic analysis, whose factor is not allocated
/// yet.
pub fn ensure_fits(what: &str, needed_bytes: u64) -> FeResult<()> {
    if needed_bytes < CHECK_FROM_BYTES {
        return Ok(());
    }
    let budget = budget()?;
    check_fits(what, needed_bytes, LEDGER.others(budget), budget)
}

/// Enters a factorisation of `needed_bytes` (its factor's `kept_bytes` and faer's scratch) in
/// [`LEDGER`] when it fits beside the others there; None for small factorisations, which are not
/// counted.
pub fn reserve(
    what: &str,
    needed_bytes: u64,
    kept_bytes: u64,
) -> FeResult<Option<Reservation<'static>>> {
    if needed_bytes < CHECK_FROM_BYTES {
        return Ok(None);
    }
    LEDGER
        .reserve(what, needed_bytes, kept_bytes, budget()?)
        .map(Some)
}

/// `solve` on every item in parallel; an item refused for memory only because others were under
/// way beside it ([`FeError::is_crowded_out`]) is solved again after them, one at a time, so a
/// machine with room for one factor at a time still gets every answer. The answers are in the
/// items' order and do not depend on which were solved again (each solve is deterministic).
pub fn in_parallel_then_alone<I: Sync, T: Send>(
    items: &[I],
    solve: impl Fn(&I) -> FeResult<T> + Sync,
) -> FeResult<Vec<T>> {
    use rayon::prelude::*;
    let first: Vec<FeResult<T>> = items.par_iter().map(&solve).collect();
    first
        .into_iter()
        .zip(items)
        .map(|(r, item)| match r {
            Err(e) if e.is_crowded_out() => solve(item),
            r => r,
        })
        .collect()
}

/// The process's ledger of large factorisations.
pub static LEDGER: Ledger = Ledger::new();

/// Large factorisations entered between their check and their factor's drop.
#[derive(Debug, Default)]
pub struct Ledger {
    counts: Mutex<Counts>,
}

#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    /// Bytes of factorisations checked but not finished: allocated, perhaps not yet touched, so
    /// not in the kernel's figure.
    in_flight: u64,
    /// Bytes of finished factors still alive: in the kernel's figure, but counted against a
    /// limit.
    held: u64,
}

impl Counts {
    /// Bytes taken from `budget`: what is under way, and under a limit what is held too.
    fn taken(&self, budget: Option<(u64, BudgetSource)>) -> u64 {
        match budget {
            Some((_, BudgetSource::Limit)) => self.in_flight.saturating_add(self.held),
            _ => self.in_flight,
        }
    }
}

impl Ledger {
    /// An empty ledger.
    pub const fn new() -> Self {
        Ledger {
            counts: Mutex::new(Counts {
                in_flight: 0,
                held: 0,
            }),
        }
    }

    /// The counts; a poisoned lock (a panic elsewhere while holding it, which only adds and
    /// subtracts) still holds consistent numbers.
    fn counts(&self) -> MutexGuard<'_, Counts> {
        self.counts.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Bytes the others take from `budget`: those under way, and under a limit those held too.
    pub fn others(&self, budget: Option<(u64, BudgetSource)>) -> u64 {
        self.counts().taken(budget)
    }

    /// Checks `needed_bytes` beside the others against `budget` and enters it (the check and the
    /// entry under one lock, so two factorisations cannot both pass on the same room).
    pub fn reserve(
        &self,
        what: &str,
        needed_bytes: u64,
        kept_bytes: u64,
        budget: Option<(u64, BudgetSource)>,
    ) -> FeResult<Reservation<'_>> {
        let mut c = self.counts();
        check_fits(what, needed_bytes, c.taken(budget), budget)?;
        c.in_flight = c.in_flight.saturating_add(needed_bytes);
        Ok(Reservation {
            ledger: self,
            in_flight: needed_bytes,
            kept: kept_bytes.min(needed_bytes),
        })
    }
}

/// A factorisation under way, entered in a [`Ledger`]; dropped unfinished (an error), it leaves.
#[derive(Debug)]
pub struct Reservation<'a> {
    ledger: &'a Ledger,
    in_flight: u64,
    kept: u64,
}

impl<'a> Reservation<'a> {
    /// The factorisation is done: its scratch is freed and its factor touched (in the kernel's
    /// figure now), so only the factor stays entered, as held, until it is dropped.
    pub fn finished(mut self) -> Held<'a> {
        let mut c = self.ledger.counts();
        c.in_flight = c.in_flight.saturating_sub(self.in_flight);
        c.held = c.held.saturating_add(self.kept);
        self.in_flight = 0;
        Held {
            ledger: self.ledger,
            bytes: self.kept,
        }
    }
}

impl Drop for Reservation<'_> {
    fn drop(&mut self) {
        if self.in_flight > 0 {
            let mut c = self.ledger.counts();
            c.in_flight = c.in_flight.saturating_sub(self.in_flight);
        }
    }
}

/// A finished factor entered in a [`Ledger`] while it lives.
#[derive(Debug)]
pub struct Held<'a> {
    ledger: &'a Ledger,
    bytes: u64,
}

impl Clone for Held<'_> {
    /// A cloned factor is another copy of the values, held as well.
    fn clone(&self) -> Self {
        let mut c = self.ledger.counts();
        c.held = c.held.saturating_add(self.bytes);
        Held {
            ledger: self.ledger,
            bytes: self.bytes,
        }
    }
}

impl Drop for Held<'_> {
    fn drop(&mut self) {
        let mut c = self.ledger.counts();
        c.held = c.held.saturating_sub(self.bytes);
    }
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
        assert!(check_fits("factor", 3 * gb, 0, avail).is_ok());
        assert!(check_fits("factor", 4 * gb, 0, avail).is_ok());
        let e = check_fits("the solid's Cholesky factor", 5 * gb, 0, avail).unwrap_err();
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
            0,
            Some((0, BudgetSource::Limit))
        )
        .is_ok());
        assert!(check_fits("factor", 100 * gb, 0, None).is_ok());
        let e = check_fits("factor", gb, 0, Some((gb / 2, BudgetSource::Limit))).unwrap_err();
        assert!(e.to_string().contains("TACTFAB_MEMORY_LIMIT_MB"), "{e}");
    }

    /// Two factorisations that each fit alone but not together: the second is refused while the
    /// first is under way; once the first is finished it is in the kernel's figure (so only a
    /// limit still counts it) and once dropped it is gone.
    #[test]
    fn the_ledger_counts_factorisations_under_way_and_held() {
        let mb = 1u64 << 20;
        let ledger = Ledger::new();
        let limit = Some((1000 * mb, BudgetSource::Limit));
        let avail = Some((1000 * mb, BudgetSource::Available));
        let a = ledger
            .reserve("factor A", 600 * mb, 500 * mb, limit)
            .unwrap();
        for budget in [limit, avail] {
            let e = ledger
                .reserve("factor B", 600 * mb, 500 * mb, budget)
                .unwrap_err();
            let text = e.to_string();
            assert!(
                text.contains("needs 600 MB beside the 600 MB that other factorisations"),
                "{text}"
            );
        }
        let held = a.finished();
        assert_eq!(ledger.others(avail), 0);
        assert_eq!(ledger.others(limit), 500 * mb);
        assert!(ledger
            .reserve("factor B", 600 * mb, 500 * mb, limit)
            .is_err());
        let b = ledger
            .reserve("factor B", 600 * mb, 500 * mb, avail)
            .unwrap();
        drop(b); // unfinished (an error): it leaves
        assert_eq!(ledger.others(avail), 0);
        let copy = held.clone();
        assert_eq!(ledger.others(limit), 1000 * mb);
        drop((held, copy));
        assert_eq!(ledger.others(limit), 0);
        assert!(ledger
            .reserve("factor B", 600 * mb, 500 * mb, limit)
            .is_ok());
        // Small factorisations are neither checked nor entered.
        let small = ledger.reserve(
            "factor C",
            CHECK_FROM_BYTES - 1,
            0,
            Some((0, BudgetSource::Limit)),
        );
        assert!(small.is_ok());
    }

    /// Threads racing for the same room: exactly one gets it (the check and the entry are one
    /// step).
    #[test]
    fn racing_factorisations_cannot_share_the_same_room() {
        let mb = 1u64 << 20;
        let ledger = Ledger::new();
        let budget = Some((1000 * mb, BudgetSource::Available));
        let barrier = std::sync::Barrier::new(8);
        let granted = std::thread::scope(|s| {
            let handles: Vec<_> = (0..8)
                .map(|_| {
                    s.spawn(|| {
                        barrier.wait();
                        ledger.reserve("factor", 600 * mb, 0, budget).ok()
                    })
                })
                .collect();
            let got: Vec<_> = handles.into_iter().map(|h| h.join().unwrap()).collect();
            got.iter().filter(|r| r.is_some()).count()
        });
        assert_eq!(granted, 1);
        assert_eq!(ledger.others(budget), 0);
    }

    fn refused(others_mb: u64, needed_mb: u64) -> FeError {
        FeError::OutOfMemory {
            what: "factor".into(),
            needed_mb,
            budget_mb: 1000,
            budget_source: BudgetSource::Limit.describe(),
            others_mb,
            hint: "",
        }
    }

    /// Items crowded out in the parallel pass are solved again alone, in order; a factor too big
    /// even alone, or any other error, is the answer.
    #[test]
    fn crowded_out_items_are_solved_again_alone() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        assert!(refused(600, 600).is_crowded_out());
        assert!(!refused(600, 1200).is_crowded_out());
        assert!(!refused(0, 600).is_crowded_out());
        let tries: Vec<AtomicUsize> = (0..6).map(|_| AtomicUsize::new(0)).collect();
        let items: Vec<usize> = (0..6).collect();
        let out = in_parallel_then_alone(&items, |&i| {
            let n = tries[i].fetch_add(1, Ordering::SeqCst);
            if i % 2 == 1 && n == 0 {
                Err(refused(600, 600))
            } else {
                Ok(10 * i)
            }
        })
        .unwrap();
        assert_eq!(out, vec![0, 10, 20, 30, 40, 50]);
        let counts: Vec<usize> = tries.iter().map(|t| t.load(Ordering::SeqCst)).collect();
        assert_eq!(counts, vec![1, 2, 1, 2, 1, 2]);
        let e = in_parallel_then_alone(&items, |&i| {
            if i == 3 {
                Err(refused(600, 1200))
            } else {
                Ok(i)
            }
        })
        .unwrap_err();
        assert!(!e.is_crowded_out());
    }
}
