//! The corner's own discretisation error: the corner deviation is first order in the grid
//! (the closed-form tests measure it: the pyramid apex and the uncompensated corner halve their
//! error when the grid halves), so the same cell etched on the grid and on its double gives a
//! Richardson estimate of the error and the extrapolated value, at 1/8 of the fine run's cost
//! (a quarter of the nodes, half the time steps).

use serde::Serialize;

/// Convergence order of the corner deviation in the grid step \[measured: the closed-form
/// tests and the bundled corner, -229 / -203 / -149 um on 5 / 10 / 20 um: differences 26 and
/// 54 um, observed order 1.05\].
pub const CORNER_ORDER: f64 = 1.0;

/// Where the tolerance falls against the corner's uncertainty.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToleranceDecision {
    /// The whole band (extrapolated +/- error) lies within the tolerance.
    Within,
    /// The whole band lies beyond the tolerance.
    Beyond,
    /// The tolerance falls inside the band: a finer grid decides.
    WithinError,
}

/// The corner's Richardson estimate from the grid and its double.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CornerError {
    /// The coarser grid step actually used (twice the fine one, as the cell divides).
    pub coarse_grid_um: f64,
    /// The corner deviation on the coarser grid.
    pub coarse_corner_deviation_um: f64,
    /// The assumed order p ([`CORNER_ORDER`]).
    pub order: f64,
    /// Estimated error of the fine grid's corner: (c_h - c_2h) / (2^p - 1), signed so that
    /// fine + error = extrapolated.
    pub error_um: f64,
    /// Richardson's extrapolation c_h + (c_h - c_2h) / (2^p - 1): the best estimate.
    pub extrapolated_corner_deviation_um: f64,
    /// The tolerance against the band extrapolated +/- |error_um|.
    pub decision: ToleranceDecision,
}

/// Richardson extrapolation of a quantity of order `order` from step `h` (value `fine`) and step
/// `coarse_h` (value `coarse`): (extrapolated, error of `fine`), after Richardson 1911 /
/// Roache 1998 Eq. 5.4.1, f_exact ~ f_h + (f_h - f_rh) / (r^p - 1).
#[track_caller]
pub fn extrapolate(fine: f64, h: f64, coarse: f64, coarse_h: f64, order: f64) -> (f64, f64) {
    assert!(
        h > 0.0 && coarse_h > h && order > 0.0,
        "Richardson needs 0 < h < coarse_h and a positive order (h {h}, coarse {coarse_h}, p \
         {order})"
    );
    let err = (fine - coarse) / ((coarse_h / h).powf(order) - 1.0);
    (fine + err, err)
}

/// The estimate for a fine corner `fine_um` on `h_um` and a coarse `coarse_um` on
/// `coarse_h_um`, and where `tolerance_um` falls: the band is the extrapolated value +/- the
/// fine value's error (conservative: the extrapolation's own error is smaller when the order
/// holds).
pub fn corner_error(
    fine_um: f64,
    h_um: f64,
    coarse_um: f64,
    coarse_h_um: f64,
    tolerance_um: f64,
) -> CornerError {
    let (ext, err) = extrapolate(fine_um, h_um, coarse_um, coarse_h_um, CORNER_ORDER);
    let (lo, hi) = (ext.abs() - err.abs(), ext.abs() + err.abs());
    let decision = if hi <= tolerance_um {
        ToleranceDecision::Within
    } else if lo > tolerance_um {
        ToleranceDecision::Beyond
    } else {
        ToleranceDecision::WithinError
    };
    CornerError {
        coarse_grid_um: coarse_h_um,
        coarse_corner_deviation_um: coarse_um,
        order: CORNER_ORDER,
        error_um: err,
        extrapolated_corner_deviation_um: ext,
        decision,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_a_first_order_sequence() {
        // f(h) = 3 - 0.7 h: first order, the extrapolation recovers 3 exactly.
        let f = |h: f64| 3.0 - 0.7 * h;
        let (e, err) = extrapolate(f(5.0), 5.0, f(10.0), 10.0, 1.0);
        assert!((e - 3.0).abs() < 1e-12, "{e}");
        assert!((err - 3.5).abs() < 1e-12, "{err}");
        // Second order with p = 2: f = 1 + h^2.
        let g = |h: f64| 1.0 + h * h;
        let (e, _) = extrapolate(g(0.5), 0.5, g(1.0), 1.0, 2.0);
        assert!((e - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bundled_numbers_and_decisions() {
        // README: -229.3 on 5 um, -203.3 on 10 um.
        let c = corner_error(-229.3, 5.0, -203.3, 10.0, 25.0);
        assert!((c.extrapolated_corner_deviation_um + 255.3).abs() < 1e-9);
        assert!((c.error_um + 26.0).abs() < 1e-9);
        assert_eq!(c.decision, ToleranceDecision::Beyond);
        // 8 and 6: band 10 +/- 2, within 25; 16 and 10: band 22 +/- 6 straddles 25.
        assert_eq!(
            corner_error(8.0, 5.0, 6.0, 10.0, 25.0).decision,
            ToleranceDecision::Within
        );
        assert_eq!(
            corner_error(16.0, 5.0, 10.0, 10.0, 25.0).decision,
            ToleranceDecision::WithinError
        );
    }

    #[test]
    #[should_panic(expected = "Richardson needs")]
    fn coarse_must_be_coarser() {
        extrapolate(1.0, 5.0, 1.0, 5.0, 1.0);
    }
}
