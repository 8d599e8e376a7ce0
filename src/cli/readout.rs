//! `tactfab readout FILE -o DIR`: the nine channels' voltages in time for a force history at one
//! point ([`tactfab::readout_chain::study`]), as a table of gains and corners, the held grasp's
//! decay, and `DIR/readout.csv` + `DIR/readout.svg`.

use std::fmt::Write as _;

use anyhow::Context;

use tactfab::readout_chain::{study, Amplifier, ReadoutSpec, ReadoutStudy};
use tactfab::sensor::{Accuracy, SensorGeometry};

use super::args::ReadoutArgs;
use super::output::f;
use super::{check_out, design, write_dir, Outcome};

pub fn run(a: &ReadoutArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&a.process)?;
    super::warn_process_errors(&a.process, &design);
    check_out(&a.out, a.replace, &a.process)?;
    let g = SensorGeometry::new(&design);
    let spec = ReadoutSpec {
        x_um: a.x_mm.map_or(g.length_um / 2.0, |x| x * 1000.0),
        y_um: a.y_mm.map_or(g.width_um / 2.0, |y| y * 1000.0),
        contact_radius_um: a.contact_radius_mm * 1000.0,
        history: a.history.into(),
        force_n: a.force_n,
        duration_s: a.duration_s,
        dt_s: a.dt_ms * 1e-3,
        accuracy: Accuracy::new(a.tol, usize::from(a.max_levels)),
    };
    let s = study(&g, &design.process.readout, &spec).with_context(|| {
        format!(
            "the load at --x-mm {} --y-mm {}",
            spec.x_um / 1000.0,
            spec.y_um / 1000.0
        )
    })?;
    let files = [
        ("readout.csv".to_string(), s.csv().into_bytes()),
        ("readout.svg".to_string(), s.svg().into_bytes()),
    ];
    write_dir(&a.out, &files, a.replace, &a.process)?;
    print!("{}", text(&s));
    println!(
        "wrote {} and {}",
        a.out.join("readout.csv").display(),
        a.out.join("readout.svg").display()
    );
    Ok(Outcome::Ok)
}

fn text(s: &ReadoutStudy) -> String {
    let mut out = String::new();
    let sp = &s.spec;
    let _ = writeln!(
        out,
        "readout: {} history, {} N at ({}, {}) mm, {} s every {} ms ({} samples)",
        sp.history.name(),
        sp.force_n,
        f(sp.x_um / 1000.0, 3),
        f(sp.y_um / 1000.0, 3),
        s.duration_s,
        sp.dt_s * 1e3,
        s.t_s.len()
    );
    let part =
        |v: Option<f64>| v.map_or_else(|| "not estimated".to_string(), |e| format!("{e:.1e}"));
    let _ = writeln!(
        out,
        "  sensitivities: 1 N on the {} ({} levels, {} dofs), error discretisation {} + model {} \
         (the linear plate against the large-deflection plate at 1 N: the chain is linear in F, \
         the plate is not)",
        s.sensitivity.model,
        s.sensitivity.levels,
        s.sensitivity.dofs,
        part(s.sensitivity.error.discretisation),
        part(s.sensitivity.error.model)
    );
    let _ = match s.amplifier {
        Amplifier::ChargeAmplifier {
            feedback_capacitance_f,
            feedback_resistance_ohm,
        } => writeln!(
            out,
            "  front end: charge amplifier, C_f {} pF, R_f {} GΩ: V = -Q / C_f above the \
             corner, tau = R_f C_f",
            f(feedback_capacitance_f * 1e12, 1),
            f(feedback_resistance_ohm * 1e-9, 3)
        ),
        Amplifier::VoltageReadout {
            input_resistance_ohm,
            cable_capacitance_f,
        } => writeln!(
            out,
            "  front end: voltage read-out, R_in {} MΩ, cable {} pF: V = Q / (C_e + C_cable) \
             above the corner, tau = R_in (C_e + C_cable) per electrode",
            f(input_resistance_ohm * 1e-6, 3),
            f(cable_capacitance_f * 1e12, 1)
        ),
    };
    if let Some(c) = s.channels.first() {
        let _ = writeln!(
            out,
            "  first channel: tau {:.4e} s, corner f_c {:.4e} Hz; steady gain {:.6} (phase lead \
             {:.3} deg) at the 5 Hz test, {:.6} ({:.3} deg) at the 1 Hz pulse",
            c.tau_s,
            c.corner_hz,
            s.at_test.0,
            s.at_test.1.to_degrees(),
            s.at_pulse.0,
            s.at_pulse.1.to_degrees()
        );
    }
    let _ = writeln!(
        out,
        "  electrode   S_pc_per_n   C_e_pf   pass_band_v_per_n      tau_s     f_c_hz     v_min_v     \
         v_max_v"
    );
    for c in &s.channels {
        let (lo, hi) = c
            .voltage_v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        let _ = writeln!(
            out,
            "  {:<9} {:>12} {:>8} {:>19} {:>10.4e} {:>10.4e} {:>11.4e} {:>11.4e}",
            c.name,
            f(c.charge_pc_per_n, 3),
            f(c.capacitance_pf, 1),
            f(c.pass_band_v_per_n, 6),
            c.tau_s,
            c.corner_hz,
            lo,
            hi
        );
    }
    if let Some(h) = &s.held {
        let _ = writeln!(
            out,
            "  held grasp: {} falls from {:.4e} V when the jaws stop closing ({} s) to {:.4e} V at {} s: \
             {} % left (e^(-t / tau) predicts {} %): PVDF senses change, and the front end \
             bleeds the held charge through its resistor",
            h.channel,
            h.voltage_at_hold_v,
            f(h.hold_start_s, 3),
            h.voltage_at_end_v,
            f(h.end_s, 3),
            f(100.0 * h.fraction_left, 2),
            f(100.0 * h.predicted_fraction, 2)
        );
    }
    out
}
