//! The die face in cells and the nine voltages per pascal on each (unit responses).
//!
//! One scene per cell (a uniform 1 N pressure over it, [`SceneLoad::Pressure`]), all solved by
//! [`evaluate_many_with`] on the linear plate and [`MeshOptions::READINGS`] (the voltages need no
//! tooth-base station lines): one factorisation per mesh level and one multi-column solve; a
//! cell over a support goes straight into it (thickness mode), as any load does. A pressure
//! field constant on each cell then reads V_i = sum_c p_c A_c (V_i per N)_c: exact for
//! the linear plate, so the field's own discretisation is the cells' (midpoint of a 4 x 4
//! sub-sample per cell, [`super::field`]).

use serde::Serialize;

use crate::process::{Limits, RegionUm, Scene, SceneLoad};
use crate::sensor::{
    evaluate_many_with, Accuracy, MeshOptions, ModelChoice, ModelKind, SensorGeometry,
};

use super::HiddenError;

/// Most cells \[choice\]: 5,000 scenes in one batch (a 0.25 mm grid on the 30 x 15 mm die is
/// 7,200: too many for the solution store of [`crate::sensor::MAX_SOLUTION_VALUES`] at level 3).
pub const MAX_CELLS: usize = 5_000;

/// A regular grid of cells over the die face, x along the jaw (the die length), y across.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CellGrid {
    pub nx: usize,
    pub ny: usize,
    pub length_um: f64,
    pub width_um: f64,
}

impl CellGrid {
    /// Cells no larger than `cell_um` on a side over the die of `g`.
    pub fn new(g: &SensorGeometry, cell_um: f64) -> Result<Self, HiddenError> {
        if !(cell_um > 0.0 && cell_um.is_finite()) {
            return Err(HiddenError::Input {
                problem: format!("cell size {cell_um} um"),
                hint: "a positive cell size, e.g. 1000 um",
            });
        }
        let nx = (g.length_um / cell_um).ceil().max(1.0);
        let ny = (g.width_um / cell_um).ceil().max(1.0);
        if nx * ny > MAX_CELLS as f64 {
            return Err(HiddenError::Input {
                problem: format!(
                    "{nx} x {ny} cells of {cell_um} um on the {} x {} um die",
                    g.length_um, g.width_um
                ),
                hint: "at most 5,000 cells: use larger cells",
            });
        }
        Ok(CellGrid {
            nx: nx as usize,
            ny: ny as usize,
            length_um: g.length_um,
            width_um: g.width_um,
        })
    }

    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Cell k = j nx + i as (x0, y0, x1, y1) in um.
    pub fn rect(&self, k: usize) -> (f64, f64, f64, f64) {
        let (i, j) = ((k % self.nx) as f64, (k / self.nx) as f64);
        let (hx, hy) = self.size_um();
        (i * hx, j * hy, (i + 1.0) * hx, (j + 1.0) * hy)
    }

    /// Cell sides (um).
    pub fn size_um(&self) -> (f64, f64) {
        (
            self.length_um / self.nx as f64,
            self.width_um / self.ny as f64,
        )
    }

    pub fn area_m2(&self) -> f64 {
        let (hx, hy) = self.size_um();
        hx * hy * 1e-12
    }
}

/// The nine voltages per pascal on each cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnitResponses {
    pub grid: CellGrid,
    pub electrodes: Vec<String>,
    /// mV per Pa, cell-major: `mv_per_pa[k * electrodes.len() + e]`.
    #[serde(skip)]
    pub mv_per_pa: Vec<f64>,
    /// The plate mesh of the answer: levels, dofs, and the worst estimated discretisation error
    /// of a cell's charges (None before three levels).
    pub levels: usize,
    pub dofs: usize,
    pub discretisation: Option<f64>,
    /// The worst model error the linear plate reports for a cell at 1 N (its membrane
    /// stiffening, which a superposition cannot carry).
    pub model_error_1n: Option<f64>,
}

/// Unit responses of every cell of `grid` on the linear plate to `acc.tol_rel` within
/// `acc.max_levels` (the rung is forced to the linear plate: superposition needs it).
pub fn unit_responses(
    g: &SensorGeometry,
    grid: CellGrid,
    acc: Accuracy,
) -> Result<UnitResponses, HiddenError> {
    let scenes: Vec<Scene> = (0..grid.len())
        .map(|k| {
            let (x0_um, y0_um, x1_um, y1_um) = grid.rect(k);
            Scene {
                name: format!("cell-{k}"),
                load: SceneLoad::Pressure {
                    force_n: 1.0,
                    region: Some(RegionUm {
                        x0_um,
                        y0_um,
                        x1_um,
                        y1_um,
                    }),
                },
                limits: Limits::default(),
            }
        })
        .collect();
    let reports = evaluate_many_with(
        g,
        &scenes,
        acc.with_model(ModelChoice::Plate),
        MeshOptions::READINGS,
    )?;
    let electrodes: Vec<String> = g.electrodes.iter().map(|e| e.name.clone()).collect();
    let a = grid.area_m2();
    let mut mv_per_pa = Vec::with_capacity(grid.len() * electrodes.len());
    let (mut levels, mut dofs) = (1, 0);
    let (mut disc, mut model): (Option<f64>, Option<f64>) = (Some(0.0), Some(0.0));
    let worse = |a: Option<f64>, b: Option<f64>| a.zip(b).map(|(a, b)| a.max(b));
    for r in &reports {
        // Each reading in the geometry's electrode order.
        for name in &electrodes {
            let v = r
                .electrodes
                .iter()
                .find(|e| &e.name == name)
                .map_or(0.0, |e| e.voltage_mv);
            mv_per_pa.push(v * a);
        }
        if r.model.kind == ModelKind::Plate {
            levels = levels.max(r.model.levels);
            dofs = dofs.max(r.model.dofs);
            disc = worse(disc, r.error.discretisation);
            model = worse(model, r.error.model);
        }
    }
    Ok(UnitResponses {
        grid,
        electrodes,
        mv_per_pa,
        levels,
        dofs,
        discretisation: disc,
        model_error_1n: model,
    })
}

impl UnitResponses {
    /// The nine voltages (mV) of a pressure constant on each cell (`cell_pa[k]`, Pa).
    #[track_caller]
    pub fn voltages_mv(&self, cell_pa: &[f64]) -> Vec<f64> {
        assert_eq!(cell_pa.len(), self.grid.len(), "one pressure per cell");
        let ne = self.electrodes.len();
        let mut v = vec![0.0; ne];
        for (k, &p) in cell_pa.iter().enumerate() {
            if p != 0.0 {
                for (e, ve) in v.iter_mut().enumerate() {
                    *ve += p * self.mv_per_pa[k * ne + e];
                }
            }
        }
        v
    }
}
