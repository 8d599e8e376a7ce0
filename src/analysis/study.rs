//! The calibration study of `tactfab calibrate`: the calibration tables, the load inverse built
//! on them, its error on held-out loads and under Gaussian voltage noise, as one call.

use serde::Serialize;

use crate::sensor::SensorGeometry;

use super::calibration::{calibrate, Calibration, CalibrationPlan, SupportGroups};
use super::inverse::{held_out_errors, noise_study, HeldOutError, Locator, NoiseRow};
use super::AnalysisError;

/// The noise part of the study: `trials` noisy copies of each held-out load per sigma, from one
/// seeded stream, at voltages scaled to `force_n`.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseSpec {
    pub sigmas_mv: Vec<f64>,
    pub trials: usize,
    pub seed: u64,
    pub force_n: f64,
}

/// Everything `tactfab calibrate` reports.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationStudy {
    pub calibration: Calibration,
    pub groups: SupportGroups,
    #[serde(skip)]
    pub locator: Locator,
    pub held_out: Vec<HeldOutError>,
    pub noise: Vec<NoiseRow>,
}

/// Calibrates `g` by `plan`, builds the inverse and measures its error.
pub fn calibration_study(
    g: &SensorGeometry,
    plan: &CalibrationPlan,
    noise: &NoiseSpec,
) -> Result<CalibrationStudy, AnalysisError> {
    let calibration = calibrate(g, plan)?;
    let groups = SupportGroups::of(g)?;
    let locator = Locator::new(&calibration, groups.clone())?;
    let held_out = held_out_errors(&locator, &calibration.held_out)?;
    let noise = noise_study(
        &locator,
        &calibration.held_out,
        noise.force_n,
        &noise.sigmas_mv,
        noise.trials,
        noise.seed,
    )?;
    Ok(CalibrationStudy {
        calibration,
        groups,
        locator,
        held_out,
        noise,
    })
}
