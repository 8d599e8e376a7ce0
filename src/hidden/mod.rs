//! Hidden features in grasped tissue, through the sensor (issue 17, items 2-3; paper 002 sec.
//! V.B, Figs. 8-10): the contact pressure of the tissue slab of [`crate::softness::inclusion`]
//! loads the plate, the nine electrodes read it, and the inverse finds the feature.
//!
//! - [`cells`]: the die face cut into rectangular cells, and each cell's unit response (the nine
//!   voltages per pascal on it) from one batched linear-plate solve: the plate is linear, so any
//!   piecewise-constant pressure is the sum of its cells, and moving the feature costs a dot
//!   product, not a solve.
//! - [`field`]: how the slab's 2-D section becomes a pressure over the 2-D face (a \[choice\],
//!   see there): the background P0(x) along the jaw, and the feature's disturbance
//!   (P / P0 - 1) rotated about its centre (a spherical lump) or extruded across the jaw (a
//!   cylinder).
//! - [`locate`]: from the nine voltages with the feature minus the background, the feature's
//!   position by least squares over candidate centres, refined continuously, its kind by the
//!   sign of the fitted amplitude, and "none" below a matched-filter threshold.
//! - [`detect`]: the smallest detectable lump over size x depth at a stated noise level.
//! - [`scenes`]: the grasp without and with the feature as two full scenes on any rung of the
//!   ladder (the large-deflection plate at the default grasp's force), against the
//!   superposition.
//! - [`summary`]: the traveler's section: the default lump and void through the sensor, cheaply.

pub mod cells;
pub mod detect;
pub mod face3d;
pub mod field;
pub mod locate;
pub mod scenes;
pub mod study;
pub mod summary;
pub mod vessel;

use thiserror::Error;

use crate::sensor::SensorError;
use crate::softness::SoftnessError;

/// Why a hidden-feature study has no answer.
#[derive(Debug, Error)]
pub enum HiddenError {
    #[error("{0}")]
    Sensor(#[from] SensorError),
    #[error("{0}")]
    Slab(#[from] SoftnessError),
    #[error("{problem}\n  hint: {hint}")]
    Input { problem: String, hint: &'static str },
}

#[cfg(test)]
mod tests;
