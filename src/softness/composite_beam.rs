//! Composite-beam softness model (paper 001, sec. 3.2, Eq. 7-12), constants re-derived.
//!
//! Section of breadth b: tissue 0 <= z <= t_t on top of the plate t_t <= z <= t_t + t_b (z down
//! from the tissue top). Neutral axis depth (first moment of the transformed section vanishes):
//!   c = (E_t t_t^2 / 2 + E_b t_b (t_t + t_b / 2)) / (E_t t_t + E_b t_b).
//! Eq. 7 (moment-curvature, Beer et al.): M R = E_t b ((t_t - c)^3 + c^3) / 3 + E_b b ((t_t + t_b -
//! c)^3 - (t_t - c)^3) / 3. Eq. 8: the equivalent beam of thickness t_t, M R = E_eq b t_t^3 / 12,
//! so Eq. 9 reads   E_eq = C1 E_t + C2,  C1 = 4 ((t_t - c)^3 + c^3) / t_t^3,  C2 = 4 E_b ((t_t +
//! t_b - c)^3 - (t_t - c)^3) / t_t^3 (the printed C1 = (4 b t_b^3 - 4 b c^3)/(b t_b^3) mixes t_b
//! for t_t and drops terms; c depends on E_t, so C1 and C2 are constants only for a given tissue).
//! Eq. 11: clamped-clamped under q, z(y) = q y^2 (lambda - y)^2 / (24 E_eq I_t); Eq. 12: z_mid = C3
//! / (C4 E_t + C5), C3 = q lambda^4, C4 = 384 I_t C1, C5 = 384 I_t C2, I_t = b t_t^3 / 12.
//! Moduli: plane-strain (wide section) E_t / (1 - nu_t^2) for the tissue and Q22 for the plate, as
//! the FE. Read-out: plate bottom-fibre strain eps = d_bot kappa, d_bot = t_t + t_b - c, kappa =
//! -z''.

use serde::Serialize;

use crate::softness::SoftnessSetup;

/// The composite beam of a setup and a tissue modulus (per unit breadth).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CompositeBeam {
    pub span_m: f64,
    pub tb_m: f64,
    pub eb_pa: f64,
    pub tt_m: f64,
    /// Effective (plane-strain) tissue modulus E_t / (1 - nu^2).
    pub et_pa: f64,
}

impl CompositeBeam {
    pub fn new(s: &SoftnessSetup, tissue_e_pa: f64) -> Self {
        CompositeBeam {
            span_m: s.span_m,
            tb_m: s.plate_thickness_m,
            eb_pa: s.plate_modulus_pa,
            tt_m: s.tissue_thickness_m,
            et_pa: tissue_e_pa / (1.0 - s.tissue_nu * s.tissue_nu),
        }
    }
    /// Neutral-axis depth c from the tissue top (m).
    pub fn neutral_axis_m(&self) -> f64 {
        let (et, eb, tt, tb) = (self.et_pa, self.eb_pa, self.tt_m, self.tb_m);
        (et * tt * tt / 2.0 + eb * tb * (tt + tb / 2.0)) / (et * tt + eb * tb)
    }
    /// (C1, C2) of Eq. 9 as re-derived.
    pub fn c1_c2(&self) -> (f64, f64) {
        let (c, tt, tb) = (self.neutral_axis_m(), self.tt_m, self.tb_m);
        let t3 = tt.powi(3);
        (
            4.0 * ((tt - c).powi(3) + c.powi(3)) / t3,
            4.0 * self.eb_pa * ((tt + tb - c).powi(3) - (tt - c).powi(3)) / t3,
        )
    }
    /// E_eq I_t per unit breadth (N m), Eq. 8-9.
    pub fn ei_eq(&self) -> f64 {
        let (c1, c2) = self.c1_c2();
        (c1 * self.et_pa + c2) * self.tt_m.powi(3) / 12.0
    }
    /// Eq. 12: mid-span deflection (m, along the load) under pressure q (Pa).
    pub fn mid_deflection_m(&self, q_pa: f64) -> f64 {
        let (c1, c2) = self.c1_c2();
        let it = self.tt_m.powi(3) / 12.0;
        q_pa * self.span_m.powi(4) / (384.0 * it * c1 * self.et_pa + 384.0 * it * c2)
    }
    /// Slope z'(y) of Eq. 11: q y (lambda - y)(lambda - 2 y) / (12 E_eq I_t).
    pub fn slope(&self, q_pa: f64, y_m: f64) -> f64 {
        let l = self.span_m;
        q_pa * y_m * (l - y_m) * (l - 2.0 * y_m) / (12.0 * self.ei_eq())
    }
    /// int eps dy of the plate's bottom fibre over [s0, s1] = -d_bot (z'(s1) - z'(s0)).
    pub fn strain_integral_m(&self, q_pa: f64, s0_m: f64, s1_m: f64) -> f64 {
        let d_bot = self.tt_m + self.tb_m - self.neutral_axis_m();
        -d_bot * (self.slope(q_pa, s1_m) - self.slope(q_pa, s0_m))
    }
}

/// Middle-electrode voltage (V) of the composite-beam model.
pub fn voltage_v(s: &SoftnessSetup, tissue_e_pa: f64, force_n: f64) -> f64 {
    let b = CompositeBeam::new(s, tissue_e_pa);
    s.volts_per_strain_m
        * b.strain_integral_m(s.pressure_pa(force_n), s.electrode_s0_m, s.electrode_s1_m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam(et: f64) -> CompositeBeam {
        CompositeBeam {
            span_m: 0.01,
            tb_m: 100e-6,
            eb_pa: 169.76e9,
            tt_m: 5e-3,
            et_pa: et,
        }
    }

    /// Eq. 9/12 against the transformed section summed directly, and the two limits: no tissue
    /// gives the bare plate (E_b t_b^3 / 12), a tissue of the plate's modulus gives one solid
    /// layer.
    #[test]
    fn constants_against_the_section() {
        for et in [1e3, 1e5, 1e7, 1e9] {
            let b = beam(et);
            let c = b.neutral_axis_m();
            // Direct: EI = sum E_i int (z - c)^2 dz by 200-point midpoint per layer.
            let layer = |e: f64, z0: f64, z1: f64| -> f64 {
                (0..2000)
                    .map(|k| {
                        let z = z0 + (z1 - z0) * (k as f64 + 0.5) / 2000.0;
                        e * (z - c).powi(2) * (z1 - z0) / 2000.0
                    })
                    .sum()
            };
            let direct = layer(et, 0.0, b.tt_m) + layer(b.eb_pa, b.tt_m, b.tt_m + b.tb_m);
            assert!((b.ei_eq() / direct - 1.0).abs() < 1e-6, "{et}");
            // Neutral axis: zero first moment.
            let m1 = et * ((b.tt_m - c).powi(2) - c * c) / 2.0
                + b.eb_pa * ((b.tt_m + b.tb_m - c).powi(2) - (b.tt_m - c).powi(2)) / 2.0;
            assert!(m1.abs() < 1e-9 * b.eb_pa * b.tb_m * b.tt_m);
            // Eq. 12 equals Eq. 11 at mid-span.
            let q = 100.0;
            let z11 = q * (0.005f64).powi(4) / (24.0 * b.ei_eq());
            assert!((b.mid_deflection_m(q) / z11 - 1.0).abs() < 1e-12);
        }
        let bare = beam(1e-9);
        assert!((bare.ei_eq() / (169.76e9 * 1e-12 / 12.0) - 1.0).abs() < 1e-9);
        let solid = CompositeBeam {
            et_pa: 169.76e9,
            ..beam(0.0)
        };
        assert!((solid.ei_eq() / (169.76e9 * (5.1e-3f64).powi(3) / 12.0) - 1.0).abs() < 1e-12);
        // Bottom-fibre strain of the bare plate at mid-span: (t_b / 2) q lambda^2 / (24 D).
        let (q, l) = (100.0, 0.01);
        let eps_mid = -(bare.slope(q, 0.5 * l + 1e-7) - bare.slope(q, 0.5 * l - 1e-7)) / 2e-7
            * (bare.tt_m + bare.tb_m - bare.neutral_axis_m());
        assert!(
            (eps_mid / (50e-6 * q * l * l / (24.0 * 169.76e9 * 1e-12 / 12.0)) - 1.0).abs() < 1e-6
        );
    }
}
