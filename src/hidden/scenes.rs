//! The grasp without and with the feature as two full scenes on any rung of the fidelity ladder.
//!
//! The cells' unit responses ([`super::cells`]) superpose, so they are the linear plate's. The
//! default grasp puts a few newtons on the die, where the linear plate's membrane error is tens of
//! percent: here each cell's pressure is one rectangle of a [`SceneLoad::Patches`] load and both
//! scenes are solved by [`evaluate_many`](crate::sensor::evaluate_many) on the rung asked for (auto climbs to the
//! large-deflection plate where the linear one misses the tolerance), each with its own error
//! (discretisation + model), and compared with the superposition.
//!
//! [`cells_answers`] is the batch underneath: any cell-pressure fields as patches scenes in one
//! [`evaluate_many`](crate::sensor::evaluate_many) call. On the linear plate each answer is, by linearity, the sum of its
//! cells' unit responses on the same mesh (exactly, when the mesh is the same): the vessel's two
//! fields ([`super::vessel`]) and the through-sensor background and feature when neither the
//! inverse nor the map needs the cells one by one.

use serde::Serialize;

use crate::process::{Limits, PressurePatch, RegionUm, Scene, SceneLoad};
use crate::sensor::{
    evaluate_many_with, Accuracy, ErrorParts, MeshOptions, ModelKind, SceneReport, SensorGeometry,
};

use super::cells::CellGrid;
use super::HiddenError;

/// One grasp solved as a full scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneAnswer {
    /// The rung that answered, its mesh and why.
    pub rung: ModelKind,
    pub levels: usize,
    pub dofs: usize,
    pub reason: String,
    /// The nine voltages (mV) in the geometry's electrode order.
    pub voltages_mv: Vec<f64>,
    /// The answer's error (worst over its quantities, relative): discretisation and model.
    pub error: ErrorParts,
    pub converged: bool,
    pub max_deflection_um: f64,
    /// This answer minus the linear superposition of the cells (mV), per electrode (empty when
    /// no superposition was compared: [`cells_answers`]).
    pub minus_superposition_mv: Vec<f64>,
}

/// The background and the with-feature grasp as full scenes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FullScenes {
    /// The rung asked for (`--model`).
    pub model: &'static str,
    pub background: SceneAnswer,
    pub feature: SceneAnswer,
}

impl FullScenes {
    /// The feature's voltage difference on the full scenes (mV).
    pub fn difference_mv(&self) -> Vec<f64> {
        self.feature
            .voltages_mv
            .iter()
            .zip(&self.background.voltages_mv)
            .map(|(a, b)| a - b)
            .collect()
    }
}

/// The cells' pressures (Pa) as one patches scene: force = p A per cell.
pub fn cells_scene(name: &str, grid: &CellGrid, cell_pa: &[f64]) -> Scene {
    let a = grid.area_m2();
    Scene {
        name: name.into(),
        load: SceneLoad::Patches {
            patches: (0..grid.len())
                .map(|k| {
                    let (x0_um, y0_um, x1_um, y1_um) = grid.rect(k);
                    PressurePatch {
                        region: RegionUm {
                            x0_um,
                            y0_um,
                            x1_um,
                            y1_um,
                        },
                        force_n: cell_pa[k] * a,
                    }
                })
                .collect(),
        },
        limits: Limits::default(),
    }
}

/// One [`SceneAnswer`] per field (`(name, Pa per cell of grid)`), all fields as patches scenes of
/// one [`evaluate_many_with`] batch on `acc`'s rung and `mesh` (one factorisation per mesh level
/// on the linear plate); `minus_superposition_mv` is left empty.
#[track_caller]
pub fn cells_answers(
    g: &SensorGeometry,
    grid: &CellGrid,
    fields: &[(&str, &[f64])],
    acc: Accuracy,
    mesh: MeshOptions,
) -> Result<Vec<SceneAnswer>, HiddenError> {
    assert!(
        fields.iter().all(|f| f.1.len() == grid.len()),
        "one pressure per cell"
    );
    let scenes: Vec<Scene> = fields
        .iter()
        .map(|(name, p)| cells_scene(name, grid, p))
        .collect();
    let reports = evaluate_many_with(g, &scenes, acc, mesh)?;
    Ok(reports.iter().map(|r| answer(g, r)).collect())
}

/// The nine voltages of `r` in the geometry's electrode order, and its rung and error.
fn answer(g: &SensorGeometry, r: &SceneReport) -> SceneAnswer {
    let voltages_mv: Vec<f64> = g
        .electrodes
        .iter()
        .map(|n| {
            r.electrodes
                .iter()
                .find(|e| e.name == n.name)
                .map_or(0.0, |e| e.voltage_mv)
        })
        .collect();
    SceneAnswer {
        rung: r.model.kind,
        levels: r.model.levels,
        dofs: r.model.dofs,
        reason: r.model.reason.clone(),
        minus_superposition_mv: Vec::new(),
        voltages_mv,
        error: r.error.clone(),
        converged: r.converged,
        max_deflection_um: r.max_deflection_um,
    }
}

/// Solves the background `p0` and the background plus `dp` (Pa per cell of `grid`) on `acc`'s
/// rung; `superposed_mv` are the linear superposition's (background, with feature) voltages.
#[track_caller]
pub fn full_scenes(
    g: &SensorGeometry,
    grid: &CellGrid,
    p0: &[f64],
    dp: &[f64],
    superposed_mv: (&[f64], &[f64]),
    acc: Accuracy,
) -> Result<FullScenes, HiddenError> {
    assert!(
        p0.len() == grid.len() && dp.len() == grid.len(),
        "one pressure per cell"
    );
    let with: Vec<f64> = p0.iter().zip(dp).map(|(a, b)| a + b).collect();
    let fields = [("tissue-background", p0), ("tissue-feature", &with[..])];
    let mut answers = cells_answers(g, grid, &fields, acc, MeshOptions::READINGS)?.into_iter();
    let mut compared = |lin: &[f64]| {
        let mut a = answers.next().expect("one answer per field");
        a.minus_superposition_mv = a.voltages_mv.iter().zip(lin).map(|(x, y)| x - y).collect();
        a
    };
    let background = compared(superposed_mv.0);
    let feature = compared(superposed_mv.1);
    Ok(FullScenes {
        model: acc.model.as_str(),
        background,
        feature,
    })
}
