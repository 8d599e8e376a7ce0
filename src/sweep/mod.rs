//! Design sweep (paper 001, sec. 4.1, Fig. 15): 15,000 plate designs (length x width x thickness),
//! the paper's response of each under a 4 N centre load (deflection, elongation across the span,
//! maximum stress), and the family that matches the prototype's elongation within a tolerance.
//!
//! - [`design`]: one design, its plate model and response, the beam limit.
//! - [`run`]: parallel runs on a shared symbolic factorisation, the matching rule, error estimates.
//! - [`shard`]: `--shard i/n` ranges, the CSV format, the merge step.
//! - [`plot`]: the family scatter (SVG).

pub mod design;
pub mod plot;
pub mod run;
pub mod shard;

use std::path::PathBuf;
use thiserror::Error;

pub use design::{Design, DesignModel, DesignSolver, Grid, MeshSpec, Range, Response};
pub use run::{estimate_error, run_range, DesignError, Matching, Mode, Row};
pub use shard::{merge_dir, Merged, Shard};

/// Sweep errors; each carries a hint.
#[derive(Debug, Error)]
pub enum SweepError {
    #[error(
        "the sweep grid holds {} designs, above the limit of {}\n  hint: {hint}",
        designs.map_or_else(|| "more than 2^64".to_string(), |n| n.to_string()),
        design::MAX_DESIGNS
    )]
    TooLarge {
        designs: Option<usize>,
        hint: &'static str,
    },
    #[error("bad shard '{text}'\n  hint: {hint}")]
    BadShard { text: String, hint: &'static str },
    #[error("merge failed: {detail}\n  hint: {hint}")]
    Merge { detail: String, hint: &'static str },
    #[error("{}: {cause}\n  hint: check that the directory exists and is readable", path.display())]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error(transparent)]
    Fe(#[from] crate::fe::FeError),
}
