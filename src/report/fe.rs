//! The FE sensitivity summary of the declared scenes: the deterministic part of each
//! [`SceneReport`] with its limits checked, and its plots. Solve times stay out: the traveler and
//! `build.json` must be byte-identical for the same input.

use serde::Serialize;

use crate::finding::Finding;
use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};
use crate::process::{Scene, SceneLoad};
use crate::sensor::SceneReport;

use super::limits::{check_limits, LimitCheck};

/// One electrode's reading.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeElectrode {
    pub name: String,
    pub charge_pc: f64,
    pub voltage_mv: f64,
}

/// One scene: load, model, results and limits (no timings).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeScene {
    pub name: String,
    pub load: String,
    pub force_n: f64,
    /// `beam`, `plate`, `large_deflection_plate` or `direct`.
    pub model: crate::sensor::ModelKind,
    pub elements: usize,
    pub dofs: usize,
    pub levels: usize,
    pub error_estimate: Option<f64>,
    /// The worst discretisation, model and total error over the scene's quantities.
    pub error: crate::sensor::ErrorParts,
    /// Why this rung answered.
    pub rung_reason: String,
    pub converged: bool,
    /// The load of the scene's pattern at which the plate reaches the channel floor, and the
    /// gap under the plate.
    pub touch_down_load_n: Option<f64>,
    pub gap_um: Option<f64>,
    pub deflection_at_load_um: f64,
    pub max_deflection_um: f64,
    pub max_stress_mpa: f64,
    /// Which stress the safety factor is judged on.
    pub stress_from: crate::sensor::StressFrom,
    pub safety_factor: f64,
    pub max_permissible_load_n: f64,
    pub sensitivity_mv_per_n: f64,
    pub most_sensitive: String,
    pub electrodes: Vec<FeElectrode>,
    pub limits: Vec<LimitCheck>,
    pub warnings: Vec<Finding>,
    /// (largest element um, deflection at the load per newton um/N) per mesh level: the
    /// convergence the error estimate is made from.
    pub deflection_by_level: Vec<(f64, f64)>,
}

impl FeScene {
    pub fn passed(&self) -> bool {
        self.limits.iter().all(|l| l.passed)
    }
}

/// Every declared scene, solved to `tol_rel`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeSummary {
    pub tol_rel: f64,
    pub max_levels: usize,
    /// A scene whose estimate did not reach `tol_rel` fails the build (unless
    /// `--allow-unconverged`).
    pub require_convergence: bool,
    pub scenes: Vec<FeScene>,
    /// Why the declared scenes were not solved (the etch plan has errors: the device it
    /// describes cannot be made, so no reading of it is a pass).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
    /// The plate's lowest natural frequencies against the 5 Hz test and the 1 Hz pulse (is
    /// quasi-static right?); None when the scenes were not solved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modes: Option<crate::sensor::PlateModes>,
    /// The edge stiffness the plate rungs stood on (`support_model`); None when the scenes were
    /// not solved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub supports: Option<crate::sensor::support_stiffness::SupportStiffness>,
    /// Paper 002's default lump and void through the sensor (hidden features in grasped
    /// tissue); None when the scenes were not solved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tissue: Option<crate::hidden::summary::TissueSummary>,
}

impl FeSummary {
    /// Failing limits, and scenes that did not reach the tolerance, as `scene `name`: what`
    /// lines: an answer of unknown accuracy is never a pass.
    pub fn failures(&self) -> Vec<String> {
        let mut out: Vec<String> = self.skipped.iter().map(|s| format!("FE: {s}")).collect();
        for s in &self.scenes {
            if self.require_convergence && !s.converged {
                out.push(format!(
                    "scene `{}`: not converged: estimated error {} is not under the tolerance {} \
                     after {} mesh levels (raise --max-levels or --tol, or pass \
                     --allow-unconverged)",
                    s.name,
                    s.error_estimate
                        .map_or_else(|| "unknown".to_string(), |e| format!("{e:.2e}")),
                    self.tol_rel,
                    s.levels
                ));
            }
            out.extend(
                s.limits
                    .iter()
                    .filter(|l| !l.passed)
                    .map(|l| format!("scene `{}`: {l}", s.name)),
            );
            out.extend(
                s.warnings
                    .iter()
                    .filter(|w| w.severity == crate::finding::Severity::Error)
                    .map(|w| format!("scene `{}`: {}", s.name, w.message)),
            );
        }
        out
    }
}

/// The load in words, die coordinates in mm.
pub fn describe_load(load: &SceneLoad) -> String {
    match load {
        SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => {
            format!(
                "{force_n} N at ({}, {}) mm, contact radius {} mm",
                x_um / 1000.0,
                y_um / 1000.0,
                radius_um / 1000.0
            )
        }
        SceneLoad::Pressure {
            force_n,
            region: None,
        } => format!("{force_n} N uniform pressure over the plate"),
        SceneLoad::Pressure {
            force_n,
            region: Some(r),
        } => format!(
            "{force_n} N uniform pressure over x {}..{} mm, y {}..{} mm",
            r.x0_um / 1000.0,
            r.x1_um / 1000.0,
            r.y0_um / 1000.0,
            r.y1_um / 1000.0
        ),
        SceneLoad::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            force_n,
        } => format!(
            "{force_n} N probe {} x {} mm at ({}, {}) mm, {angle_deg} deg",
            width_um / 1000.0,
            height_um / 1000.0,
            x_um / 1000.0,
            y_um / 1000.0
        ),
        SceneLoad::Line { y_um, force_n } => {
            format!("{force_n} N line load along x at y = {} mm", y_um / 1000.0)
        }
        SceneLoad::Patches { patches } => format!(
            "{} N of pressure over {} patches",
            patches.iter().map(|p| p.force_n).sum::<f64>(),
            patches.len()
        ),
    }
}

/// The summary of `reports`, solved for `scenes` in the same order.
#[track_caller]
pub fn summarise(
    scenes: &[Scene],
    reports: &[SceneReport],
    tol_rel: f64,
    max_levels: usize,
    require_convergence: bool,
) -> FeSummary {
    assert_eq!(scenes.len(), reports.len(), "one report per scene");
    let scenes = scenes
        .iter()
        .zip(reports)
        .map(|(s, r)| FeScene {
            name: r.scene.clone(),
            load: describe_load(&s.load),
            force_n: r.force_n,
            model: r.model.kind,
            elements: r.model.elements,
            dofs: r.model.dofs,
            levels: r.model.levels,
            error_estimate: r.error_estimate,
            error: r.error.clone(),
            rung_reason: r.model.reason.clone(),
            converged: r.converged,
            touch_down_load_n: r.touch_down.as_ref().and_then(|t| t.load_n),
            gap_um: r.touch_down.as_ref().map(|t| t.gap_um),
            deflection_at_load_um: r.deflection_at_load_um,
            max_deflection_um: r.max_deflection_um,
            max_stress_mpa: r.max_stress_mpa,
            stress_from: r.stress_from,
            safety_factor: r.safety_factor,
            max_permissible_load_n: r.max_permissible_load_n,
            sensitivity_mv_per_n: r.sensitivity_mv_per_n,
            most_sensitive: r.most_sensitive.clone(),
            electrodes: r
                .electrodes
                .iter()
                .map(|e| FeElectrode {
                    name: e.name.clone(),
                    charge_pc: e.charge_pc,
                    voltage_mv: e.voltage_mv,
                })
                .collect(),
            limits: check_limits(r, &s.limits),
            warnings: r.warnings.clone(),
            deflection_by_level: r
                .convergence
                .iter()
                .map(|l| (l.max_element_um, l.deflection_at_load_um / r.force_n))
                .collect(),
        })
        .collect();
    FeSummary {
        tol_rel,
        max_levels,
        require_convergence,
        scenes,
        skipped: None,
        modes: None,
        supports: None,
        tissue: None,
    }
}

/// The summary of scenes that were not solved, and why.
pub fn skipped(tol_rel: f64, max_levels: usize, why: String) -> FeSummary {
    FeSummary {
        tol_rel,
        max_levels,
        require_convergence: true,
        scenes: Vec::new(),
        skipped: Some(why),
        modes: None,
        supports: None,
        tissue: None,
    }
}

/// Plots of the summary: voltage per newton by electrode, and deflection per newton by mesh level.
pub fn plots(fe: &FeSummary) -> Vec<(String, String)> {
    let names: Vec<String> = fe
        .scenes
        .first()
        .map(|s| s.electrodes.iter().map(|e| e.name.clone()).collect())
        .unwrap_or_default();
    let volts = XyPlot {
        title: "voltage per newton by electrode".into(),
        x: Axis::linear(format!("electrode 1-{}: {}", names.len(), names.join(" "))),
        y: Axis::linear("V/F (mV/N)"),
        series: fe
            .scenes
            .iter()
            .map(|s| Series {
                name: s.name.clone(),
                points: s
                    .electrodes
                    .iter()
                    .enumerate()
                    .map(|(i, e)| ((i + 1) as f64, e.voltage_mv / s.force_n))
                    .collect(),
                style: Style::LineAndMarkers,
            })
            .collect(),
    };
    let conv = XyPlot {
        title: "deflection at the load per newton by mesh level".into(),
        x: Axis::log("largest element (um)"),
        y: Axis::linear("deflection / F (um/N)"),
        series: fe
            .scenes
            .iter()
            .filter(|s| s.deflection_by_level.len() > 1)
            .map(|s| Series {
                name: s.name.clone(),
                points: s.deflection_by_level.clone(),
                style: Style::LineAndMarkers,
            })
            .collect(),
    };
    let mut out = vec![(volts.title.clone(), xy_svg(&volts, 640, 320))];
    if !conv.series.is_empty() {
        out.push((conv.title.clone(), xy_svg(&conv, 640, 320)));
    }
    out
}
