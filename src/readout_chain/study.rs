//! `tactfab readout`: the nine channels' voltages in time for a force history at one point, the
//! library call behind the subcommand (sensitivities from the linear plate, the front end from
//! the process file, the history from [`super::history`]).

use serde::Serialize;

use crate::process::{Limits, ReadoutElectronics, Scene, SceneLoad};
use crate::sensor::{
    evaluate, Accuracy, ErrorParts, ModelChoice, ModelKind, SensorError, SensorGeometry,
};

use super::chain::{held_decay, run, Channel, HeldDecay, Source};
use super::front_end::{high_pass_response, Amplifier};
use super::history::{sample, HistoryKind, PULSE_RATE_HZ, TEST_FREQ_HZ};

/// What to run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ReadoutSpec {
    pub x_um: f64,
    pub y_um: f64,
    /// Contact radius of the load (the stress under a point is singular; the charges barely
    /// depend on it).
    pub contact_radius_um: f64,
    pub history: HistoryKind,
    /// Peak grasp force or sine amplitude, N.
    pub force_n: f64,
    /// Record length; None: the history's default.
    pub duration_s: Option<f64>,
    pub dt_s: f64,
    /// Accuracy of the sensitivities (always the linear plate: the chain is linear in F).
    pub accuracy: Accuracy,
}

/// Why there is no answer.
#[derive(Debug, thiserror::Error)]
pub enum ReadoutError {
    #[error("{0}")]
    Sensor(#[from] SensorError),
    #[error("{problem}\n  hint: {hint}")]
    Input { problem: String, hint: &'static str },
}

/// How the sensitivities S_i were obtained.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensitivitySource {
    pub model: ModelKind,
    pub levels: usize,
    pub dofs: usize,
    /// Discretisation and model error of the charges; the model part is the linear plate's
    /// difference from the large-deflection plate at 1 N (membrane stiffening), which this
    /// linear chain does not carry.
    pub error: ErrorParts,
}

/// The whole record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReadoutStudy {
    pub spec: ReadoutSpec,
    pub duration_s: f64,
    pub amplifier: Amplifier,
    pub sensitivity: SensitivitySource,
    pub channels: Vec<Channel>,
    #[serde(skip)]
    pub t_s: Vec<f64>,
    #[serde(skip)]
    pub force_n: Vec<f64>,
    /// What is left of the signal at the end of a held grasp (None for the sine).
    pub held: Option<HeldDecay>,
    /// Steady gain and phase lead (rad) of the first channel's high-pass at the 5 Hz test and
    /// the 1 Hz pulse.
    pub at_test: (f64, f64),
    pub at_pulse: (f64, f64),
}

/// Sensitivities at the load point (1 N on the linear plate), the front end of `electronics`,
/// the sampled history, and every channel's output.
pub fn study(
    g: &SensorGeometry,
    electronics: &ReadoutElectronics,
    spec: &ReadoutSpec,
) -> Result<ReadoutStudy, ReadoutError> {
    let duration_s = spec
        .duration_s
        .unwrap_or_else(|| spec.history.default_duration_s());
    let (t_s, force_n) =
        sample(spec.history, spec.force_n, duration_s, spec.dt_s).map_err(|problem| {
            ReadoutError::Input {
                problem,
                hint: "set --duration-s and --dt-ms so the record has at most 2,000,000 samples",
            }
        })?;
    let scene = Scene {
        name: "readout-1n".into(),
        load: SceneLoad::Point {
            x_um: spec.x_um,
            y_um: spec.y_um,
            force_n: 1.0,
            radius_um: spec.contact_radius_um,
        },
        limits: Limits::default(),
    };
    let r = evaluate(g, &scene, spec.accuracy.with_model(ModelChoice::Plate))?;
    let sources: Vec<Source> = r
        .electrodes
        .iter()
        .map(|e| {
            let area = g
                .electrodes
                .iter()
                .find(|a| a.name == e.name)
                .map_or(0.0, |a| a.area_um2);
            Source {
                name: e.name.clone(),
                charge_pc_per_n: e.charge_pc,
                capacitance_pf: g.capacitance_f(area) * 1e12,
            }
        })
        .collect();
    let amplifier = Amplifier::from_process(electronics);
    // An electrode of no area on an ideal cable has no capacitance to read it through.
    if let Some(s) = sources.iter().find(|s| {
        let c = s.capacitance_pf * 1e-12;
        let (tau, gain) = (amplifier.tau_s(c), amplifier.gain_v_per_c(c));
        !(tau > 0.0 && tau.is_finite() && gain.is_finite())
    }) {
        return Err(ReadoutError::Input {
            problem: format!(
                "electrode {} ({} pF) gives the {} no finite time constant",
                s.name,
                s.capacitance_pf,
                amplifier.name()
            ),
            hint: "give readout.cable_capacitance_pf a value or check the electrode's area",
        });
    }
    let channels = run(&sources, &amplifier, &t_s, &force_n);
    let held = spec
        .history
        .hold_start_s()
        .and_then(|h| held_decay(&channels, &t_s, h));
    let tau = channels.first().map_or(f64::INFINITY, |c| c.tau_s);
    Ok(ReadoutStudy {
        spec: *spec,
        duration_s,
        amplifier,
        sensitivity: SensitivitySource {
            model: r.model.kind,
            levels: r.model.levels,
            dofs: r.model.dofs,
            error: r.error.clone(),
        },
        channels,
        at_test: high_pass_response(TEST_FREQ_HZ, tau),
        at_pulse: high_pass_response(PULSE_RATE_HZ, tau),
        held,
        t_s,
        force_n,
    })
}

impl ReadoutStudy {
    /// `readout.csv`: time, force and every channel's voltage, units in the header.
    pub fn csv(&self) -> String {
        let mut s = String::from("t_s,F_n");
        for c in &self.channels {
            s.push_str(&format!(",V_{}_v", c.name));
        }
        s.push('\n');
        for (k, (t, f)) in self.t_s.iter().zip(&self.force_n).enumerate() {
            s.push_str(&format!("{t:.6},{f:.6e}"));
            for c in &self.channels {
                s.push_str(&format!(",{:.6e}", c.voltage_v[k]));
            }
            s.push('\n');
        }
        s
    }

    /// `readout.svg`: the force and the nine voltages against time.
    pub fn svg(&self) -> String {
        super::plot::readout_svg(self)
    }
}
