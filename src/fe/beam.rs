//! Fixed-fixed (clamped-clamped) beam with a point load: support reactions (paper 001, Eq. 3-6).

use serde::Serialize;

/// Support reactions of a fixed-fixed beam (N or N/m for a line load per unit width).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BeamReactions {
    /// Reaction at the support y = 0.
    pub r1: f64,
    /// Reaction at the support y = span.
    pub r2: f64,
}

/// Point load P at y on a clamped-clamped span lambda: R1 = P (lambda^3 - 3 lambda y^2 + 2 y^3) /
/// lambda^3, R2 = P (3 lambda y^2 - 2 y^3) / lambda^3 (paper 001, Eq. 3-6; independent of EI, so a
/// plate in cylindrical bending gives the same reactions per unit width with D in place of EI).
#[track_caller]
pub fn fixed_fixed_reactions(force: f64, y: f64, span: f64) -> BeamReactions {
    assert!(
        span > 0.0 && (0.0..=span).contains(&y),
        "load position must lie on the span"
    );
    let l3 = span.powi(3);
    BeamReactions {
        r1: force * (l3 - 3.0 * span * y * y + 2.0 * y.powi(3)) / l3,
        r2: force * (3.0 * span * y * y - 2.0 * y.powi(3)) / l3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invariants() {
        let r = fixed_fixed_reactions(2.0, 0.0, 5.0);
        assert_eq!((r.r1, r.r2), (2.0, 0.0));
        let r = fixed_fixed_reactions(2.0, 2.5, 5.0);
        assert!((r.r1 - r.r2).abs() < 1e-15);
        let r = fixed_fixed_reactions(3.0, 1.3, 5.0);
        assert!((r.r1 + r.r2 - 3.0).abs() < 1e-14);
    }
}
