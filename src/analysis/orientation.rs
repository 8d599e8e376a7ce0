//! The probe-orientation study of paper 000: a 14 x 7 mm rectangular probe at the sensor centre,
//! rotated 0-180 deg in 10 deg steps, at 0.5, 1 and 2 N; charge against angle per electrode, fits
//! in well-conditioned bases, the inverse angle from one electrode's charge on its monotone branch
//! checked by re-running the FE at the estimated angle (the paper's Tables 2-3), and the
//! normalised bivariate charge(angle, force) = N(angle) g(F) of its Eq. 12-13.
//!
//! The linear plate is linear in force, so the angle sweep is solved once at the reference force
//! and scaled; real solves at the other forces at a few angles check that
//! (`linearity_deviation`). The sensor is not (the large-deflection rung, see `calibrate`), so the
//! study runs on the linear plate only and its model error is reported with each solve.

use std::time::Instant;

use serde::Serialize;

use crate::process::{Limits, Scene, SceneLoad};
use crate::sensor::{evaluate_many, Accuracy, SceneReport, SensorGeometry};

use super::calibration::Cost;
use super::fit::{fit, monomial_condition_number, Basis, BasisKind, Fit};
use super::AnalysisError;

/// The study's inputs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrientationPlan {
    pub x_um: f64,
    pub y_um: f64,
    pub width_um: f64,
    pub height_um: f64,
    pub angles_deg: Vec<f64>,
    pub forces_n: Vec<f64>,
    pub reference_force_n: f64,
    /// Angles solved at every other force too (the linearity check).
    pub check_angles_deg: Vec<f64>,
    pub degree: usize,
    /// Harmonics of the Fourier-in-2-theta fit.
    pub fourier_degree: usize,
    /// Electrode for the inverse angle; None = of those whose charge keeps its sign, the one whose
    /// charge varies most with angle.
    pub electrode: Option<String>,
    /// Fractions of the branch's charge range the inverse is tried at (4 tries as in Tables 2-3).
    pub inverse_fractions: Vec<f64>,
    pub accuracy: Accuracy,
}

impl OrientationPlan {
    /// Paper 000: 14 x 7 mm probe at the die centre, 0-180 deg by `step_deg`, 0.5/1/2 N.
    pub fn paper(g: &SensorGeometry, step_deg: f64, accuracy: Accuracy) -> Self {
        let n = (180.0 / step_deg).round() as usize;
        OrientationPlan {
            x_um: g.length_um / 2.0,
            y_um: g.width_um / 2.0,
            width_um: 14_000.0,
            height_um: 7_000.0,
            angles_deg: (0..=n).map(|k| 180.0 * k as f64 / n as f64).collect(),
            forces_n: vec![0.5, 1.0, 2.0],
            reference_force_n: 1.0,
            check_angles_deg: vec![0.0, 90.0],
            degree: 10,
            fourier_degree: 4,
            electrode: None,
            inverse_fractions: vec![0.2, 0.4, 0.6, 0.8],
            accuracy,
        }
    }
}

/// Fits of one electrode's charge against angle at the reference force.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElectrodeFits {
    pub electrode: String,
    pub chebyshev: Fit,
    pub fourier: Fit,
    /// Charge range over the angles (pC), and (max - min) / mean |charge|.
    pub range_pc: f64,
    pub relative_variation: f64,
}

/// One row of the inverse-angle table (paper 000 Tables 2-3).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InverseRow {
    pub force_n: f64,
    pub assumed_charge_pc: f64,
    pub estimated_angle_deg: f64,
    /// Charge of the FE re-run at the estimated angle.
    pub fe_charge_pc: f64,
    /// |fe - assumed| / |assumed| in per cent (the paper's "error").
    pub charge_error_pct: f64,
    /// (fe - assumed) / (dc/dangle): the angle error that charge error corresponds to.
    pub angle_error_deg: f64,
}

/// c(angle, F) = N(angle) g(F) with N(0) = 1 (paper 000 Eq. 12-13).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bivariate {
    pub electrode: String,
    /// N fitted to c(angle, F) / c(0, F) of every force at once.
    pub normalised: Fit,
    /// g(F) = slope F: the linear plate is linear, so the paper's 6th-degree force polynomial
    /// (Eq. 10-11) reduces to one coefficient, fitted by least squares to c(0, F); the sensor's
    /// own departure from it is `calibrate`'s ladder table.
    pub slope_pc_per_n: f64,
    /// Largest |N g - c| over every (angle, force) sample, pC, and relative to max |c|.
    pub max_abs_residual_pc: f64,
    pub max_rel_residual: f64,
    /// Largest spread between the normalised curves of different forces (0 for a linear model).
    pub normalised_spread: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Orientation {
    pub plan: OrientationPlan,
    pub electrodes: Vec<String>,
    /// `charge_pc[f][a][e]`: force index, angle index, electrode index.
    pub charge_pc: Vec<Vec<Vec<f64>>>,
    pub max_error_estimate: Option<f64>,
    /// Largest |c_solved(F) - c_scaled(F)| / max |c| over the check angles.
    pub linearity_deviation: f64,
    pub monomial_condition_number: f64,
    pub fits: Vec<ElectrodeFits>,
    pub inverse_electrode: String,
    /// The monotone branch of the fitted curve the inverse uses (deg).
    pub branch_deg: (f64, f64),
    pub inverse: Vec<InverseRow>,
    pub bivariate: Vec<Bivariate>,
    pub cost: Cost,
    pub inverse_cost: Cost,
}

fn probe(plan: &OrientationPlan, name: String, angle_deg: f64, force_n: f64) -> Scene {
    Scene {
        name,
        load: SceneLoad::Probe {
            x_um: plan.x_um,
            y_um: plan.y_um,
            width_um: plan.width_um,
            height_um: plan.height_um,
            angle_deg,
            force_n,
        },
        limits: Limits::default(),
    }
}

fn cost_of(reports: &[SceneReport], wall_ms: f64) -> Cost {
    let plate: Vec<&SceneReport> = reports.iter().filter(|r| r.model.kind.is_plate()).collect();
    Cost {
        scenes: reports.len(),
        wall_ms,
        dofs: plate.iter().map(|r| r.model.dofs).max().unwrap_or(0),
        levels: plate.iter().map(|r| r.model.levels).max().unwrap_or(1),
        max_error_estimate: plate
            .iter()
            .map(|r| r.error_estimate)
            .try_fold(0f64, |a, e| e.map(|e| a.max(e))),
    }
}

/// The longest interval between consecutive extrema of `f` on [lo, hi] (dense sampling, 0.05 deg).
pub fn monotone_branch(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    let n = ((hi - lo) / 0.05).ceil() as usize;
    let t: Vec<f64> = (0..=n)
        .map(|k| lo + (hi - lo) * k as f64 / n as f64)
        .collect();
    let v: Vec<f64> = t.iter().map(|&a| f(a)).collect();
    let mut cuts = vec![0];
    for k in 1..n {
        if (v[k] - v[k - 1]) * (v[k + 1] - v[k]) < 0.0 {
            cuts.push(k);
        }
    }
    cuts.push(n);
    let best = cuts
        .windows(2)
        .max_by(|a, b| {
            (v[a[1]] - v[a[0]])
                .abs()
                .total_cmp(&(v[b[1]] - v[b[0]]).abs())
        })
        .expect("two cuts");
    (t[best[0]], t[best[1]])
}

/// Angle in [lo, hi] where the fitted curve equals `charge` (bisection on the monotone branch).
pub fn invert_angle(fit: &Fit, scale: f64, charge: f64, lo: f64, hi: f64) -> Option<f64> {
    let g = |a: f64| scale * fit.eval(a) - charge;
    let (mut a, mut b) = (lo, hi);
    let (ga, gb) = (g(a), g(b));
    if ga * gb > 0.0 {
        return None;
    }
    let rising = gb > ga;
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if (g(m) < 0.0) == rising {
            a = m;
        } else {
            b = m;
        }
    }
    Some(0.5 * (a + b))
}

/// The whole study: the angle sweep at the reference force (and the check solves at the other
/// forces), fits per electrode, the inverse angle checked by FE re-runs, and the bivariate fits.
pub fn study(g: &SensorGeometry, plan: &OrientationPlan) -> Result<Orientation, AnalysisError> {
    if plan.accuracy.model != crate::sensor::ModelChoice::Plate {
        return Err(AnalysisError::LinearOnly {
            study: "orientation",
            model: plan.accuracy.model.as_str(),
        });
    }
    let fref = plan.reference_force_n;
    let others: Vec<f64> = plan
        .forces_n
        .iter()
        .copied()
        .filter(|f| (f - fref).abs() > 1e-12)
        .collect();
    let scenes = sweep_scenes(plan, &others);
    let t0 = Instant::now();
    let reports = evaluate_many(g, &scenes, plan.accuracy)?;
    let cost = cost_of(&reports, t0.elapsed().as_secs_f64() * 1e3);
    let na = plan.angles_deg.len();
    let reference: Vec<Vec<f64>> = reports[..na].iter().map(charges).collect();
    let cmax = reference.iter().flatten().fold(0f64, |a, c| a.max(c.abs()));
    let linearity_deviation = linearity_deviation(plan, &others, &reports[na..], &reference, cmax);
    let charge_pc = scaled_charges(plan, &reference);
    let names: Vec<String> = g.electrodes.iter().map(|e| e.name.clone()).collect();
    let (lo, hi) = (plan.angles_deg[0], plan.angles_deg[na - 1]);
    let (cheb, four) = bases(plan, lo, hi);
    let fits = electrode_fits(plan, &names, &reference, cheb, four)?;
    let ie = inverse_electrode(plan, &names, &reference, &fits)?;
    let f_ie = &fits[ie].chebyshev;
    let branch_deg = monotone_branch(&|a| f_ie.eval(a), lo, hi);
    let tries = inverse_tries(plan, &others, f_ie, branch_deg);
    let rescenes: Vec<Scene> = tries
        .iter()
        .enumerate()
        .map(|(k, &(f, _, a))| probe(plan, format!("inverse-{k}"), a, f))
        .collect();
    let t1 = Instant::now();
    let rerun = evaluate_many(g, &rescenes, plan.accuracy)?;
    let inverse_cost = cost_of(&rerun, t1.elapsed().as_secs_f64() * 1e3);
    let inverse = inverse_rows(fref, &tries, &rerun, ie, f_ie);
    let bivariate = names
        .iter()
        .enumerate()
        .filter(|&(e, _)| reference[0][e].abs() > 1e-9 * cmax)
        .map(|(e, name)| bivariate(plan, &charge_pc, e, name, cheb))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Orientation {
        plan: plan.clone(),
        electrodes: names.clone(),
        charge_pc,
        max_error_estimate: cost.max_error_estimate,
        linearity_deviation,
        monomial_condition_number: monomial_condition_number(&plan.angles_deg, plan.degree),
        fits,
        inverse_electrode: names[ie].clone(),
        branch_deg,
        inverse,
        bivariate,
        cost,
        inverse_cost,
    })
}

/// Every electrode's charge in one report (pC).
fn charges(r: &SceneReport) -> Vec<f64> {
    r.electrodes.iter().map(|e| e.charge_pc).collect()
}

/// The scenes solved at once: every angle at the reference force, then the check angles at each
/// other force.
fn sweep_scenes(plan: &OrientationPlan, others: &[f64]) -> Vec<Scene> {
    let fref = plan.reference_force_n;
    let mut scenes: Vec<Scene> = plan
        .angles_deg
        .iter()
        .map(|&a| probe(plan, format!("probe-{a}deg-{fref}N"), a, fref))
        .collect();
    for &f in others {
        for &a in &plan.check_angles_deg {
            scenes.push(probe(plan, format!("probe-{a}deg-{f}N"), a, f));
        }
    }
    scenes
}

/// Linearity: real solves at the other forces against the scaled reference, max |c - c_ref F /
/// F_ref| / (max |c_ref| F / F_ref).
fn linearity_deviation(
    plan: &OrientationPlan,
    others: &[f64],
    checks: &[SceneReport],
    reference: &[Vec<f64>],
    cmax: f64,
) -> f64 {
    let fref = plan.reference_force_n;
    let mut linearity_deviation: f64 = 0.0;
    for (k, r) in checks.iter().enumerate() {
        let (fi, ai) = (
            k / plan.check_angles_deg.len(),
            k % plan.check_angles_deg.len(),
        );
        let f = others[fi];
        let Some(ia) = plan
            .angles_deg
            .iter()
            .position(|a| (a - plan.check_angles_deg[ai]).abs() < 1e-9)
        else {
            continue;
        };
        for (c, c1) in charges(r).iter().zip(&reference[ia]) {
            linearity_deviation =
                linearity_deviation.max((c - c1 * f / fref).abs() / (cmax * f / fref));
        }
    }
    linearity_deviation
}

/// charge_pc[f][a][e]: the reference sweep scaled to every force (the model is linear).
fn scaled_charges(plan: &OrientationPlan, reference: &[Vec<f64>]) -> Vec<Vec<Vec<f64>>> {
    let fref = plan.reference_force_n;
    plan.forces_n
        .iter()
        .map(|&f| {
            reference
                .iter()
                .map(|row| row.iter().map(|c| c * f / fref).collect())
                .collect()
        })
        .collect()
}

/// The Chebyshev and Fourier-in-2-theta bases over the swept angles.
fn bases(plan: &OrientationPlan, lo: f64, hi: f64) -> (Basis, Basis) {
    let cheb = Basis {
        kind: BasisKind::Chebyshev,
        degree: plan.degree,
        lo_deg: lo,
        hi_deg: hi,
    };
    let four = Basis {
        kind: BasisKind::Fourier2Theta,
        degree: plan.fourier_degree,
        lo_deg: lo,
        hi_deg: hi,
    };
    (cheb, four)
}

/// Both fits of each electrode's charge against angle, its range and (max - min) / mean |charge|.
fn electrode_fits(
    plan: &OrientationPlan,
    names: &[String],
    reference: &[Vec<f64>],
    cheb: Basis,
    four: Basis,
) -> Result<Vec<ElectrodeFits>, AnalysisError> {
    let na = plan.angles_deg.len();
    let mut fits = Vec::new();
    for (e, name) in names.iter().enumerate() {
        let y: Vec<f64> = reference.iter().map(|row| row[e]).collect();
        let (mn, mx) = y
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
        let mean = y.iter().map(|v| v.abs()).sum::<f64>() / na as f64;
        fits.push(ElectrodeFits {
            electrode: name.clone(),
            chebyshev: fit(cheb, &plan.angles_deg, &y)?,
            fourier: fit(four, &plan.angles_deg, &y)?,
            range_pc: mx - mn,
            relative_variation: if mean > 0.0 { (mx - mn) / mean } else { 0.0 },
        });
    }
    Ok(fits)
}

/// The electrode for the inverse angle: the one named, else of those whose charge keeps its sign
/// the one whose charge varies most with angle.
fn inverse_electrode(
    plan: &OrientationPlan,
    names: &[String],
    reference: &[Vec<f64>],
    fits: &[ElectrodeFits],
) -> Result<usize, AnalysisError> {
    match &plan.electrode {
        Some(n) => {
            names
                .iter()
                .position(|x| x == n)
                .ok_or_else(|| AnalysisError::UnknownElectrode {
                    name: n.clone(),
                    known: names.join(", "),
                })
        }
        // The paper's error is relative to the charge: pick among electrodes whose charge keeps
        // its sign over the angles (else the relative error is undefined near the zero
        // crossing).
        None => (0..names.len())
            .filter(|&e| {
                let s = reference[0][e].signum();
                s != 0.0 && reference.iter().all(|row| row[e].signum() == s)
            })
            .max_by(|&a, &b| {
                fits[a]
                    .relative_variation
                    .total_cmp(&fits[b].relative_variation)
            })
            .ok_or_else(|| AnalysisError::Fit {
                reason: "every electrode's charge changes sign with angle: name one with \
                         --electrode"
                    .into(),
            }),
    }
}

/// The inverse tries (force, assumed charge, fitted angle): at the reference force and the
/// smallest other force (Tables 2 and 3: 1 N, 0.5 N), at fractions of the branch's charge range.
fn inverse_tries(
    plan: &OrientationPlan,
    others: &[f64],
    f_ie: &Fit,
    branch_deg: (f64, f64),
) -> Vec<(f64, f64, f64)> {
    let fref = plan.reference_force_n;
    let mut table_forces = vec![fref];
    table_forces.extend(others.iter().copied().min_by(f64::total_cmp));
    let (c0, c1) = (f_ie.eval(branch_deg.0), f_ie.eval(branch_deg.1));
    let mut tries = Vec::new();
    for &f in &table_forces {
        let s = f / fref;
        for &q in &plan.inverse_fractions {
            let assumed = s * (c0 + q * (c1 - c0));
            let angle = invert_angle(f_ie, s, assumed, branch_deg.0, branch_deg.1)
                .expect("inside the branch by construction");
            tries.push((f, assumed, angle));
        }
    }
    tries
}

/// The inverse table: each try's FE charge at the estimated angle, the charge error in per cent
/// and the angle error (fe - assumed) / (dc/dangle).
fn inverse_rows(
    fref: f64,
    tries: &[(f64, f64, f64)],
    rerun: &[SceneReport],
    ie: usize,
    f_ie: &Fit,
) -> Vec<InverseRow> {
    tries
        .iter()
        .zip(rerun)
        .map(|(&(f, assumed, angle), r)| {
            let fe = r.electrodes[ie].charge_pc;
            let slope = (f / fref) * (f_ie.eval(angle + 0.01) - f_ie.eval(angle - 0.01)) / 0.02;
            InverseRow {
                force_n: f,
                assumed_charge_pc: assumed,
                estimated_angle_deg: angle,
                fe_charge_pc: fe,
                charge_error_pct: 100.0 * (fe - assumed).abs() / assumed.abs(),
                angle_error_deg: if slope != 0.0 {
                    (fe - assumed) / slope
                } else {
                    f64::NAN
                },
            }
        })
        .collect()
}

/// Eq. 12-13: normalise each force's curve by its value at the first angle, fit N to all of them
/// at once, fit g(F) = k F to the first-angle values, and measure N g against every sample.
fn bivariate(
    plan: &OrientationPlan,
    c: &[Vec<Vec<f64>>],
    e: usize,
    name: &str,
    basis: Basis,
) -> Result<Bivariate, AnalysisError> {
    let (mut t, mut y) = (Vec::new(), Vec::new());
    for cf in c {
        for (a, row) in plan.angles_deg.iter().zip(cf) {
            t.push(*a);
            y.push(row[e] / cf[0][e]);
        }
    }
    let normalised = fit(basis, &t, &y)?;
    let (num, den) = plan
        .forces_n
        .iter()
        .zip(c)
        .fold((0.0, 0.0), |(n, d), (f, cf)| (n + f * cf[0][e], d + f * f));
    let slope = num / den;
    let (mut worst, mut cmax, mut spread) = (0f64, 0f64, 0f64);
    for (f, cf) in plan.forces_n.iter().zip(c) {
        for (k, (a, row)) in plan.angles_deg.iter().zip(cf).enumerate() {
            worst = worst.max((normalised.eval(*a) * slope * f - row[e]).abs());
            cmax = cmax.max(row[e].abs());
            spread = spread.max((row[e] / cf[0][e] - c[0][k][e] / c[0][0][e]).abs());
        }
    }
    Ok(Bivariate {
        electrode: name.to_string(),
        normalised,
        slope_pc_per_n: slope,
        max_abs_residual_pc: worst,
        max_rel_residual: if cmax > 0.0 { worst / cmax } else { 0.0 },
        normalised_spread: spread,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn branch_and_inverse_on_a_known_curve() {
        // cos 2a + 3: monotone on [0, 90], the longest branch; inverse recovers the angle.
        let t: Vec<f64> = (0..=18).map(|k| 10.0 * k as f64).collect();
        let c = |a: f64| 3.0 + (2.0 * a.to_radians()).cos() - 0.1 * (a / 180.0);
        let y: Vec<f64> = t.iter().map(|&a| c(a)).collect();
        let f = fit(
            Basis {
                kind: BasisKind::Chebyshev,
                degree: 10,
                lo_deg: 0.0,
                hi_deg: 180.0,
            },
            &t,
            &y,
        )
        .unwrap();
        let (a, b) = monotone_branch(&|x| f.eval(x), 0.0, 180.0);
        assert!(a < 0.1 && (b - 90.0).abs() < 1.0, "{a} {b}");
        for truth in [12.0, 45.0, 77.7] {
            let est = invert_angle(&f, 2.0, 2.0 * c(truth), a, b).unwrap();
            assert!((est - truth).abs() < 0.05, "{truth} -> {est}");
        }
    }
}
