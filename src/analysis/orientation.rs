//! The probe-orientation study of paper 000: a 14 x 7 mm rectangular probe at the sensor centre,
//! rotated 0-180 deg in 10 deg steps, at 0.5, 1 and 2 N; charge against angle per electrode, fits
//! in well-conditioned bases, the inverse angle from one electrode's charge on its monotone branch
//! checked by re-running the FE at the estimated angle (the paper's Tables 2-3), and the
//! normalised bivariate charge(angle, force) = N(angle) g(F) of its Eq. 12-13.
//!
//! On the linear plate (`--model plate`) the charges are linear in force, so the angle sweep is
//! solved once at the reference force and scaled; real solves at the other forces at a few angles
//! check that (`linearity_deviation`, round-off). On the large-deflection rung (`--model
//! large-deflection`, or `auto` where the linear plate misses the tolerance) every angle is solved
//! at every force: the charge grows faster than the force once the plate stretches, the inverse
//! uses each force's own fit, and `linearity_deviation` measures the sensor's nonlinearity.

use std::time::Instant;

use serde::Serialize;

use crate::process::{Limits, Scene, SceneLoad};
use crate::sensor::{
    evaluate_many_with, Accuracy, MeshOptions, ModelChoice, SceneReport, SensorGeometry,
};

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
    /// g(F) = slope F + quadratic F^2, fitted by least squares to c(0, F) over the forces (the
    /// paper's 6th-degree force polynomial, Eq. 10-11, cut to what three forces determine); on the
    /// linear plate the quadratic term is round-off.
    pub slope_pc_per_n: f64,
    pub quadratic_pc_per_n2: f64,
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
    /// Largest |c(F) - c(F_ref) F / F_ref| / (max |c(F_ref)| F / F_ref) over the solved (force,
    /// angle) pairs: round-off on the linear plate, the sensor's nonlinearity on the
    /// large-deflection rung.
    pub linearity_deviation: f64,
    /// Every angle was solved at every force (a rung that may be nonlinear); false: the
    /// reference sweep scaled, checked at `check_angles_deg`.
    pub solved_every_force: bool,
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
    if plan.accuracy.model == ModelChoice::Beam {
        return Err(AnalysisError::NeedsPlate {
            study: "orientation",
            model: plan.accuracy.model.as_str(),
        });
    }
    let every = plan.accuracy.model != ModelChoice::Plate;
    let fref = plan.reference_force_n;
    let others: Vec<f64> = plan
        .forces_n
        .iter()
        .copied()
        .filter(|f| (f - fref).abs() > 1e-12)
        .collect();
    let check_angles = if every {
        &plan.angles_deg
    } else {
        &plan.check_angles_deg
    };
    let scenes = sweep_scenes(plan, &others, check_angles);
    let t0 = Instant::now();
    let reports = evaluate_many_with(g, &scenes, plan.accuracy, MeshOptions::READINGS)?;
    let cost = cost_of(&reports, t0.elapsed().as_secs_f64() * 1e3);
    let na = plan.angles_deg.len();
    let reference: Vec<Vec<f64>> = reports[..na].iter().map(charges).collect();
    let cmax = reference.iter().flatten().fold(0f64, |a, c| a.max(c.abs()));
    let checks: Vec<Vec<f64>> = reports[na..].iter().map(charges).collect();
    let linearity_deviation =
        linearity_deviation(plan, &others, check_angles, &checks, &reference, cmax);
    let charge_pc = if every {
        solved_charges(plan, &others, &reference, &checks)
    } else {
        scaled_charges(plan, &reference)
    };
    let names: Vec<String> = g.electrodes.iter().map(|e| e.name.clone()).collect();
    let (lo, hi) = (plan.angles_deg[0], plan.angles_deg[na - 1]);
    let (cheb, four) = bases(plan, lo, hi);
    let fits = electrode_fits(plan, &names, &reference, cheb, four)?;
    let ie = inverse_electrode(plan, &names, &reference, &fits)?;
    let f_ie = &fits[ie].chebyshev;
    let branch_deg = monotone_branch(&|a| f_ie.eval(a), lo, hi);
    // Each table force's curve of the inverse electrode: the reference fit scaled on the linear
    // plate, the force's own fit where every force was solved.
    let mut curves = vec![(fref, f_ie.clone(), 1.0)];
    if let Some(f) = others.iter().copied().min_by(f64::total_cmp) {
        let curve = if every {
            let fi = plan
                .forces_n
                .iter()
                .position(|x| *x == f)
                .expect("one of the forces");
            let y: Vec<f64> = charge_pc[fi].iter().map(|row| row[ie]).collect();
            (f, fit(cheb, &plan.angles_deg, &y)?, 1.0)
        } else {
            (f, f_ie.clone(), f / fref)
        };
        curves.push(curve);
    }
    let tries = inverse_tries(plan, &curves, branch_deg);
    let rescenes: Vec<Scene> = tries
        .iter()
        .enumerate()
        .map(|(k, t)| probe(plan, format!("inverse-{k}"), t.angle_deg, t.force_n))
        .collect();
    let t1 = Instant::now();
    let rerun = evaluate_many_with(g, &rescenes, plan.accuracy, MeshOptions::READINGS)?;
    let inverse_cost = cost_of(&rerun, t1.elapsed().as_secs_f64() * 1e3);
    let inverse = inverse_rows(&tries, &curves, &rerun, ie);
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
        solved_every_force: every,
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

/// The scenes solved at once: every angle at the reference force, then `check_angles` at each
/// other force.
fn sweep_scenes(plan: &OrientationPlan, others: &[f64], check_angles: &[f64]) -> Vec<Scene> {
    let fref = plan.reference_force_n;
    let mut scenes: Vec<Scene> = plan
        .angles_deg
        .iter()
        .map(|&a| probe(plan, format!("probe-{a}deg-{fref}N"), a, fref))
        .collect();
    for &f in others {
        for &a in check_angles {
            scenes.push(probe(plan, format!("probe-{a}deg-{f}N"), a, f));
        }
    }
    scenes
}

/// Linearity: the solves at the other forces against the scaled reference, max |c - c_ref F /
/// F_ref| / (max |c_ref| F / F_ref).
fn linearity_deviation(
    plan: &OrientationPlan,
    others: &[f64],
    check_angles: &[f64],
    checks: &[Vec<f64>],
    reference: &[Vec<f64>],
    cmax: f64,
) -> f64 {
    let fref = plan.reference_force_n;
    let mut linearity_deviation: f64 = 0.0;
    for (k, c) in checks.iter().enumerate() {
        let (fi, ai) = (k / check_angles.len(), k % check_angles.len());
        let f = others[fi];
        let Some(ia) = plan
            .angles_deg
            .iter()
            .position(|a| (a - check_angles[ai]).abs() < 1e-9)
        else {
            continue;
        };
        for (c, c1) in c.iter().zip(&reference[ia]) {
            linearity_deviation =
                linearity_deviation.max((c - c1 * f / fref).abs() / (cmax * f / fref));
        }
    }
    linearity_deviation
}

/// charge_pc[f][a][e] from solves at every force: the reference block and the others' blocks
/// (in `others` order) put back in `forces_n` order.
fn solved_charges(
    plan: &OrientationPlan,
    others: &[f64],
    reference: &[Vec<f64>],
    checks: &[Vec<f64>],
) -> Vec<Vec<Vec<f64>>> {
    let na = plan.angles_deg.len();
    plan.forces_n
        .iter()
        .map(|f| match others.iter().position(|o| o == f) {
            Some(k) => checks[k * na..(k + 1) * na].to_vec(),
            None => reference.to_vec(),
        })
        .collect()
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

/// One inverse try: the force, the charge assumed read, the angle the force's curve gives.
#[derive(Debug, Clone, Copy)]
struct Try {
    force_n: f64,
    curve: usize,
    assumed_pc: f64,
    angle_deg: f64,
}

/// The inverse tries at each table force (Tables 2 and 3: 1 N, 0.5 N), at fractions of the
/// branch's charge range on that force's curve `(force, fit, scale)` (charge = scale fit(angle)).
fn inverse_tries(
    plan: &OrientationPlan,
    curves: &[(f64, Fit, f64)],
    branch_deg: (f64, f64),
) -> Vec<Try> {
    let mut tries = Vec::new();
    for (k, (f, fit, s)) in curves.iter().enumerate() {
        let (c0, c1) = (s * fit.eval(branch_deg.0), s * fit.eval(branch_deg.1));
        for &q in &plan.inverse_fractions {
            let assumed = c0 + q * (c1 - c0);
            let angle = invert_angle(fit, *s, assumed, branch_deg.0, branch_deg.1)
                .expect("between the branch ends' values by construction");
            tries.push(Try {
                force_n: *f,
                curve: k,
                assumed_pc: assumed,
                angle_deg: angle,
            });
        }
    }
    tries
}

/// The inverse table: each try's FE charge at the estimated angle, the charge error in per cent
/// and the angle error (fe - assumed) / (dc/dangle) on the try's curve.
fn inverse_rows(
    tries: &[Try],
    curves: &[(f64, Fit, f64)],
    rerun: &[SceneReport],
    ie: usize,
) -> Vec<InverseRow> {
    tries
        .iter()
        .zip(rerun)
        .map(|(t, r)| {
            let fe = r.electrodes[ie].charge_pc;
            let (_, fit, s) = &curves[t.curve];
            let slope = s * (fit.eval(t.angle_deg + 0.01) - fit.eval(t.angle_deg - 0.01)) / 0.02;
            InverseRow {
                force_n: t.force_n,
                assumed_charge_pc: t.assumed_pc,
                estimated_angle_deg: t.angle_deg,
                fe_charge_pc: fe,
                charge_error_pct: 100.0 * (fe - t.assumed_pc).abs() / t.assumed_pc.abs(),
                angle_error_deg: if slope != 0.0 {
                    (fe - t.assumed_pc) / slope
                } else {
                    f64::NAN
                },
            }
        })
        .collect()
}

/// Eq. 12-13: normalise each force's curve by its value at the first angle, fit N to all of them
/// at once, fit g(F) = k1 F + k2 F^2 to the first-angle values, and measure N g against every sample.
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
    // g(F) = k1 F + k2 F^2 by least squares on c(0, F): normal equations of the 2 x 2 system
    // (k2 = 0 with one force).
    let (mut s11, mut s12, mut s22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (f, cf) in plan.forces_n.iter().zip(c) {
        let (f2, y0) = (f * f, cf[0][e]);
        (s11, s12, s22) = (s11 + f2, s12 + f2 * f, s22 + f2 * f2);
        (b1, b2) = (b1 + f * y0, b2 + f2 * y0);
    }
    let det = s11 * s22 - s12 * s12;
    let (slope, quadratic) = if plan.forces_n.len() >= 2 && det > 1e-12 * s11 * s22 {
        ((b1 * s22 - b2 * s12) / det, (s11 * b2 - s12 * b1) / det)
    } else {
        (b1 / s11, 0.0)
    };
    let g_of = |f: f64| slope * f + quadratic * f * f;
    let (mut worst, mut cmax, mut spread) = (0f64, 0f64, 0f64);
    for (f, cf) in plan.forces_n.iter().zip(c) {
        for (k, (a, row)) in plan.angles_deg.iter().zip(cf).enumerate() {
            worst = worst.max((normalised.eval(*a) * g_of(*f) - row[e]).abs());
            cmax = cmax.max(row[e].abs());
            spread = spread.max((row[e] / cf[0][e] - c[0][k][e] / c[0][0][e]).abs());
        }
    }
    Ok(Bivariate {
        electrode: name.to_string(),
        normalised,
        slope_pc_per_n: slope,
        quadratic_pc_per_n2: quadratic,
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
