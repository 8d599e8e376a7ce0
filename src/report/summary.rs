//! `build.json`: the machine-readable summary of a build. Everything in it is deterministic: the
//! same input gives the same bytes (wall times are printed by `tactfab build`, never stored).

use serde::Serialize;

use crate::finding::Finding;

use super::build::Built;
use super::fe::FeSummary;
use super::inventory::{sha256_hex, Inventory};

/// One file written by the build.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FileEntry {
    pub name: String,
    pub bytes: usize,
    pub sha256: String,
}

/// The summary. Field names are a stable contract.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BuildSummary {
    pub device: String,
    pub revision: String,
    /// The process file's name (not its path, which depends on where the build ran from).
    pub process_file: String,
    /// SHA-256 of the process file's bytes.
    pub process_sha256: String,
    pub passed: bool,
    /// Why it failed, one line each (etch-plan errors, DRC, FE limits).
    pub failures: Vec<String>,
    pub checks: Vec<Finding>,
    pub drc_passed: bool,
    pub drc_violations: usize,
    pub drc_failing: usize,
    pub masks: Inventory,
    pub plate_thickness_um: f64,
    pub fe: Option<FeSummary>,
    /// Every other file of the build, sorted by name.
    pub files: Vec<FileEntry>,
}

/// The summary of `built` whose other files are `files`.
pub fn summary(
    built: &Built,
    process_file: &str,
    process_sha256: &str,
    files: &[(String, Vec<u8>)],
) -> BuildSummary {
    let failures = built.failures();
    let mut entries: Vec<FileEntry> = files
        .iter()
        .map(|(n, b)| FileEntry {
            name: n.clone(),
            bytes: b.len(),
            sha256: sha256_hex(b),
        })
        .collect();
    entries.sort_by(|a, b| a.name.cmp(&b.name));
    BuildSummary {
        device: built.set.device.clone(),
        revision: built.set.revision.clone(),
        process_file: process_file.to_string(),
        process_sha256: process_sha256.to_string(),
        passed: failures.is_empty(),
        failures,
        checks: built.traveler.checks.clone(),
        drc_passed: built.drc.passed(),
        drc_violations: built.drc.violations.len(),
        drc_failing: built.drc.failing(),
        masks: built.inventory.clone(),
        plate_thickness_um: built.plan.plate_thickness_um,
        fe: built.fe.clone(),
        files: entries,
    }
}
