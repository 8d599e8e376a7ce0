//! The load inverse: force, x and y from the electrode voltages, through the monotone calibration
//! curves rather than the straight line of paper 002 Fig. 24.
//!
//! Two force-free features (calibration.rs): u_y = (S1 - S2)/(S1 + S2) of the support totals,
//! monotone in y (Figs. 12, 23), and u_x = (VS1 - VS2)/(S1 + S2) of the end units' support pairs,
//! monotone in x between the end units (Fig. 26); beyond them (towards the free ends) it turns, so
//! x is clamped there and the estimate says so. Each is a PCHIP surface over the calibration grid;
//! y is solved on its curve at the current x, then x at the new y, until both settle (the
//! cross-dependence is weak). The force is then the support total over its calibrated sensitivity
//! at (x, y): F = (S1 + S2) / (s_S1 + s_S2)(x, y). By equilibrium the supports carry the whole
//! load, so that sensitivity only changes with the electrodes' coverage of the support length and
//! barely with position; the middle electrodes' sensitivities change steeply with position, so a
//! least-squares scale over all nine would turn every position error into a force error.

use serde::Serialize;

use super::calibration::{Calibration, Sample, SupportGroups};
use super::interp::{grid_eval, Pchip};
use super::noise::Gaussian;
use super::AnalysisError;

/// A calibrated inverse.
#[derive(Debug, Clone, PartialEq)]
pub struct Locator {
    pub electrodes: Vec<String>,
    groups: SupportGroups,
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// [electrode][j][i] in mV/N.
    sens: Vec<Vec<Vec<f64>>>,
    ux: Vec<Vec<f64>>,
    uy: Vec<Vec<f64>>,
    /// Monotone branches of u_x along x and u_y along y (index ranges of the grid nodes).
    x_branch: (usize, usize),
    y_branch: (usize, usize),
}

/// The answer for one set of voltages.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    pub force_n: f64,
    pub x_um: f64,
    pub y_um: f64,
    pub iterations: usize,
    pub converged: bool,
    /// The feature lay outside the calibrated range, so the position was clamped to its end
    /// (a load over a support: y there is not observable).
    pub clamped_x: bool,
    pub clamped_y: bool,
    /// RMS of V - F s(x, y) over the electrodes: how well the calibrated model explains the input.
    pub residual_mv: f64,
}

/// Longest run of grid nodes around the middle over which `u` is strictly monotone.
fn branch(u: &[f64]) -> (usize, usize) {
    let n = u.len();
    let mid = n / 2;
    let s = |i: usize| (u[i + 1] - u[i]).signum();
    let dir = if mid + 1 < n { s(mid.min(n - 2)) } else { 0.0 };
    let (mut lo, mut hi) = (mid.min(n - 2), mid.min(n - 2) + 1);
    while lo > 0 && s(lo - 1) == dir && dir != 0.0 {
        lo -= 1;
    }
    while hi + 1 < n && s(hi) == dir && dir != 0.0 {
        hi += 1;
    }
    (lo, hi)
}

impl Locator {
    pub fn new(cal: &Calibration, groups: SupportGroups) -> Result<Self, AnalysisError> {
        let (xs, ys) = (cal.grid_x_um.clone(), cal.grid_y_um.clone());
        if xs.len() < 2
            || ys.len() < 2
            || cal.grid.len() != ys.len()
            || cal.grid.iter().any(|r| r.len() != xs.len())
        {
            return Err(AnalysisError::Calibration {
                reason: format!(
                    "the grid must be at least 2 x 2 and complete ({} x nodes, {} y nodes)",
                    xs.len(),
                    ys.len()
                ),
            });
        }
        if !xs.windows(2).all(|w| w[1] > w[0]) || !ys.windows(2).all(|w| w[1] > w[0]) {
            return Err(AnalysisError::Calibration {
                reason: "grid nodes must increase strictly".into(),
            });
        }
        let ne = cal.electrodes.len();
        let per_n =
            |s: &Sample| -> Vec<f64> { s.voltage_mv.iter().map(|v| v / s.force_n).collect() };
        let sens = (0..ne)
            .map(|e| {
                cal.grid
                    .iter()
                    .map(|row| row.iter().map(|s| per_n(s)[e]).collect())
                    .collect()
            })
            .collect();
        let feature = |f: &dyn Fn(&[f64]) -> f64| -> Vec<Vec<f64>> {
            cal.grid
                .iter()
                .map(|row| row.iter().map(|s| f(&s.voltage_mv)).collect())
                .collect()
        };
        let ux = feature(&|v| groups.u_x(v));
        let uy = feature(&|v| groups.u_y(v));
        if ux.iter().chain(&uy).flatten().any(|u| !u.is_finite()) {
            return Err(AnalysisError::Calibration {
                reason: "a grid load gives no support signal (zero support sum)".into(),
            });
        }
        let mid_row = &ux[ys.len() / 2];
        let mid_col: Vec<f64> = uy.iter().map(|row| row[xs.len() / 2]).collect();
        Ok(Locator {
            electrodes: cal.electrodes.clone(),
            x_branch: branch(mid_row),
            y_branch: branch(&mid_col),
            groups,
            xs,
            ys,
            sens,
            ux,
            uy,
        })
    }

    /// Range of positions the inverse covers (x0, x1, y0, y1).
    pub fn domain_um(&self) -> (f64, f64, f64, f64) {
        (
            self.xs[self.x_branch.0],
            self.xs[self.x_branch.1],
            self.ys[self.y_branch.0],
            self.ys[self.y_branch.1],
        )
    }

    /// Sensitivities s_i(x, y) in mV/N.
    pub fn sensitivity(&self, x: f64, y: f64) -> Vec<f64> {
        self.sens
            .iter()
            .map(|s| grid_eval(&self.xs, &self.ys, s, x, y))
            .collect()
    }

    /// Solves `curve(t) = target` on [lo, hi], clamping to the nearer end outside the range.
    fn solve_clamped(curve: &Pchip, target: f64, lo: f64, hi: f64) -> (f64, bool) {
        match curve.solve(target, lo, hi) {
            Some(t) => (t, false),
            None => {
                let (a, b) = (curve.eval(lo), curve.eval(hi));
                (
                    if (target - a).abs() < (target - b).abs() {
                        lo
                    } else {
                        hi
                    },
                    true,
                )
            }
        }
    }

    pub fn locate(&self, v: &[f64]) -> Result<Estimate, AnalysisError> {
        if v.len() != self.electrodes.len() {
            return Err(AnalysisError::VoltageCount {
                expected: self.electrodes.len(),
                got: v.len(),
                names: self.electrodes.join(","),
            });
        }
        let (tx, ty) = (self.groups.u_x(v), self.groups.u_y(v));
        if !tx.is_finite() || !ty.is_finite() {
            return Err(AnalysisError::NoLoad);
        }
        let (x0, x1, y0, y1) = self.domain_um();
        let (mut x, mut y) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (mut clamped_x, mut clamped_y) = (false, false);
        let mut converged = false;
        let mut iterations = 0;
        for it in 1..=100 {
            iterations = it;
            let col: Vec<f64> = self
                .uy
                .iter()
                .map(|row| Pchip::new(&self.xs, row).eval(x))
                .collect();
            let (ny, cy) = Self::solve_clamped(&Pchip::new(&self.ys, &col), ty, y0, y1);
            let row: Vec<f64> = (0..self.xs.len())
                .map(|i| {
                    Pchip::new(&self.ys, &self.ux.iter().map(|r| r[i]).collect::<Vec<_>>()).eval(ny)
                })
                .collect();
            let (nx, cx) = Self::solve_clamped(&Pchip::new(&self.xs, &row), tx, x0, x1);
            let step = (nx - x).abs().max((ny - y).abs());
            (x, y, clamped_x, clamped_y) = (nx, ny, cx, cy);
            if step < 1e-3 {
                converged = true;
                break;
            }
        }
        let s = self.sensitivity(x, y);
        let force_n = self.groups.total(v) / self.groups.total(&s);
        let residual_mv = (s
            .iter()
            .zip(v)
            .map(|(a, b)| (b - force_n * a).powi(2))
            .sum::<f64>()
            / v.len() as f64)
            .sqrt();
        Ok(Estimate {
            force_n,
            x_um: x,
            y_um: y,
            iterations,
            converged,
            clamped_x,
            clamped_y,
            residual_mv,
        })
    }
}

/// One held-out load against its estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOutError {
    pub x_um: f64,
    pub y_um: f64,
    pub force_n: f64,
    pub estimate: Estimate,
    pub error_x_um: f64,
    pub error_y_um: f64,
    /// (F_est - F) / F.
    pub error_force_rel: f64,
}

pub fn held_out_errors(
    loc: &Locator,
    held_out: &[Sample],
) -> Result<Vec<HeldOutError>, AnalysisError> {
    held_out
        .iter()
        .map(|s| {
            let e = loc.locate(&s.voltage_mv)?;
            Ok(HeldOutError {
                x_um: s.x_um,
                y_um: s.y_um,
                force_n: s.force_n,
                error_x_um: e.x_um - s.x_um,
                error_y_um: e.y_um - s.y_um,
                error_force_rel: (e.force_n - s.force_n) / s.force_n,
                estimate: e,
            })
        })
        .collect()
}

/// Error statistics over the held-out loads with Gaussian noise of `sigma_mv` on every voltage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoiseRow {
    pub sigma_mv: f64,
    pub trials: usize,
    pub rms_error_x_um: f64,
    pub max_error_x_um: f64,
    pub rms_error_y_um: f64,
    pub max_error_y_um: f64,
    pub rms_error_force_rel: f64,
    pub max_error_force_rel: f64,
}

/// `trials` noisy copies of every held-out load per sigma, from one seeded stream. The held-out
/// voltages are first scaled to `force_n` (exact: the model is linear), so sigma compares with one
/// force for every position; the error at another force F is that at sigma F_ref / F.
pub fn noise_study(
    loc: &Locator,
    held_out: &[Sample],
    force_n: f64,
    sigmas_mv: &[f64],
    trials: usize,
    seed: u64,
) -> Result<Vec<NoiseRow>, AnalysisError> {
    let mut rng = Gaussian::new(seed);
    let mut rows = Vec::new();
    for &sigma in sigmas_mv {
        let (mut ex, mut ey, mut ef) = (Vec::new(), Vec::new(), Vec::new());
        for s in held_out {
            let k = force_n / s.force_n;
            for _ in 0..trials {
                let v: Vec<f64> = s
                    .voltage_mv
                    .iter()
                    .map(|v| k * v + sigma * rng.sample())
                    .collect();
                let e = loc.locate(&v)?;
                ex.push(e.x_um - s.x_um);
                ey.push(e.y_um - s.y_um);
                ef.push((e.force_n - force_n) / force_n);
            }
        }
        let rms = |v: &[f64]| (v.iter().map(|a| a * a).sum::<f64>() / v.len().max(1) as f64).sqrt();
        let max = |v: &[f64]| v.iter().fold(0f64, |a, b| a.max(b.abs()));
        rows.push(NoiseRow {
            sigma_mv: sigma,
            trials: ex.len(),
            rms_error_x_um: rms(&ex),
            max_error_x_um: max(&ex),
            rms_error_y_um: rms(&ey),
            max_error_y_um: max(&ey),
            rms_error_force_rel: rms(&ef),
            max_error_force_rel: max(&ef),
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_monotone_branch_stops_at_the_first_turn() {
        assert_eq!(branch(&[1.0, 0.8, 0.5, 0.1, -0.3, -0.2]), (0, 4));
        assert_eq!(branch(&[0.0, 1.0, 2.0, 3.0]), (0, 3));
        assert_eq!(branch(&[2.0, 1.0, 0.5, 1.0, 2.0, 3.0, 4.0]), (2, 6));
    }
}
