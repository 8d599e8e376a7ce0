//! Where an output came from: the tool, the process file's bytes and the `--set` overrides, so
//! that two outputs can be told apart and a calibration is never applied to a design it was not
//! made for.

use serde::{Deserialize, Serialize};

/// `tactfab <version>`, as every output names the tool.
pub const TOOL: &str = concat!("tactfab ", env!("CARGO_PKG_VERSION"));

/// The identity of the design behind an output.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Origin {
    /// [`TOOL`] when written.
    pub tool: String,
    /// The process file's name (not its path, which depends on where the command ran from).
    pub process_file: String,
    /// SHA-256 of the process file's bytes.
    pub process_sha256: String,
    /// `--set path=value` overrides, as given and in order.
    pub overrides: Vec<String>,
}

impl Origin {
    /// The origin of an output of this tool from `process_file` (name and SHA-256) with the
    /// `overrides` as the loader applied them (canonical path, argument).
    pub fn new(process_file: &str, process_sha256: &str, overrides: &[(String, String)]) -> Self {
        Origin {
            tool: TOOL.to_string(),
            process_file: process_file.to_string(),
            process_sha256: process_sha256.to_string(),
            overrides: overrides.iter().map(|(_, arg)| arg.clone()).collect(),
        }
    }

    /// Why `self` (an output's origin) does not describe the same design as `now`: other process
    /// bytes or other overrides. None when it does (the tool version and file name may differ).
    ///
    /// ```
    /// use tactfab::report::Origin;
    /// let a = Origin::new("a.yaml", "ab12", &[]);
    /// assert!(a.design_mismatch(&Origin::new("b.yaml", "ab12", &[])).is_none());
    /// let set = [("geometry.plate_thickness_um".to_string(), "geometry.plate_thickness_um=80".to_string())];
    /// assert!(a.design_mismatch(&Origin::new("a.yaml", "ab12", &set)).is_some());
    /// ```
    pub fn design_mismatch(&self, now: &Origin) -> Option<String> {
        let sets = |o: &Origin| {
            if o.overrides.is_empty() {
                "no --set".to_string()
            } else {
                o.overrides
                    .iter()
                    .map(|s| format!("--set {s}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            }
        };
        if self.process_sha256 != now.process_sha256 {
            Some(format!(
                "it was made from {} with SHA-256 {}, this run's {} has SHA-256 {}",
                self.process_file, self.process_sha256, now.process_file, now.process_sha256
            ))
        } else if self.overrides != now.overrides {
            Some(format!(
                "it was made with {}, this run has {}",
                sets(self),
                sets(now)
            ))
        } else {
            None
        }
    }
}
