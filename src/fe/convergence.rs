//! Mesh-convergence studies: observed order, Richardson extrapolation and the grid convergence
//! index (Roache, Verification and Validation in Computational Science, 1998; Fs = 1.25 for three
//! grids).

use crate::fe::error::{FeError, FeResult};
use crate::fe::problem::PlateProblem;
use crate::fe::solution::PlateSolution;
use crate::fe::solve::Factorised;
use serde::Serialize;
use std::time::Instant;

/// Safety factor of the GCI for three-grid studies (Roache 1998).
pub const GCI_SAFETY: f64 = 1.25;

/// How three successive values approach the limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ConvergenceKind {
    /// Monotone: 0 < (f2-f1)/(f3-f2) < 1; Richardson applies.
    Monotonic,
    /// Sign change of the differences; estimate falls back to |f1 - f2| / (r21 - 1).
    Oscillatory,
    /// Differences not shrinking; estimate falls back to |f1 - f2| / (r21 - 1).
    Divergent,
    /// Differences at round-off level.
    RoundOff,
}

/// Three-grid estimate (f1 finest, f3 coarsest, constant refinement ratio r).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Richardson {
    pub kind: ConvergenceKind,
    /// p = ln((f3 - f2)/(f2 - f1)) / ln r (Roache Eq. 5.10.6.1) for a constant ratio, only for
    /// monotone convergence ([`richardson_ratios`] for two ratios).
    pub observed_order: Option<f64>,
    /// f_ext = f1 + (f1 - f2)/(r^p - 1) (Richardson), else f1.
    pub extrapolated: f64,
    /// GCI_fine = Fs |(f2 - f1)/f1| / (r^p - 1) (Roache Eq. 5.6.1); |(f2-f1)/f1| Fs when p is
    /// unavailable.
    pub gci_fine: f64,
    /// Absolute error estimate of f1: |f_ext - f1|, or |f1 - f2| / (r21 - 1) when p is
    /// unavailable.
    pub error_estimate: f64,
}

/// Observed order, Richardson value and GCI from coarse (f3), medium (f2) and fine (f1) values.
pub fn richardson(f3: f64, f2: f64, f1: f64, r: f64) -> Richardson {
    richardson_ratios(f3, f2, f1, r, r)
}

/// [`richardson`] for meshes refined by different ratios: r32 = h3/h2, r21 = h2/h1. The observed
/// order solves e32/e21 = r21^p (r32^p - 1)/(r21^p - 1) (from f = f_ext + C h^p; Celik et al.,
/// J. Fluids Eng. 130, 2008, Eqs. 3-5), by bisection: the right side grows with p from
/// ln r32 / ln r21 at p -> 0. Without an order the estimate is the first-order one,
/// |f1 - f2| / (r21 - 1).
pub fn richardson_ratios(f3: f64, f2: f64, f1: f64, r32: f64, r21: f64) -> Richardson {
    assert!(r32 > 1.0 && r21 > 1.0, "refinement ratios must exceed 1");
    let (e21, e32) = (f2 - f1, f3 - f2);
    let scale = f1.abs().max(f2.abs()).max(f3.abs()).max(f64::MIN_POSITIVE);
    let fallback = |kind| Richardson {
        kind,
        observed_order: None,
        extrapolated: f1,
        gci_fine: GCI_SAFETY * (e21 / f1).abs() / (r21 - 1.0),
        error_estimate: e21.abs() / (r21 - 1.0),
    };
    if e21.abs() <= 1e-13 * scale {
        return fallback(ConvergenceKind::RoundOff);
    }
    let ratio = e32 / e21;
    if !ratio.is_finite() || ratio <= 0.0 {
        return fallback(ConvergenceKind::Oscillatory);
    }
    let g = |p: f64| r21.powf(p) * (r32.powf(p) - 1.0) / (r21.powf(p) - 1.0);
    let (mut lo, mut hi) = (1e-9, 64.0);
    if ratio <= g(lo) {
        return fallback(ConvergenceKind::Divergent);
    }
    if ratio >= g(hi) {
        lo = hi;
    }
    while hi - lo > 1e-12 * hi {
        let mid = 0.5 * (lo + hi);
        if g(mid) < ratio {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let rp1 = r21.powf(p) - 1.0;
    let extrapolated = f1 + (f1 - f2) / rp1;
    Richardson {
        kind: ConvergenceKind::Monotonic,
        observed_order: Some(p),
        extrapolated,
        gci_fine: GCI_SAFETY * (e21 / f1).abs() / rp1,
        error_estimate: (extrapolated - f1).abs(),
    }
}

/// One mesh level of a convergence study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelReport {
    pub level: usize,
    pub elements: usize,
    pub dofs: usize,
    /// Wall time of factorisation + solve + quantity evaluation (ms).
    pub time_ms: f64,
    pub value: f64,
    /// Three-grid estimate using this level as the finest (from the third level on).
    pub estimate: Option<Richardson>,
    /// Relative error estimate of `value`: the GCI (or its fallback).
    pub rel_error_estimate: Option<f64>,
}

/// Result of a convergence study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergenceReport {
    pub levels: Vec<LevelReport>,
    pub refinement_ratio: f64,
    pub tolerance: f64,
    /// True when the last level's relative error estimate is below the tolerance.
    pub converged: bool,
}

impl ConvergenceReport {
    /// Finest computed value.
    pub fn value(&self) -> f64 {
        self.levels.last().map_or(f64::NAN, |l| l.value)
    }
    /// Last three-grid estimate, if any.
    pub fn estimate(&self) -> Option<Richardson> {
        self.levels.last().and_then(|l| l.estimate)
    }
}

/// Solve one level and time it.
fn run_level<Q>(problem: &PlateProblem, quantity: &Q, level: usize) -> FeResult<LevelReport>
where
    Q: Fn(&[PlateSolution]) -> f64,
{
    let t0 = Instant::now();
    let f = Factorised::new(problem)?;
    let sols = f.solve(&problem.load_cases)?;
    let value = quantity(&sols);
    let time_ms = t0.elapsed().as_secs_f64() * 1e3;
    if !value.is_finite() {
        return Err(FeError::Convergence {
            detail: format!("quantity is not finite at level {level}"),
            hint: "check the quantity closure",
        });
    }
    Ok(LevelReport {
        level,
        elements: problem.mesh.n_elements(),
        dofs: f.n_free_dofs(),
        time_ms,
        value,
        estimate: None,
        rel_error_estimate: None,
    })
}

fn attach_estimate(levels: &mut [LevelReport], r: f64) {
    let n = levels.len();
    if n >= 3 {
        let est = richardson(
            levels[n - 3].value,
            levels[n - 2].value,
            levels[n - 1].value,
            r,
        );
        levels[n - 1].rel_error_estimate = Some(est.gci_fine);
        levels[n - 1].estimate = Some(est);
    }
}

/// Run the given levels (each `build_problem(level)` refined by `refinement_ratio` over the
/// previous one) and attach three-grid estimates.
pub fn run_levels<B, Q>(
    build_problem: B,
    quantity: Q,
    levels: std::ops::Range<usize>,
    refinement_ratio: f64,
) -> FeResult<ConvergenceReport>
where
    B: Fn(usize) -> PlateProblem,
    Q: Fn(&[PlateSolution]) -> f64,
{
    let mut out = Vec::new();
    for level in levels {
        out.push(run_level(&build_problem(level), &quantity, level)?);
        attach_estimate(&mut out, refinement_ratio);
    }
    let converged = false;
    Ok(ConvergenceReport {
        levels: out,
        refinement_ratio,
        tolerance: f64::NAN,
        converged,
    })
}

/// Refine level by level (from 0) until the relative error estimate (GCI of the finest three
/// levels) is below `tol`, or `max_level` is reached (then `converged` is false). The observed
/// order is reported, never assumed.
pub fn solve_to_tolerance<B, Q>(
    build_problem: B,
    quantity: Q,
    refinement_ratio: f64,
    tol: f64,
    max_level: usize,
) -> FeResult<ConvergenceReport>
where
    B: Fn(usize) -> PlateProblem,
    Q: Fn(&[PlateSolution]) -> f64,
{
    assert!(tol > 0.0, "tolerance must be positive");
    let mut levels = Vec::new();
    for level in 0..=max_level {
        levels.push(run_level(&build_problem(level), &quantity, level)?);
        attach_estimate(&mut levels, refinement_ratio);
        if levels
            .last()
            .unwrap()
            .rel_error_estimate
            .is_some_and(|e| e < tol)
        {
            return Ok(ConvergenceReport {
                levels,
                refinement_ratio,
                tolerance: tol,
                converged: true,
            });
        }
    }
    Ok(ConvergenceReport {
        levels,
        refinement_ratio,
        tolerance: tol,
        converged: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_known_order() {
        // f(h) = 1 + 0.3 h^2 at h = 1, 1/2, 1/4.
        let f = |h: f64| 1.0 + 0.3 * h * h;
        let e = richardson(f(1.0), f(0.5), f(0.25), 2.0);
        assert_eq!(e.kind, ConvergenceKind::Monotonic);
        assert!((e.observed_order.unwrap() - 2.0).abs() < 1e-10);
        assert!((e.extrapolated - 1.0).abs() < 1e-12);
    }

    /// Meshes subdivided 2, 3 and 4 times (ratios 1.5 and 4/3), orders from 0.7 to 4.
    #[test]
    fn unequal_ratios_recover_known_order() {
        for p in [0.7, 1.2, 2.0, 4.0] {
            let f = |n: f64| 3.0 - 0.8 * n.powf(-p);
            let e = richardson_ratios(f(2.0), f(3.0), f(4.0), 1.5, 4.0 / 3.0);
            assert_eq!(e.kind, ConvergenceKind::Monotonic);
            assert!(
                (e.observed_order.unwrap() - p).abs() < 1e-8,
                "p = {p}: {e:?}"
            );
            assert!((e.extrapolated - 3.0).abs() < 1e-10, "p = {p}: {e:?}");
        }
        // Below the smallest ratio of differences any positive order gives: no order, first-order
        // estimate.
        let e = richardson_ratios(1.0, 1.1, 1.17, 2.0, 1.5);
        assert_eq!(e.kind, ConvergenceKind::Divergent);
        assert!((e.error_estimate - 0.14).abs() < 1e-12);
    }

    #[test]
    fn oscillatory_and_divergent_flagged() {
        let e = richardson(1.1, 0.95, 1.02, 2.0);
        assert_eq!(e.kind, ConvergenceKind::Oscillatory);
        assert!((e.error_estimate - 0.07).abs() < 1e-12);
        let e = richardson(1.0, 1.1, 1.3, 2.0);
        assert_eq!(e.kind, ConvergenceKind::Divergent);
        assert!(e.observed_order.is_none());
    }
}
