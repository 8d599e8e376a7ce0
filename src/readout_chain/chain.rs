//! Nine channels in time: each electrode a charge source Q_i(t) = S_i F(t) (quasi-static and
//! linear: the plate answers far faster than the force changes, see `fe::modal`) behind its front
//! end, a first-order high-pass.

use serde::Serialize;

use super::front_end::{corner_hz, Amplifier};
use super::high_pass::high_pass;

/// What one electrode contributes: its charge per newton at the load point and its capacitance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Source {
    pub name: String,
    pub charge_pc_per_n: f64,
    pub capacitance_pf: f64,
}

/// One channel's record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Channel {
    pub name: String,
    pub charge_pc_per_n: f64,
    pub capacitance_pf: f64,
    /// Output per newton in the pass band (sign included: the charge amplifier inverts), V/N.
    pub pass_band_v_per_n: f64,
    pub tau_s: f64,
    pub corner_hz: f64,
    /// The output voltage at every sample, V.
    #[serde(skip)]
    pub voltage_v: Vec<f64>,
}

/// The output of every channel for the force history `force_n` sampled at `t_s`.
///
/// V_i = H(gain_i S_i F) with H the high-pass of tau_i and gain_i the front end's volts per
/// coulomb ([`Amplifier::gain_v_per_c`]); the filter is linear, so the force is filtered once
/// per distinct tau and scaled.
#[track_caller]
pub fn run(sources: &[Source], amp: &Amplifier, t_s: &[f64], force_n: &[f64]) -> Vec<Channel> {
    let mut filtered: Vec<(f64, Vec<f64>)> = Vec::new();
    sources
        .iter()
        .map(|s| {
            let c_f = s.capacitance_pf * 1e-12;
            let tau = amp.tau_s(c_f);
            let gain = amp.gain_v_per_c(c_f) * s.charge_pc_per_n * 1e-12;
            let k = match filtered.iter().position(|(t, _)| *t == tau) {
                Some(k) => k,
                None => {
                    filtered.push((tau, high_pass(t_s, force_n, tau)));
                    filtered.len() - 1
                }
            };
            Channel {
                name: s.name.clone(),
                charge_pc_per_n: s.charge_pc_per_n,
                capacitance_pf: s.capacitance_pf,
                pass_band_v_per_n: gain,
                tau_s: tau,
                corner_hz: corner_hz(tau),
                // + 0.0 turns -0.0 (a negative gain times a zero) into 0.0 for the CSV.
                voltage_v: filtered[k].1.iter().map(|h| gain * h + 0.0).collect(),
            }
        })
        .collect()
}

/// How much of a held grasp's signal is left: the channel's voltage when the hold begins and at
/// the end of the record, their ratio, and the first-order prediction e^(-(t_end - t_hold) /
/// tau) it should equal once the closing transient is over.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldDecay {
    pub channel: String,
    pub hold_start_s: f64,
    pub end_s: f64,
    pub voltage_at_hold_v: f64,
    pub voltage_at_end_v: f64,
    pub fraction_left: f64,
    pub predicted_fraction: f64,
}

/// The decay of the channel with the largest |V| at the start of the hold.
pub fn held_decay(channels: &[Channel], t_s: &[f64], hold_start_s: f64) -> Option<HeldDecay> {
    let k = t_s.iter().position(|&t| t >= hold_start_s)?;
    let end = t_s.len() - 1;
    let c = channels
        .iter()
        .max_by(|a, b| a.voltage_v[k].abs().total_cmp(&b.voltage_v[k].abs()))?;
    let (v0, v1) = (c.voltage_v[k], c.voltage_v[end]);
    Some(HeldDecay {
        channel: c.name.clone(),
        hold_start_s: t_s[k],
        end_s: t_s[end],
        voltage_at_hold_v: v0,
        voltage_at_end_v: v1,
        fraction_left: if v0 != 0.0 { v1 / v0 } else { 0.0 },
        predicted_fraction: (-(t_s[end] - t_s[k]) / c.tau_s).exp(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sources() -> Vec<Source> {
        vec![
            Source {
                name: "A".into(),
                charge_pc_per_n: 200.0,
                capacitance_pf: 400.0,
            },
            Source {
                name: "B".into(),
                charge_pc_per_n: -50.0,
                capacitance_pf: 100.0,
            },
        ]
    }

    #[test]
    fn charge_amplifier_gain_and_corner() {
        let amp = Amplifier::ChargeAmplifier {
            feedback_capacitance_f: 1e-9,
            feedback_resistance_ohm: 1e10,
        };
        let t: Vec<f64> = (0..=100).map(|k| k as f64 * 1e-4).collect();
        let f: Vec<f64> = t.iter().map(|&t| 2.0 * t / 1e-2).collect();
        let ch = run(&sources(), &amp, &t, &f);
        // -Q / C_f: 200 pC/N over 1 nF is -0.2 V/N, whatever the electrode's capacitance.
        assert!((ch[0].pass_band_v_per_n + 0.2).abs() < 1e-15);
        assert!((ch[1].pass_band_v_per_n - 0.05).abs() < 1e-15);
        assert!((ch[0].tau_s - 10.0).abs() < 1e-12 && ch[0].tau_s == ch[1].tau_s);
        assert!((ch[0].corner_hz - 1.0 / (20.0 * std::f64::consts::PI)).abs() < 1e-15);
        // 10 ms of a 10 s filter: the output is the pass-band value to 0.1 %.
        let v = *ch[0].voltage_v.last().unwrap();
        assert!((v / (-0.2 * 2.0) - 1.0).abs() < 1e-3, "{v}");
    }

    #[test]
    fn voltage_readout_divides_by_electrode_plus_cable_and_each_has_its_tau() {
        let amp = Amplifier::VoltageReadout {
            input_resistance_ohm: 1e6,
            cable_capacitance_f: 100e-12,
        };
        let ch = run(&sources(), &amp, &[0.0, 1e-9], &[0.0, 1.0]);
        assert!((ch[0].pass_band_v_per_n - 200e-12 / 500e-12).abs() < 1e-12);
        assert!((ch[1].tau_s - 1e6 * 200e-12).abs() < 1e-18);
        assert!((ch[0].tau_s - 1e6 * 500e-12).abs() < 1e-18);
        // A 1 ns ramp is a step to the pass-band value.
        assert!((ch[1].voltage_v[1] + 50e-12 / 200e-12).abs() < 1e-6);
    }

    #[test]
    fn output_is_linear_in_the_force() {
        let amp = Amplifier::ChargeAmplifier {
            feedback_capacitance_f: 1e-9,
            feedback_resistance_ohm: 1e9,
        };
        let t: Vec<f64> = (0..=500).map(|k| k as f64 * 1e-2).collect();
        let f: Vec<f64> = t.iter().map(|&t| (3.0 * t).sin() + 0.5).collect();
        let f3: Vec<f64> = f.iter().map(|v| -3.0 * v).collect();
        let a = run(&sources(), &amp, &t, &f);
        let b = run(&sources(), &amp, &t, &f3);
        for (ca, cb) in a.iter().zip(&b) {
            for (va, vb) in ca.voltage_v.iter().zip(&cb.voltage_v) {
                assert!((vb + 3.0 * va).abs() <= 1e-12 * va.abs().max(1e-3));
            }
        }
    }

    #[test]
    fn a_held_force_decays_as_predicted() {
        let amp = Amplifier::ChargeAmplifier {
            feedback_capacitance_f: 1e-9,
            feedback_resistance_ohm: 1e9,
        };
        let t: Vec<f64> = (0..=5000).map(|k| k as f64 * 1e-3).collect();
        let f: Vec<f64> = t.iter().map(|&t| (t / 0.01).min(1.0)).collect();
        let ch = run(&sources(), &amp, &t, &f);
        let d = held_decay(&ch, &t, 0.01).unwrap();
        assert_eq!(d.channel, "A");
        assert!((d.fraction_left - d.predicted_fraction).abs() < 1e-12);
        assert!((d.predicted_fraction - (-4.99f64).exp()).abs() < 1e-12);
    }
}
