//! Calibration tables from the FE model (paper 002, sec. V Figs. 12-13 and sec. VII Figs. 22-26):
//! voltages against force at the centre, the support pair against y across the full width (loads
//! over the supports included), VS1 = V11 + V21 against VS2 = V13 + V23 along x, and a grid of
//! positions at 1 N for the inverse. Every load of the study is one batched FE call.

use std::time::Instant;

use serde::Serialize;

use crate::process::{Limits, Scene, SceneLoad};
use crate::sensor::{
    evaluate_many_with, Accuracy, ElectrodeSide, MeshOptions, ModelChoice, SceneReport,
    SensorGeometry,
};

use super::AnalysisError;

/// Forces of the linearity table (paper 002 Fig. 22 spans 10 mN - 3 N; the issue asks 1 mN - 5 N).
pub const FORCE_TABLE_N: [f64; 8] = [0.001, 0.01, 0.1, 0.5, 1.0, 2.0, 3.0, 5.0];
/// Forces of the held-out loads, none of them a calibration force.
pub const HELD_OUT_FORCES_N: [f64; 4] = [0.05, 0.3, 1.7, 4.2];

/// Where the study loads the sensor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationPlan {
    /// Contact radius of every point load (the FE spreads it over the square of equal area).
    pub radius_um: f64,
    pub force_table_n: Vec<f64>,
    /// y positions at x = length / 2, support to support.
    pub y_sweep_um: Vec<f64>,
    /// x positions at y = width / 2.
    pub x_sweep_um: Vec<f64>,
    /// Inverse grid (1 N): x nodes and y nodes (loads wholly on the plate).
    pub grid_x_um: Vec<f64>,
    pub grid_y_um: Vec<f64>,
    /// Held-out loads (x, y, force): between grid nodes, at forces not calibrated.
    pub held_out: Vec<(f64, f64, f64)>,
    pub accuracy: Accuracy,
}

impl CalibrationPlan {
    /// Sweeps with `x_step_um` along the length and `y_step_um` across the width; the grid uses
    /// the x sweep's nodes and the y sweep's plate nodes plus the first and last positions with
    /// the contact wholly on the plate; `n_held_out` loads sit at cell centres.
    pub fn new(
        g: &SensorGeometry,
        x_step_um: f64,
        y_step_um: f64,
        n_held_out: usize,
        radius_um: f64,
        accuracy: Accuracy,
    ) -> Self {
        let h = contact_half_side_um(radius_um);
        // Contact wholly on the die (a patch over the die edge would lose the part outside).
        let ny = ((g.width_um - 2.0 * h) / y_step_um).round().max(1.0) as usize;
        let y_sweep_um: Vec<f64> = (0..=ny)
            .map(|j| h + (g.width_um - 2.0 * h) * j as f64 / ny as f64)
            .collect();
        // At least two columns: the inverse interpolates between grid lines.
        let nx = (g.length_um / x_step_um).round().max(2.0) as usize;
        // Cell centres, without those whose contact would reach over the die's ends.
        let x_sweep_um: Vec<f64> = (0..nx)
            .map(|i| g.length_um * (i as f64 + 0.5) / nx as f64)
            .filter(|&x| x >= h && x <= g.length_um - h)
            .collect();
        let (lo, hi) = (g.plate_y0_um + h, g.plate_y1_um - h);
        let mut grid_y_um = vec![lo];
        grid_y_um.extend(
            y_sweep_um
                .iter()
                .copied()
                .filter(|&y| y > lo + 0.25 * y_step_um && y < hi - 0.25 * y_step_um),
        );
        grid_y_um.push(hi);
        let grid_x_um = x_sweep_um.clone();
        // Held-out cells lie between the end units (x in [L/6, 5L/6]): beyond them u_x turns
        // towards the free ends and the inverse clamps x (reported, not hidden, by `locate`).
        let cells_x: Vec<usize> = (0..grid_x_um.len() - 1)
            .filter(|&i| {
                grid_x_um[i] >= g.length_um / 6.0 - 1e-6
                    && grid_x_um[i + 1] <= 5.0 * g.length_um / 6.0 + 1e-6
            })
            .collect();
        let cells_x = if cells_x.is_empty() {
            (0..grid_x_um.len() - 1).collect()
        } else {
            cells_x
        };
        let cy = grid_y_um.len() - 1;
        let held_out = (0..n_held_out)
            .map(|k| {
                // Spread over the cells: stride 3 in x and 5 in y.
                let (i, j) = (cells_x[(1 + 3 * k) % cells_x.len()], (2 + 5 * k) % cy);
                let x = 0.5 * (grid_x_um[i] + grid_x_um[i + 1]);
                let y = 0.5 * (grid_y_um[j] + grid_y_um[j + 1]);
                (x, y, HELD_OUT_FORCES_N[k % HELD_OUT_FORCES_N.len()])
            })
            .collect();
        CalibrationPlan {
            radius_um,
            force_table_n: FORCE_TABLE_N.to_vec(),
            y_sweep_um,
            x_sweep_um,
            grid_x_um,
            grid_y_um,
            held_out,
            accuracy,
        }
    }
}

/// Half side of the square patch of the same area as a contact of radius r: sqrt(pi) r / 2.
pub fn contact_half_side_um(radius_um: f64) -> f64 {
    0.5 * std::f64::consts::PI.sqrt() * radius_um
}

/// One solved load.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sample {
    pub x_um: f64,
    pub y_um: f64,
    pub force_n: f64,
    /// One per electrode, in [`Calibration::electrodes`] order.
    pub voltage_mv: Vec<f64>,
    /// `plate`, `large_deflection_plate` or `direct` (wholly over a support); None when read back from a calibration file.
    pub model: Option<crate::sensor::ModelKind>,
    pub error_estimate: Option<f64>,
}

/// What the study cost and how accurate its solves are.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cost {
    pub scenes: usize,
    pub wall_ms: f64,
    pub dofs: usize,
    pub levels: usize,
    /// Largest estimated relative error over the plate scenes (None without three levels).
    pub max_error_estimate: Option<f64>,
}

/// The calibration tables.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    pub electrodes: Vec<String>,
    pub force_table: Vec<Sample>,
    /// Largest |V(F)/F - V(1 N)| / max|V(1 N)| over the force table: 0 for a linear model.
    pub linearity_deviation: f64,
    /// The force table answered by the fidelity ladder (`--model auto`: the large-deflection
    /// plate where the linear one misses the tolerance), whatever rung the rest of the study uses.
    pub force_table_ladder: Vec<Sample>,
    /// Per electrode, the sensor's linearity error over the force table on the ladder.
    pub linearity_by_electrode: Vec<ElectrodeLinearity>,
    pub y_sweep: Vec<Sample>,
    pub x_sweep: Vec<Sample>,
    pub grid_x_um: Vec<f64>,
    pub grid_y_um: Vec<f64>,
    /// `grid[j][i]` at (`grid_x_um[i]`, `grid_y_um[j]`), 1 N.
    pub grid: Vec<Vec<Sample>>,
    pub held_out: Vec<Sample>,
    pub cost: Cost,
}

fn point(name: String, x_um: f64, y_um: f64, force_n: f64, radius_um: f64) -> Scene {
    Scene {
        name,
        load: SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        },
        limits: Limits::default(),
    }
}

fn sample(r: &SceneReport, x_um: f64, y_um: f64) -> Sample {
    Sample {
        x_um,
        y_um,
        force_n: r.force_n,
        voltage_mv: r.electrodes.iter().map(|e| e.voltage_mv).collect(),
        model: Some(r.model.kind),
        error_estimate: r.error_estimate,
    }
}

/// Runs the plan as one batched FE call.
pub fn calibrate(g: &SensorGeometry, plan: &CalibrationPlan) -> Result<Calibration, AnalysisError> {
    let increasing = |v: &[f64]| v.len() >= 2 && v.windows(2).all(|w| w[1] > w[0]);
    if !increasing(&plan.grid_x_um) || !increasing(&plan.grid_y_um) {
        return Err(AnalysisError::Plan {
            reason: format!(
                "a {:.0} um contact (a {:.0} um square) leaves no grid of at least 2 x 2 \
                 positions with the contact wholly on the {:.0} x {:.0} um plate",
                plan.radius_um,
                2.0 * contact_half_side_um(plan.radius_um),
                g.length_um,
                g.plate_y1_um - g.plate_y0_um
            ),
        });
    }
    let (cx, cy) = (g.length_um / 2.0, g.width_um / 2.0);
    let r = plan.radius_um;
    let mut scenes = Vec::new();
    let mut at = Vec::new();
    for &f in &plan.force_table_n {
        scenes.push(point(format!("force-{f}N"), cx, cy, f, r));
        at.push((cx, cy));
    }
    for &y in &plan.y_sweep_um {
        scenes.push(point(format!("y-{y}um"), cx, y, 1.0, r));
        at.push((cx, y));
    }
    for &x in &plan.x_sweep_um {
        scenes.push(point(format!("x-{x}um"), x, cy, 1.0, r));
        at.push((x, cy));
    }
    for &y in &plan.grid_y_um {
        for &x in &plan.grid_x_um {
            scenes.push(point(format!("grid-{x}-{y}um"), x, y, 1.0, r));
            at.push((x, y));
        }
    }
    for (k, &(x, y, f)) in plan.held_out.iter().enumerate() {
        scenes.push(point(format!("held-out-{k}"), x, y, f, r));
        at.push((x, y));
    }
    let t0 = Instant::now();
    let reports = evaluate_many_with(g, &scenes, plan.accuracy, MeshOptions::READINGS)?;
    let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut samples = reports
        .iter()
        .zip(&at)
        .map(|(rep, &(x, y))| sample(rep, x, y));
    let mut take = |n: usize| -> Vec<Sample> { samples.by_ref().take(n).collect() };
    let force_table = take(plan.force_table_n.len());
    let y_sweep = take(plan.y_sweep_um.len());
    let x_sweep = take(plan.x_sweep_um.len());
    let grid: Vec<Vec<Sample>> = plan
        .grid_y_um
        .iter()
        .map(|_| take(plan.grid_x_um.len()))
        .collect();
    let held_out = take(plan.held_out.len());
    let plate: Vec<&SceneReport> = reports.iter().filter(|r| r.model.kind.is_plate()).collect();
    let cost = Cost {
        scenes: scenes.len(),
        wall_ms,
        dofs: plate.iter().map(|r| r.model.dofs).max().unwrap_or(0),
        levels: plate.iter().map(|r| r.model.levels).max().unwrap_or(1),
        max_error_estimate: plate
            .iter()
            .map(|r| r.error_estimate)
            .try_fold(0f64, |a, e| e.map(|e| a.max(e))),
    };
    let linearity_deviation = linearity(&force_table);
    let force_table_ladder = if plan.accuracy.model == ModelChoice::Auto {
        force_table.clone()
    } else {
        let ladder = plan.accuracy.with_model(ModelChoice::Auto);
        evaluate_many_with(
            g,
            &scenes[..plan.force_table_n.len()],
            ladder,
            MeshOptions::READINGS,
        )?
        .iter()
        .map(|r| sample(r, cx, cy))
        .collect()
    };
    let linearity_by_electrode = linearity_by_electrode(g, &force_table_ladder);
    Ok(Calibration {
        electrodes: g.electrodes.iter().map(|e| e.name.clone()).collect(),
        force_table,
        linearity_deviation,
        force_table_ladder,
        linearity_by_electrode,
        y_sweep,
        x_sweep,
        grid_x_um: plan.grid_x_um.clone(),
        grid_y_um: plan.grid_y_um.clone(),
        grid,
        held_out,
        cost,
    })
}

/// How far one electrode (or a support's total charge) is from V proportional to F over the
/// force table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElectrodeLinearity {
    pub electrode: String,
    pub side: ElectrodeSide,
    /// Largest |V(F)/F - V(1 N)| / |V(1 N)| over the table's forces.
    pub deviation: f64,
    /// V(F_max)/F_max over V(1 N): above 1 the reading grows faster than the force.
    pub top_over_unit: f64,
}

/// Each electrode's departure from V proportional to F, relative to its own 1 N reading: the
/// support electrodes read the reactions (linear by equilibrium for a symmetric load), the middle
/// ones the film strain (not linear once the plate stretches).
fn linearity_by_electrode(g: &SensorGeometry, table: &[Sample]) -> Vec<ElectrodeLinearity> {
    let Some(unit) = table.iter().find(|s| (s.force_n - 1.0).abs() < 1e-12) else {
        return Vec::new();
    };
    let top = table
        .iter()
        .max_by(|a, b| a.force_n.total_cmp(&b.force_n))
        .expect("the unit row is in the table");
    // Per electrode, then each support's total charge (sum of Q = C V over its electrodes),
    // which equilibrium ties to the force.
    let mut rows: Vec<(String, ElectrodeSide, Vec<f64>)> = g
        .electrodes
        .iter()
        .enumerate()
        .map(|(i, e)| {
            (
                e.name.clone(),
                e.side,
                table.iter().map(|s| s.voltage_mv[i]).collect(),
            )
        })
        .collect();
    for (side, name) in [
        (ElectrodeSide::Support1, "support 1 total charge"),
        (ElectrodeSide::Support2, "support 2 total charge"),
    ] {
        let q: Vec<f64> = table
            .iter()
            .map(|s| {
                g.electrodes
                    .iter()
                    .zip(&s.voltage_mv)
                    .filter(|(e, _)| e.side == side)
                    .map(|(e, v)| v * g.capacitance_f(e.area_um2))
                    .sum()
            })
            .collect();
        rows.push((name.to_string(), side, q));
    }
    let (iu, it) = (
        table
            .iter()
            .position(|s| std::ptr::eq(s, unit))
            .expect("in the table"),
        table
            .iter()
            .position(|s| std::ptr::eq(s, top))
            .expect("in the table"),
    );
    rows.into_iter()
        .map(|(electrode, side, v)| {
            let u = v[iu];
            let deviation = if u == 0.0 {
                0.0
            } else {
                table
                    .iter()
                    .zip(&v)
                    .map(|(s, x)| (x / s.force_n - u).abs() / u.abs())
                    .fold(0.0, f64::max)
            };
            ElectrodeLinearity {
                electrode,
                side,
                deviation,
                top_over_unit: if u == 0.0 {
                    1.0
                } else {
                    v[it] / top.force_n / u
                },
            }
        })
        .collect()
}

/// Largest departure from V proportional to F, relative to the largest voltage per newton.
fn linearity(table: &[Sample]) -> f64 {
    let Some(unit) = table.iter().find(|s| (s.force_n - 1.0).abs() < 1e-12) else {
        return f64::NAN;
    };
    let scale = unit.voltage_mv.iter().fold(0f64, |a, v| a.max(v.abs()));
    table
        .iter()
        .flat_map(|s| {
            s.voltage_mv
                .iter()
                .zip(&unit.voltage_mv)
                .map(move |(v, u)| (v / s.force_n - u).abs() / scale)
        })
        .fold(0.0, f64::max)
}

/// Index sets the paper's sums use: support 1 and 2 electrodes, and the first and last unit's
/// support pair (S11 + S21 and S13 + S23 on mis-grasper), by x position.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SupportGroups {
    pub support1: Vec<usize>,
    pub support2: Vec<usize>,
    pub first_unit: Vec<usize>,
    pub last_unit: Vec<usize>,
}

impl SupportGroups {
    pub fn of(g: &SensorGeometry) -> Result<Self, AnalysisError> {
        let idx = |side: ElectrodeSide| -> Vec<usize> {
            g.electrodes
                .iter()
                .enumerate()
                .filter(|(_, e)| e.side == side)
                .map(|(i, _)| i)
                .collect()
        };
        let (support1, support2) = (idx(ElectrodeSide::Support1), idx(ElectrodeSide::Support2));
        if support1.len() < 2 || support2.len() < 2 {
            return Err(AnalysisError::Calibration {
                reason: "the load inverse needs at least two electrodes on each support".into(),
            });
        }
        let x = |i: usize| g.electrodes[i].x0_um;
        let pick = |set: &[usize], first: bool| -> usize {
            *set.iter()
                .min_by(|&&a, &&b| {
                    if first {
                        x(a).total_cmp(&x(b))
                    } else {
                        x(b).total_cmp(&x(a))
                    }
                })
                .expect("non-empty")
        };
        Ok(SupportGroups {
            first_unit: vec![pick(&support1, true), pick(&support2, true)],
            last_unit: vec![pick(&support1, false), pick(&support2, false)],
            support1,
            support2,
        })
    }

    fn sum(set: &[usize], v: &[f64]) -> f64 {
        set.iter().map(|&i| v[i]).sum()
    }

    /// (S1 - S2) / (S1 + S2) of the support totals: 1 over support 1, -1 over support 2,
    /// force-free.
    pub fn u_y(&self, v: &[f64]) -> f64 {
        let (a, b) = (Self::sum(&self.support1, v), Self::sum(&self.support2, v));
        (a - b) / (a + b)
    }

    /// (VS1 - VS2) / (S1 + S2): VS1 the first unit's pair, VS2 the last's (paper 002 Fig. 26),
    /// normalised by the support total. Not by VS1 + VS2: near mid-length the end units lift
    /// (opposite signs), so that sum passes through zero and the ratio is not monotone.
    pub fn u_x(&self, v: &[f64]) -> f64 {
        let (a, b) = (
            Self::sum(&self.first_unit, v),
            Self::sum(&self.last_unit, v),
        );
        let total = Self::sum(&self.support1, v) + Self::sum(&self.support2, v);
        (a - b) / total
    }

    /// S1 + S2: every support electrode.
    pub fn total(&self, v: &[f64]) -> f64 {
        Self::sum(&self.support1, v) + Self::sum(&self.support2, v)
    }

    pub fn vs1(&self, v: &[f64]) -> f64 {
        Self::sum(&self.first_unit, v)
    }

    pub fn vs2(&self, v: &[f64]) -> f64 {
        Self::sum(&self.last_unit, v)
    }
}
