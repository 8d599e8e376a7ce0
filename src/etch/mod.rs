//! The etch plan: every number the process implies, and the checks of what does not add up.
//!
//! Inputs come only from the validated [`Process`]; the plan is plain data (serialisable as the
//! stable JSON of `tactfab etch --json`).

pub mod compensation;
pub mod geometry;
pub mod limits;
pub mod oxidation;
mod plan;
pub mod rate;
pub mod resist;
pub mod sim;

#[cfg(test)]
mod tests_bars;

pub use compensation::{design as compensation_design, CompensationDesign};
pub use plan::*;

use crate::process::Process;

/// Computes the etch plan of a validated process.
pub fn plan(process: &Process) -> EtchPlan {
    plan::build(process)
}
