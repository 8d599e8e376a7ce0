//! The two front ends an electrode can be read through, as first-order high-pass filters: the
//! gain from charge to output voltage in the pass band and the time constant that sets the
//! low-frequency corner.

use serde::Serialize;

use crate::process::{FrontEnd, ReadoutElectronics};

/// One channel's electronics, in SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Amplifier {
    /// Charge amplifier (ideal op-amp, feedback C_f parallel R_f): V_out = -Q / C_f in the pass
    /// band, high-passed with tau = R_f C_f; the electrode's own capacitance drops out (its
    /// terminals are held at virtual ground).
    ChargeAmplifier {
        feedback_capacitance_f: f64,
        feedback_resistance_ohm: f64,
    },
    /// The electrode straight into a voltage input: V = Q / (C_e + C_cable) in the pass band,
    /// discharged through R_in, tau = R_in (C_e + C_cable).
    VoltageReadout {
        input_resistance_ohm: f64,
        cable_capacitance_f: f64,
    },
}

impl Amplifier {
    /// The front end the process file asks for (values already validated).
    pub fn from_process(r: &ReadoutElectronics) -> Self {
        match r.front_end {
            FrontEnd::ChargeAmplifier => Amplifier::ChargeAmplifier {
                feedback_capacitance_f: r.feedback_capacitance_pf * 1e-12,
                feedback_resistance_ohm: r.feedback_resistance_gohm * 1e9,
            },
            FrontEnd::VoltageReadout => Amplifier::VoltageReadout {
                input_resistance_ohm: r.input_resistance_mohm * 1e6,
                cable_capacitance_f: r.cable_capacitance_pf * 1e-12,
            },
        }
    }

    /// Output volts per coulomb of electrode charge in the pass band (above the corner):
    /// -1 / C_f for the charge amplifier (it inverts), 1 / (C_e + C_cable) for the voltage
    /// read-out of an electrode of capacitance `electrode_f`.
    pub fn gain_v_per_c(&self, electrode_f: f64) -> f64 {
        match *self {
            Amplifier::ChargeAmplifier {
                feedback_capacitance_f,
                ..
            } => -1.0 / feedback_capacitance_f,
            Amplifier::VoltageReadout {
                cable_capacitance_f,
                ..
            } => 1.0 / (electrode_f + cable_capacitance_f),
        }
    }

    /// The time constant of the high-pass, s: R_f C_f, or R_in (C_e + C_cable).
    pub fn tau_s(&self, electrode_f: f64) -> f64 {
        match *self {
            Amplifier::ChargeAmplifier {
                feedback_capacitance_f,
                feedback_resistance_ohm,
            } => feedback_resistance_ohm * feedback_capacitance_f,
            Amplifier::VoltageReadout {
                input_resistance_ohm,
                cable_capacitance_f,
            } => input_resistance_ohm * (electrode_f + cable_capacitance_f),
        }
    }

    /// Short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            Amplifier::ChargeAmplifier { .. } => "charge amplifier",
            Amplifier::VoltageReadout { .. } => "voltage read-out",
        }
    }
}

/// The -3 dB corner of a first-order high-pass, f_c = 1 / (2 pi tau), Hz.
pub fn corner_hz(tau_s: f64) -> f64 {
    1.0 / (2.0 * std::f64::consts::PI * tau_s)
}

/// Steady-state gain of the first-order high-pass at `freq_hz`: |H| = omega tau / sqrt(1 +
/// (omega tau)^2), and its phase lead atan(1 / (omega tau)) in radians (H(s) = s tau / (1 + s
/// tau)).
pub fn high_pass_response(freq_hz: f64, tau_s: f64) -> (f64, f64) {
    let wt = 2.0 * std::f64::consts::PI * freq_hz * tau_s;
    (wt / (1.0 + wt * wt).sqrt(), (1.0 / wt).atan())
}
