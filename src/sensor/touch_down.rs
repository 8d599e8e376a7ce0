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
/// reaches `gap_um`, to 0.1 % in deflection: bracketed regula falsi (Illinois) from `w1 = w(1)`.
/// None above `MAX_FACTOR` (100); errors of `w` pass through.
pub fn find_factor<E>(
    gap_um: f64,
    w1: f64,
    mut w: impl FnMut(f64) -> Result<f64, E>,
) -> Result<Option<f64>, E> {
    if !(w1 > 0.0 && gap_um > 0.0) {
        return Ok(None);
    }
    let (mut lo, mut hi) = ((0.0, -gap_um), (1.0, w1 - gap_um));
    // Bracket: grow by the linear guess until the deflection passes the gap.
    while hi.1 < 0.0 {
        lo = hi;
        let next = (hi.0 * gap_um / (hi.1 + gap_um))
            .max(2.0 * hi.0)
            .min(MAX_FACTOR);
        if next <= hi.0 {
            return Ok(None);
        }
        hi = (next, w(next)? - gap_um);
        if hi.1 < 0.0 && next >= MAX_FACTOR {
            return Ok(None);
        }
    }
    let mut side = 0;
    for _ in 0..40 {
        let x = (lo.0 * hi.1 - hi.0 * lo.1) / (hi.1 - lo.1);
        let f = w(x)? - gap_um;
        if f.abs() <= 1e-3 * gap_um {
            return Ok(Some(x));
        }
        if f < 0.0 {
            lo = (x, f);
            if side == -1 {
                hi.1 *= 0.5;
            }
            side = -1;
        } else {
            hi = (x, f);
            if side == 1 {
                lo.1 *= 0.5;
            }
            side = 1;
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
    }
}
