//! Where the plate meets the channel floor: the load, scaled from a scene's, at which the largest
//! deflection reaches the gap under the plate. Beyond it the floor carries part of the load,
//! which no rung models yet, so readings there are refused with a finding.

use serde::Serialize;

use crate::fe::Load;

/// The touch-down of one scene's load pattern.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TouchDown {
    /// Room under the plate ([`super::SensorGeometry::gap_um`]).
    pub gap_um: f64,
    /// The load (same pattern as the scene) at which the plate touches; None when it does not
    /// touch below `MAX_FACTOR` (100) times the scene's load.
    pub load_n: Option<f64>,
    /// How it was found.
    pub basis: String,
}

/// Loads beyond this multiple of the scene's are not searched.
pub const MAX_FACTOR: f64 = 100.0;

/// Plate loads with every force scaled by `s`.
pub(super) fn scaled_loads(loads: &[Load], s: f64) -> Vec<Load> {
    let mut out = loads.to_vec();
    for p in &mut out {
        match p {
            Load::Point { force_n, .. } => *force_n *= s,
            Load::Pressure { total_force_n, .. }
            | Load::Line { total_force_n, .. }
            | Load::Probe { total_force_n, .. }
            | Load::Polygon { total_force_n, .. } => *total_force_n *= s,
        }
    }
    out
}

/// The load factor at which `w(factor)` (the largest deflection, um, increasing in the factor)
/// reaches `gap_um`, to 0.1 % in deflection, from `w1 = w(1)`. A plate's deflection follows a
/// power of the load (w ~ F in bending, ~ F^(1/3) as a membrane), so both the bracketing steps and
/// the search inside the bracket interpolate ln w against ln F (secant in log-log, bisection when
/// that leaves the bracket or stalls on one side). None above `MAX_FACTOR` (100); errors of `w` pass through.
pub fn find_factor<E>(
    gap_um: f64,
    w1: f64,
    mut w: impl FnMut(f64) -> Result<f64, E>,
) -> Result<Option<f64>, E> {
    if !(w1 > 0.0 && gap_um > 0.0) {
        return Ok(None);
    }
    // (factor, deflection) below and above the gap.
    let (mut lo, mut hi) = ((0.0f64, 0.0f64), (1.0f64, w1));
    // Bracket: the local power law aimed 5 % past the gap, at least 1.2x the factor per step.
    while hi.1 < gap_um {
        let p = if lo.0 > 0.0 && lo.1 > 0.0 && hi.1 > lo.1 {
            ((hi.1 / lo.1).ln() / (hi.0 / lo.0).ln()).clamp(0.2, 1.0)
        } else {
            1.0
        };
        let next = (hi.0 * (1.05 * gap_um / hi.1).powf(1.0 / p))
            .max(1.2 * hi.0)
            .min(MAX_FACTOR);
        if next <= hi.0 {
            return Ok(None);
        }
        lo = hi;
        hi = (next, w(next)?);
        if hi.1 < gap_um && next >= MAX_FACTOR {
            return Ok(None);
        }
    }
    // The side the last two steps moved; twice the same side and the secant is stalling: halve.
    let (mut last, mut before) = (0i8, 0i8);
    for _ in 0..60 {
        let stalled = last != 0 && last == before;
        let x = if stalled {
            0.5 * (lo.0 + hi.0)
        } else if lo.0 > 0.0 && lo.1 > 0.0 {
            let t = (gap_um / lo.1).ln() / (hi.1 / lo.1).ln();
            (lo.0.ln() + t * (hi.0 / lo.0).ln()).exp()
        } else {
            lo.0 + (hi.0 - lo.0) * (gap_um - lo.1) / (hi.1 - lo.1)
        };
        let x = if x > lo.0 && x < hi.0 && x.is_finite() {
            x
        } else {
            0.5 * (lo.0 + hi.0)
        };
        let f = w(x)?;
        if (f - gap_um).abs() <= 1e-3 * gap_um {
            return Ok(Some(x));
        }
        before = last;
        if f < gap_um {
            lo = (x, f);
            last = -1;
        } else {
            hi = (x, f);
            last = 1;
        }
        if stalled {
            (last, before) = (0, 0);
        }
    }
    Ok(Some(0.5 * (lo.0 + hi.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_linear_and_a_hardening_touch_down() {
        let lin = find_factor::<()>(175.0, 35.0, |s| Ok(35.0 * s))
            .unwrap()
            .unwrap();
        assert!((lin - 5.0).abs() < 5e-3 * 5.0, "{lin}");
        // w + w^3 / 1e5 = 35 s (a hardening plate): at w = 175, s = (175 + 53.59) / 35.
        let hard = |s: f64| -> Result<f64, ()> {
            let (mut a, mut b) = (0.0, 1e4);
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if m + m * m * m / 1e5 < 35.0 * s {
                    a = m
                } else {
                    b = m
                }
            }
            Ok(a)
        };
        let s = find_factor(175.0, hard(1.0).unwrap(), hard)
            .unwrap()
            .unwrap();
        let expect = (175.0 + 175f64.powi(3) / 1e5) / 35.0;
        assert!((s - expect).abs() <= 2e-3 * expect, "{s} vs {expect}");
        assert_eq!(
            find_factor::<()>(175.0, 1.0, |s| Ok(s.min(1.5))).unwrap(),
            None
        );
        // A membrane-like plate (w ~ F^(1/3) beyond a bending start) is found in a few
        // evaluations, not dozens: each one is a nonlinear plate solve.
        let mut calls = 0;
        let membrane = |s: f64| -> Result<f64, ()> {
            calls += 1;
            Ok(if s <= 1.0 {
                35.0 * s
            } else {
                35.0 * s.powf(1.0 / 3.0)
            })
        };
        let s = find_factor(140.0, 35.0, membrane).unwrap().unwrap();
        assert!((35.0 * s.powf(1.0 / 3.0) - 140.0).abs() <= 0.14, "{s}");
        assert!(calls <= 6, "{calls} evaluations");
    }
}
