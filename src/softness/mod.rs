//! Softness of a grasped object from the middle electrode (paper 001, sec. 3.2, 4.3.2, 5.2; Fig.
//! 24).
//!
//! A tissue layer (E_t 1e4 - 1e8 Pa, nu 0.49, thickness t_t) lies on the plate span between the two
//! supports; a distributed load F acts on its top over the span x die length. The middle PVDF
//! electrode under the plate reads the plate's bottom-surface strain across the span. Two models of
//! the same cross-section (cylindrical bending across the span, plane strain along the die length):
//!
//! - [`composite_beam`]: paper 001 Eq. 7-12 (transformed section, constants re-derived: the printed
//!   Eq. 9 has typesetting errors), closed form.
//! - [`tissue_fe`]: plane-strain FE of the tissue with locking-free Q2/P1 (B-bar) elements
//!   ([`continuum`]) tied to an Euler-Bernoulli frame model of the Si plate, clamped at the
//!   supports.
//!
//! [`inverse`] recovers E_t from a voltage and a force with either model. [`inclusion`] squeezes a
//! tissue slab with a hidden lump, void or pressurised vessel between the jaws (paper 002 Figs.
//! 8-10); [`mapped`] is the same Q2/P1 element on curved meshes, and [`kirsch`] checks it against
//! the stress concentration 3 at a circular hole. [`axisym`] is the axisymmetric Q2/P1 element,
//! [`axislab`] the spherical lump or void on the axis of a tissue cylinder between the jaws (the
//! 3-D scene by axisymmetry), and [`far_field`] checks both elements against Goodier's spherical
//! cavity and Eshelby's spherical and cylindrical inclusions. [`slab3d`] is the 3-D block of
//! tissue across the jaw (free sides) with a sphere anywhere, on the Q2/P1 (B-bar) brick of
//! [`hex_bbar`]; [`slab3d_out`] writes its face field.
//!
//! Both models assume perfect bonding between tissue and plate, linear elasticity, and neglect the
//! PVDF film's own stiffness (25 um, 3 GPa against 100 um Si: < 0.5 % of the bending stiffness).

pub mod axislab;
pub mod axisym;
pub mod composite_beam;
pub mod continuum;
pub mod far_field;
pub mod hex_bbar;
pub mod inclusion;
pub mod inverse;
pub mod kirsch;
pub mod mapped;
pub mod plot;
pub mod slab3d;
pub mod slab3d_out;
pub mod sphere_mesh;
pub mod study;
pub mod tissue_fe;

use serde::Serialize;
use thiserror::Error;

use crate::sensor::{ElectrodeSide, SensorGeometry};

/// Softness errors; each carries a hint.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SoftnessError {
    #[error("sparse solver failed ({detail})\n  hint: {hint}")]
    Solver { detail: String, hint: &'static str },
    #[error("no middle electrode over the die centre\n  hint: {hint}")]
    NoMiddleElectrode { hint: &'static str },
    #[error(
        "voltage per force {v_per_n:.4e} V/N is outside the model's range [{lo:.4e}, {hi:.4e}] \
         for E in [{e_lo_pa:.3e}, {e_hi_pa:.3e}] Pa\n  hint: {hint}"
    )]
    OutOfRange {
        v_per_n: f64,
        lo: f64,
        hi: f64,
        e_lo_pa: f64,
        e_hi_pa: f64,
        hint: &'static str,
    },
    #[error("invalid input {field} = {value}\n  hint: {hint}")]
    BadInput {
        field: &'static str,
        value: f64,
        hint: &'static str,
    },
}

/// Paper 001 sec. 4.3.2: nu = 0.49 for the nearly incompressible tissue.
pub const TISSUE_NU: f64 = 0.49;
/// \[choice\] Tissue thickness: paper 001 gives none (Fig. 22 shows a block several times the plate's
/// thickness); 5 mm, half the span, a grasped bowel wall / organ slab. A CLI flag changes it.
pub const TISSUE_THICKNESS_UM: f64 = 5000.0;

/// The cross-section both models share (SI units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SoftnessSetup {
    /// Clamped span: the channel floor between the etched {111} walls (m).
    pub span_m: f64,
    /// Die length over which the load is distributed (m): pressure = F / (span x length).
    pub loaded_length_m: f64,
    pub plate_thickness_m: f64,
    /// Plate modulus for bending across the span with no strain along the die length: Q22 (Pa).
    pub plate_modulus_pa: f64,
    pub tissue_thickness_m: f64,
    pub tissue_nu: f64,
    /// Middle electrode across the span, from the span's start (m).
    pub electrode_s0_m: f64,
    pub electrode_s1_m: f64,
    /// V = volts_per_strain_m x int eps ds over the electrode, where int runs across the span (m).
    pub volts_per_strain_m: f64,
    pub electrode_name: String,
}

impl SoftnessSetup {
    /// From the sensor geometry (the PVDF mask's middle electrode over the die centre).
    /// Charge Q = int (d31 s1 + d32 s2) dA over the electrode, PVDF plane stress with the film
    /// strain (eps_span, 0): s_span = E/(1-nu^2) eps, s_other = nu E/(1-nu^2) eps
    /// (fe-validation.md); the span is the die's y axis, so d31 goes with it when the drawn
    /// axis is y. V = Q / C, C = eps0 eps_r A / t.
    pub fn from_sensor(
        g: &SensorGeometry,
        tissue_thickness_um: f64,
        tissue_nu: f64,
    ) -> Result<Self, SoftnessError> {
        if !(tissue_thickness_um > 0.0 && tissue_thickness_um.is_finite()) {
            return Err(SoftnessError::BadInput {
                field: "tissue_thickness_um",
                value: tissue_thickness_um,
                hint: "a positive thickness in um, e.g. 5000",
            });
        }
        if !(tissue_nu > -1.0 && tissue_nu < 0.5) {
            return Err(SoftnessError::BadInput {
                field: "tissue_nu",
                value: tissue_nu,
                hint: "Poisson's ratio in (-1, 0.5), e.g. 0.49",
            });
        }
        let xc = 0.5 * g.length_um;
        let e = g
            .electrodes
            .iter()
            .find(|e| e.side == ElectrodeSide::Middle && e.x0_um <= xc && e.x1_um >= xc)
            .ok_or(SoftnessError::NoMiddleElectrode {
                hint: "the PVDF mask needs a middle island over the die centre",
            })?;
        let (d_span, d_other) = match g.drawn_axis {
            crate::process::Axis::Y => (g.d31_pc_per_n, g.d32_pc_per_n),
            crate::process::Axis::X => (g.d32_pc_per_n, g.d31_pc_per_n),
        };
        let ebar = g.pvdf_e_pa / (1.0 - g.pvdf_nu * g.pvdf_nu);
        let charge_per_strain_m =
            ebar * (d_span + g.pvdf_nu * d_other) * 1e-12 * (e.x1_um - e.x0_um) * 1e-6;
        let (s0, s1) = (
            (e.y0_um.max(g.plate_y0_um) - g.plate_y0_um) * 1e-6,
            (e.y1_um.min(g.plate_y1_um) - g.plate_y0_um) * 1e-6,
        );
        Ok(SoftnessSetup {
            span_m: (g.plate_y1_um - g.plate_y0_um) * 1e-6,
            loaded_length_m: g.length_um * 1e-6,
            plate_thickness_m: g.plate_thickness_um * 1e-6,
            plate_modulus_pa: g.material.q22_pa,
            tissue_thickness_m: tissue_thickness_um * 1e-6,
            tissue_nu,
            electrode_s0_m: s0,
            electrode_s1_m: s1,
            volts_per_strain_m: charge_per_strain_m / g.capacitance_f(e.area_um2),
            electrode_name: e.name.clone(),
        })
    }

    /// Pressure on the tissue top (Pa) for a total force (N).
    pub fn pressure_pa(&self, force_n: f64) -> f64 {
        force_n / (self.span_m * self.loaded_length_m)
    }
}
