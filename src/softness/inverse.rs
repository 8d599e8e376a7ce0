//! E_t from a middle-electrode voltage and the force (paper 001 sec. 3.2: "from Eq. 12 the only
//! remaining unknown, E_t, can be calculated"). Both models are linear in F, so V / F = g(E_t) with
//! g decreasing; bisection on ln E_t over the bracket.

use serde::Serialize;

use crate::softness::SoftnessError;

/// A recovered modulus and how well the voltage determines it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Inverse {
    pub tissue_e_pa: f64,
    /// |d ln E / d ln V|: relative error of E per relative error of the voltage (large on the plateaus).
    pub e_rel_per_v_rel: f64,
    /// Model evaluations used.
    pub evaluations: usize,
}

/// Solve g(E) = v_per_n for E in [e_lo, e_hi] (g decreasing), to a relative tolerance in E of
/// `rel_tol`.
pub fn invert(
    g: &mut dyn FnMut(f64) -> Result<f64, SoftnessError>,
    v_per_n: f64,
    e_lo_pa: f64,
    e_hi_pa: f64,
    rel_tol: f64,
) -> Result<Inverse, SoftnessError> {
    if !(v_per_n.is_finite()) {
        return Err(SoftnessError::BadInput {
            field: "voltage / force",
            value: v_per_n,
            hint: "finite voltage and a non-zero force",
        });
    }
    let (glo, ghi) = (g(e_lo_pa)?, g(e_hi_pa)?);
    let mut evals = 2;
    if !(v_per_n <= glo && v_per_n >= ghi) {
        return Err(SoftnessError::OutOfRange {
            v_per_n,
            lo: ghi,
            hi: glo,
            e_lo_pa,
            e_hi_pa,
            hint: "the voltage is outside what any tissue in the range gives: check the force, \
                   the sign and the units (V)",
        });
    }
    let (mut a, mut b) = (e_lo_pa.ln(), e_hi_pa.ln());
    while b - a > rel_tol {
        let m = 0.5 * (a + b);
        evals += 1;
        if g(m.exp())? > v_per_n {
            a = m;
        } else {
            b = m;
        }
    }
    let e = (0.5 * (a + b)).exp();
    let h = 0.01;
    let (gp, gm) = (g(e * (1.0 + h))?, g(e / (1.0 + h))?);
    evals += 2;
    let dlnv = (gp.ln() - gm.ln()) / (2.0 * (1.0 + h).ln());
    Ok(Inverse {
        tissue_e_pa: e,
        e_rel_per_v_rel: 1.0 / dlnv.abs(),
        evaluations: evals,
    })
}
