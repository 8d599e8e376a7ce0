//! The fidelity ladder: which model answers a scene, and how far each reported quantity is from
//! the truth (its discretisation error plus the model error of the rung that gave it).

use serde::Serialize;

use crate::fe::ThreeMesh;

use super::geometry::{ElectrodeSide, SensorGeometry};
use super::mesh_lines::level_ratios;

/// The rung a caller asks for (`--model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelChoice {
    /// The cheapest rung whose estimated total error is under the tolerance: the strip where it
    /// qualifies, else the linear plate when its model error (its difference from the
    /// large-deflection plate on the coarsest mesh) plus its discretisation error is under the
    /// tolerance, else the large-deflection plate.
    Auto,
    /// The fixed-fixed strip (paper 001), for line loads across a plate without teeth.
    Beam,
    /// The linear Kirchhoff plate, with its model error estimated and reported.
    Plate,
    /// The von Karman (large-deflection) plate.
    LargeDeflection,
    /// The 3D solid (`fe --model solid`, [`crate::sensor::solid`]): linear, the etched shape, the
    /// films and the base; it measures the plate rungs' model error.
    Solid,
}

impl ModelChoice {
    /// The spelling of `--model`.
    pub fn as_str(self) -> &'static str {
        match self {
            ModelChoice::Auto => "auto",
            ModelChoice::Beam => "beam",
            ModelChoice::Plate => "plate",
            ModelChoice::LargeDeflection => "large-deflection",
            ModelChoice::Solid => "solid",
        }
    }
}

/// An error split into its parts, each relative to the quantity's scale (see [`QuantityError`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorParts {
    /// Three-mesh (Richardson) estimate on the finest level; None before three levels.
    pub discretisation: Option<f64>,
    /// Model error of the rung that answered; None where no finer rung was compared.
    pub model: Option<f64>,
    /// discretisation + model; None when the discretisation part is unknown.
    pub total: Option<f64>,
}

impl ErrorParts {
    pub fn new(discretisation: Option<f64>, model: Option<f64>) -> Self {
        ErrorParts {
            discretisation,
            model,
            total: discretisation.map(|d| d + model.unwrap_or(0.0)),
        }
    }

    /// Met the tolerance: a known total under it.
    pub fn met(&self, tol: f64) -> bool {
        self.total.is_some_and(|t| t < tol)
    }
}

/// One reported quantity with its error. Errors are relative to the largest magnitude of the
/// quantity's kind in the scene (deflection; middle-electrode charges; support-electrode
/// charges; reactions: the applied force), so a charge near zero on a quiet electrode is not
/// held to a relative tolerance of its own.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityError {
    pub name: String,
    pub value: f64,
    pub unit: &'static str,
    pub error: ErrorParts,
    pub converged: bool,
}

/// What the level loop records per level, in this order: the deflection at the load, each
/// electrode's charge, then the two support reactions.
pub(super) fn quantity_names(g: &SensorGeometry) -> Vec<(String, &'static str, f64)> {
    let mut out = vec![("deflection_at_load".to_string(), "um", 1e6)];
    out.extend(
        g.electrodes
            .iter()
            .map(|e| (format!("charge_{}", e.name), "pC", 1.0)),
    );
    out.push(("reaction_support1".into(), "N", 1.0));
    out.push(("reaction_support2".into(), "N", 1.0));
    out.push((STRESS_AVERAGED.into(), "MPa", 1e-6));
    if super::edge_section::applies(g) {
        out.push((TOOTH_BASE_STRESS.into(), "MPa", 1e-6));
    }
    out.push((STRESS_PEAK.into(), "MPa", 1e-6));
    out
}

/// The teeth's base-edge stress at the critical distance, from the plate's resultants there and
/// the design's edge section ([`super::edge_section`]): where the plate's safety factor is
/// judged beside the averaged stress.
pub const TOOTH_BASE_STRESS: &str = "tooth_base_stress";

/// The largest principal stress averaged over a square a plate thickness wide: converges, and
/// the safety factor is judged on it.
pub const STRESS_AVERAGED: &str = "max_stress_averaged";
/// The largest point stress of the plate model: singular at re-entrant corners and point-like
/// loads, reported with its convergence but never counted as converged.
pub const STRESS_PEAK: &str = "max_stress_peak";

/// Kind of entry `i` of a history row of `n` entries (the normalisation group): 0 deflection, 1
/// middle charges, 2 support charges, 3 reactions, 4 averaged stress, 5 tooth-base stress (where
/// [`quantity_names`] has it, between the two), 6 peak stress (last).
fn kind(g: &SensorGeometry, i: usize, n: usize) -> usize {
    let n_el = g.electrodes.len();
    if i == 0 {
        0
    } else if i <= n_el {
        match g.electrodes[i - 1].side {
            ElectrodeSide::Middle => 1,
            _ => 2,
        }
    } else if i <= n_el + 2 {
        3
    } else if i == n_el + 3 {
        4
    } else if i + 1 == n {
        6
    } else {
        5
    }
}

/// Per-kind scale: the largest magnitude of the kind on `values`; the reactions' scale is the
/// applied force.
fn scales(g: &SensorGeometry, values: &[f64], force_n: f64) -> [f64; 7] {
    let mut scale = [0f64; 7];
    for (i, v) in values.iter().enumerate() {
        let k = kind(g, i, values.len());
        scale[k] = scale[k].max(v.abs());
    }
    scale[3] = scale[3].max(force_n.abs());
    scale
}

/// Relative discretisation error of every quantity from the last three levels of `history`
/// (None before three levels), and the observed order of the deflection.
pub(super) fn discretisation(
    g: &SensorGeometry,
    history: &[Vec<f64>],
    force_n: f64,
) -> (Vec<Option<f64>>, Option<f64>) {
    let n = history.len();
    let Some(f1) = history.last() else {
        return (Vec::new(), None);
    };
    if n < 3 {
        return (vec![None; f1.len()], None);
    }
    let (f3, f2) = (&history[n - 3], &history[n - 2]);
    let (r32, r21) = level_ratios(n - 1);
    let scale = scales(g, f1, force_n);
    let errs = (0..f1.len())
        .map(|i| {
            let s = scale[kind(g, i, f1.len())];
            Some(if s > 0.0 {
                ThreeMesh::new(f3[i], f2[i], f1[i], r32, r21).fine_error() / s
            } else {
                0.0
            })
        })
        .collect();
    let order = ThreeMesh::new(f3[0], f2[0], f1[0], r32, r21)
        .richardson
        .observed_order;
    (errs, order)
}

/// Model error of the linear plate per quantity: its difference from the large-deflection plate
/// on the same (coarsest) mesh, normalised as [`discretisation`].
pub(super) fn linear_model_error(
    g: &SensorGeometry,
    linear: &[f64],
    nonlinear: &[f64],
    force_n: f64,
) -> Vec<f64> {
    let scale = scales(g, nonlinear, force_n);
    linear
        .iter()
        .zip(nonlinear)
        .enumerate()
        .map(|(i, (a, b))| {
            let s = scale[kind(g, i, nonlinear.len())];
            if s > 0.0 {
                (a - b).abs() / s
            } else {
                0.0
            }
        })
        .collect()
}

/// The quantity table of a scene from the finest level's values and the error parts.
pub(super) fn quantities(
    g: &SensorGeometry,
    values: &[f64],
    disc: &[Option<f64>],
    model: Option<&[f64]>,
    tol: f64,
) -> Vec<QuantityError> {
    quantity_names(g)
        .into_iter()
        .zip(values)
        .enumerate()
        .map(|(i, ((name, unit, factor), v))| {
            let error = ErrorParts::new(disc.get(i).copied().flatten(), model.map(|m| m[i]));
            QuantityError {
                converged: error.met(tol),
                name,
                value: v * factor,
                unit,
                error,
            }
        })
        .collect()
}

/// The worst of each part over the quantities that count (all but the singular peak stress):
/// the scene's headline error.
pub(super) fn worst(q: &[QuantityError]) -> ErrorParts {
    let q: Vec<QuantityError> = q
        .iter()
        .filter(|x| x.name != STRESS_PEAK)
        .cloned()
        .collect();
    let q = q.as_slice();
    let max = |f: &dyn Fn(&ErrorParts) -> Option<f64>| -> Option<f64> {
        q.iter()
            .map(|x| f(&x.error))
            .try_fold(0f64, |m, v| v.map(|v| m.max(v)))
    };
    let model = if q.iter().any(|x| x.error.model.is_some()) {
        q.iter().filter_map(|x| x.error.model).reduce(f64::max)
    } else {
        None
    };
    ErrorParts {
        discretisation: max(&|e| e.discretisation),
        model,
        total: max(&|e| e.total),
    }
}
