//! The cheapest model: the sensor as a fixed-fixed strip (paper 001, Eq. 3-6) in cylindrical
//! bending, for a line load across the whole length of a plate of uniform thickness.
//!
//! Far from the free ends such a plate bends cylindrically (kappa_x = 0), so per unit length in x
//! it is a clamped-clamped beam of stiffness D22: the reactions are those of Eq. 3-6 (independent
//! of the stiffness), the moment is piecewise linear, and every electrode reading follows in closed
//! form. Near the free ends the plate is free to bend anticlastically (M_x = 0, kappa_x =
//! -D12/D11 kappa_y) over a boundary layer about one span wide; that is the model's error, bounded
//! by [`beam_error_estimate`] and checked against the plate in the tests.

use crate::fe::fixed_fixed_reactions;
use crate::process::Axis;

use super::geometry::{ElectrodeSide, SensorGeometry};
use super::readout::{ElectrodeReading, Readout};

/// What the strip model answers for one line load.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamAnswer {
    pub readout: Readout,
    pub deflection_at_load_m: f64,
    pub max_deflection_m: f64,
    /// Largest bending stress at the load line, sigma = 6 M / t^2 (cylindrical bending).
    pub stress_at_load_pa: f64,
}

/// True when the strip model describes the scene: a line load across the whole length, strictly
/// inside the span, on a plate without teeth (uniform D along the span), clamped at the walls.
pub fn beam_applies(g: &SensorGeometry, y_um: f64) -> bool {
    // The strip is clamped at both walls: no rung for the elastic footing.
    g.teeth.is_empty()
        && y_um > g.plate_y0_um
        && y_um < g.plate_y1_um
        && g.support_model == crate::process::SupportModel::Clamped
}

/// Estimated relative error of the strip readings against the plate.
///
/// At each free end the plate bends anticlastically (M_x = 0): the strain there changes by
/// kappa_x / kappa_y = D12 / D11, which moves an extension-mode reading by (D12/D11)(nu_pvdf +
/// |d32/d31|) and redistributes the reactions under the end electrodes by about D12/D11. The edge
/// zone is taken as half a span wide, so an electrode of length l_e sees it over a fraction
/// min(1, lambda / (2 l_e)); the shortest electrode sets the bound:
/// e = (D12/D11)(nu_pvdf + |d32/d31| + 1) min(1, lambda / (2 l_e)).
/// This is an engineering bound, not a theorem: the tests check it against the converged plate on
/// designs of different span, length and thickness (lambda / pi was too narrow for a 15 mm span).
pub fn beam_error_estimate(g: &SensorGeometry) -> f64 {
    let d = g.material.bending_stiffness(g.plate_thickness_um * 1e-6);
    let coupling = (d.d12_nm / d.d11_nm).abs();
    let span = g.plate_y1_um - g.plate_y0_um;
    let shortest = g
        .electrodes
        .iter()
        .map(|e| e.x1_um - e.x0_um)
        .fold(f64::INFINITY, f64::min);
    let ratio = if g.d31_pc_per_n != 0.0 {
        (g.d32_pc_per_n / g.d31_pc_per_n).abs()
    } else {
        1.0
    };
    coupling * (g.pvdf_nu + ratio + 1.0) * (span / (2.0 * shortest)).min(1.0)
}

/// Clamped-clamped strip of span lambda with a point load P (per unit length in x) at a from
/// support 1, b = lambda - a: end moment M1 = -P a b^2 / lambda^2 and the moment
/// M(s) = M1 + R1 s - P <s - a> (sagging positive; Roark's Formulas, Table 8.1 case 1d).
fn moment(p: f64, a: f64, span: f64, s: f64) -> f64 {
    let b = span - a;
    let r1 = fixed_fixed_reactions(p, a, span).r1;
    -p * a * b * b / (span * span) + r1 * s - if s > a { p * (s - a) } else { 0.0 }
}

/// Integral of M(s) over [s0, s1]: M is linear on either side of the load, so the trapezoid rule
/// on the pieces is exact.
fn moment_integral(p: f64, a: f64, span: f64, s0: f64, s1: f64) -> f64 {
    let mut cuts = vec![s0];
    if a > s0 && a < s1 {
        cuts.push(a);
    }
    cuts.push(s1);
    cuts.windows(2)
        .map(|w| 0.5 * (moment(p, a, span, w[0]) + moment(p, a, span, w[1])) * (w[1] - w[0]))
        .sum()
}

/// Readings of all electrodes for `force_n` spread over the whole length at `y_um`.
#[track_caller]
pub fn beam_answer(g: &SensorGeometry, y_um: f64, force_n: f64) -> BeamAnswer {
    assert!(
        beam_applies(g, y_um),
        "the strip model needs a line load inside the span of a plate without teeth"
    );
    let um = 1e-6;
    let span = (g.plate_y1_um - g.plate_y0_um) * um;
    let a = (y_um - g.plate_y0_um) * um;
    let b = span - a;
    let length = g.length_um * um;
    let p = force_n / length; // N per metre of length
    let t = g.plate_thickness_um * um;
    let d22 = g.material.bending_stiffness(t).d22_nm;
    let r = fixed_fixed_reactions(force_n, a, span);
    let ep = g.pvdf_e_pa / (1.0 - g.pvdf_nu * g.pvdf_nu);
    let mut electrodes = Vec::new();
    for e in &g.electrodes {
        let c_f = g.capacitance_f(e.area_um2);
        let along = ((e.x1_um.min(g.length_um) - e.x0_um.max(0.0)) / g.length_um).max(0.0);
        let (charge_pc, force) = match e.side {
            ElectrodeSide::Middle => {
                // int eps_y dA = l_e z int M / D22 ds at the film's mid-plane, z = (t + t_f) / 2
                // (as the plate rungs read it); eps_x = 0 (cylindrical bending).
                let s0 = ((e.y0_um - g.plate_y0_um) * um).clamp(0.0, span);
                let s1 = ((e.y1_um - g.plate_y0_um) * um).clamp(0.0, span);
                let z = 0.5 * (t + g.film_thickness_um * um);
                let iy = (e.x1_um - e.x0_um) * um * z * moment_integral(p, a, span, s0, s1) / d22;
                let (sx, sy) = (ep * g.pvdf_nu * iy, ep * iy);
                let (s1_, s2_) = match g.drawn_axis {
                    Axis::Y => (sy, sx),
                    Axis::X => (sx, sy),
                };
                (g.d31_pc_per_n * s1_ + g.d32_pc_per_n * s2_, None)
            }
            ElectrodeSide::Support1 => (g.d33_pc_per_n * r.r1 * along, Some(r.r1 * along)),
            ElectrodeSide::Support2 => (g.d33_pc_per_n * r.r2 * along, Some(r.r2 * along)),
        };
        electrodes.push(ElectrodeReading {
            name: e.name.clone(),
            charge_pc,
            voltage_mv: charge_pc * 1e-12 / c_f * 1e3,
            force_n: force,
        });
    }
    // w(a) = P a^3 b^3 / (3 D lambda^3); w_max = 2 P a^3 b^2 / (3 D (lambda + 2a)^2) at
    // s = 2 a lambda / (lambda + 2 a) for a >= b (Roark, Table 8.1 case 1d; mirrored for a < b).
    let w_at = p * a.powi(3) * b.powi(3) / (3.0 * d22 * span.powi(3));
    let (long, short) = if a >= b { (a, b) } else { (b, a) };
    let w_max = 2.0 * p * long.powi(3) * short.powi(2) / (3.0 * d22 * (span + 2.0 * long).powi(2));
    BeamAnswer {
        readout: Readout {
            electrodes,
            support1_n: r.r1,
            support2_n: r.r2,
        },
        deflection_at_load_m: w_at,
        max_deflection_m: w_max,
        stress_at_load_pa: 6.0 * moment(p, a, span, a).abs() / (t * t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moment_closes_at_both_clamps() {
        // M(lambda) must equal the other fixed-end moment -P a^2 b / lambda^2.
        let (p, a, l) = (3.0, 0.3, 1.0);
        let b = l - a;
        assert!((moment(p, a, l, l) + p * a * a * b / (l * l)).abs() < 1e-12);
        // Centre load: M(a) = P L / 8 (sagging), ends -P L / 8.
        assert!((moment(2.0, 0.5, 1.0, 0.5) - 0.25).abs() < 1e-12);
        assert!((moment(2.0, 0.5, 1.0, 0.0) + 0.25).abs() < 1e-12);
        // Zero end slopes: int M ds = 0 over a clamped-clamped span (first moment-area theorem).
        assert!(moment_integral(p, a, l, 0.0, l).abs() < 1e-12);
    }

    #[test]
    fn maximum_deflection_formula_matches_sampling() {
        // w(s) from double integration of M / D with clamped ends, sampled on a fine grid.
        let (p, a, l, d) = (1.0, 0.3, 1.0, 1.0);
        let n = 20000;
        let h = l / n as f64;
        let (mut slope, mut w, mut wmax) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..n {
            let s = (k as f64 + 0.5) * h;
            slope += moment(p, a, l, s) / d * h;
            w += slope * h;
            wmax = wmax.max(w.abs());
        }
        let b = l - a;
        let long = a.max(b);
        let short = a.min(b);
        let formula = 2.0 * p * long.powi(3) * short.powi(2) / (3.0 * d * (l + 2.0 * long).powi(2));
        assert!(
            (wmax - formula).abs() < 1e-4 * formula,
            "{wmax} vs {formula}"
        );
    }
}
