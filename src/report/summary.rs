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
    /// Tool, process file name and SHA-256, `--set` overrides.
    #[serde(flatten)]
    pub origin: super::Origin,
    /// How the declared scenes were solved (model rung, tolerance, levels, in-plane condition);
    /// None when FE was skipped.
    pub fe_accuracy: Option<crate::sensor::Accuracy>,
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
pub fn summary(built: &Built, files: &[(String, Vec<u8>)]) -> BuildSummary {
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
        origin: built.traveler.origin.clone(),
        fe_accuracy: built.traveler.fe_accuracy,
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
