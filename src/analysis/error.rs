//! Errors of the analyses; each variant says how to fix the input.

use thiserror::Error;

use crate::fe::FeError;
use crate::sensor::SensorError;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum AnalysisError {
    #[error("finite-element solve failed: {0}")]
    Fe(#[from] FeError),
    #[error("{0}")]
    Sensor(#[from] SensorError),
    #[error("fit: {reason}\n  hint: use at least degree + 1 distinct samples and a degree >= 0")]
    Fit { reason: String },
    #[error(
        "voltages: expected {expected} values in the electrode order {names}, got {got}\n  \
         hint: --voltages takes one value per electrode, comma-separated"
    )]
    VoltageCount {
        expected: usize,
        got: usize,
        names: String,
    },
    #[error(
        "{reason}\n  hint: a smaller contact radius (--contact-radius-mm) or a \
         finer grid (--x-step-mm, --y-step-mm)"
    )]
    Plan { reason: String },
    #[error(
        "the {study} study loads the plate with a probe, which the strip (--model {model}) \
         cannot carry\n  hint: use --model plate, large-deflection or auto"
    )]
    NeedsPlate {
        study: &'static str,
        model: &'static str,
    },
    #[error("calibration: {reason}\n  hint: regenerate it with `tactfab calibrate FILE -o DIR`")]
    Calibration { reason: String },
    #[error(
        "the support voltages sum to zero: there is no load to locate\n  hint: give the nine \
         voltages a loaded sensor reads (mV, in the electrode order of the model)"
    )]
    NoLoad,
    #[error("the sensor has no electrode `{name}` (known: {known})")]
    UnknownElectrode { name: String, known: String },
}
