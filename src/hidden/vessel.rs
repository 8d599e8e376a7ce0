//! A pulsating vessel in grasped tissue (paper 002 Fig. 10; issue 17 item 3): a void whose wall
//! carries p(t) = p_mean + p_amp sin(2 pi f t) on top of the grasp, through the sensor and its
//! read-out chain.
//!
//! The slab is linear, so its face pressure is P(t) = P_grasp + p(t) W, W the face pressure per
//! pascal in the vessel with the jaws held ([`wall_pressure_face_pa`]): two slab solves for the
//! whole cycle. The linear plate too: the grasp (the vessel at zero pressure) and W, each as a
//! patches scene of the face's cells, are two scenes of one batched linear-plate solve
//! ([`cells_answers`]: one factorisation per mesh level), and V(t) = V_grasp + p(t) V_W: the
//! 20 instants of a cycle cost 20 multiply-adds, no cell unit responses. (By linearity this is
//! the sum of the cells' unit responses, [`super::cells`], on the same mesh: a test checks it.)
//! The grasp's own linear-plate model error is reported: at the default grasp it is over the
//! tolerance, where `--model auto` answers the grasp on the large-deflection plate (the full
//! scenes), so the vessel's small signal is the linear plate's. The read-out chain
//! ([`crate::readout_chain`]) then turns each electrode's charge C_i V_i(t) into its amplifier's
//! output, the record starting with the jaws closed and the amplifier reset (the grasp's own
//! transient is `tactfab readout --history half-sine`).
//!
//! Quasi-static: the plate's first natural frequency ([`plate_modes`], ~7 kHz on the bundled
//! design) is thousands of times the pulse rate; the tissue is taken as elastic (its
//! viscoelastic relaxation, seconds, is not modelled: an assumption, stated with the output).
//! Default pressures \[choice\]: 1.2 Hz, 100 mmHg mean, 40 mmHg pulse pressure (120/80 mmHg:
//! p_amp 20 mmHg); a bare void in 20 kPa tissue at 100 mmHg (13.3 kPa) strains it far beyond
//! the linear range (p / G ~ 2) and a real artery's wall carries most of the hoop stress, so the
//! magnitudes are the linear model's, not the tissue's: the shape in time is the point.

use serde::Serialize;
use std::fmt::Write as _;

use crate::process::ReadoutElectronics;
use crate::readout_chain::{run as chain, Amplifier, Channel, Source};
use crate::sensor::{
    plate_modes, Accuracy, MeshOptions, ModelChoice, SensorGeometry, MODAL_LEVELS, MODES_REPORTED,
};
use crate::softness::inclusion::{wall_pressure_face_pa, Feature};

use super::cells::CellGrid;
use super::field::{Background, Disturbance};
use super::scenes::{cells_answers, SceneAnswer};
use super::HiddenError;

/// One mmHg in Pa (the conventional millimetre of mercury, 133.322 Pa: NIST SP 811, B.8).
pub const PA_PER_MMHG: f64 = 133.322;

/// The vessel's pressure and the record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pulse {
    pub mean_pa: f64,
    pub amplitude_pa: f64,
    pub freq_hz: f64,
    /// Instants per cycle through the sensor.
    pub instants: usize,
    /// Length of the read-out record (cycles) and its sample step.
    pub cycles: f64,
    pub dt_s: f64,
}

impl Pulse {
    /// \[choice\] 1.2 Hz, 100 mmHg mean, 40 mmHg pulse pressure; 20 instants; 5 cycles at 1 ms.
    pub fn default_pulse() -> Self {
        Pulse {
            mean_pa: 100.0 * PA_PER_MMHG,
            amplitude_pa: 20.0 * PA_PER_MMHG,
            freq_hz: 1.2,
            instants: 20,
            cycles: 5.0,
            dt_s: 1e-3,
        }
    }

    fn p(&self, t: f64) -> f64 {
        self.mean_pa + self.amplitude_pa * (2.0 * std::f64::consts::PI * self.freq_hz * t).sin()
    }
}

/// The cycle through the sensor and the chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Vessel {
    pub pulse: Pulse,
    pub electrodes: Vec<String>,
    /// The grasp with the vessel at zero pressure, and the voltages per pascal in the vessel.
    pub grasp_mv: Vec<f64>,
    pub per_pa_mv: Vec<f64>,
    /// The two linear-plate answers behind them (mesh, error: discretisation and, for the
    /// grasp, the linear plate's model error at its force; the unit's is at 1 Pa).
    pub grasp: SceneAnswer,
    pub unit: SceneAnswer,
    /// The tolerance asked for, and whether `--model auto` would leave the linear plate for the
    /// grasp (its model error over the tolerance): then only the small signal is the linear
    /// plate's, the grasp itself is the full scenes'.
    pub tol_rel: f64,
    pub auto_climbs: bool,
    /// The instants of one cycle: time, vessel pressure, nine voltages (mV, quasi-static).
    pub instants: Vec<(f64, f64, Vec<f64>)>,
    pub amplifier: Amplifier,
    pub channels: Vec<Channel>,
    #[serde(skip)]
    pub t_s: Vec<f64>,
    #[serde(skip)]
    pub p_pa: Vec<f64>,
    /// The plate's first natural frequency (Hz) and how far above the pulse it is.
    pub f1_hz: f64,
    pub f1_over_pulse: f64,
}

/// The cells' pressures of the vessel `dist` (a void's disturbance, its radius and height) at
/// `centre_um` on the background `bg`: the grasp with the vessel at zero pressure, and W, the
/// face pressure per pascal in the vessel (Pa per Pa), each as one value per cell of `grid`.
pub fn vessel_fields(
    bg: &Background,
    dist: &Disturbance,
    grid: &CellGrid,
    centre_um: (f64, f64),
) -> Result<(Vec<f64>, Vec<f64>), HiddenError> {
    if dist.shape == super::field::Shape::Sphere {
        return Err(HiddenError::Input {
            problem: "a spherical vessel".into(),
            hint: "a vessel is a tube: --shape cylinder (across the jaw) or rotated-section",
        });
    }
    if dist.feature != Feature::Void {
        return Err(HiddenError::Input {
            problem: format!("vessel {:?}", dist.feature),
            hint: "a vessel is a void whose wall carries the pressure",
        });
    }
    let slab = crate::softness::inclusion::Slab {
        feature: Feature::Void,
        radius_m: dist.radius_m,
        centre_height_m: dist.height_m,
        centre_x_m: 0.5 * bg.slab.width_m,
        ..bg.slab
    };
    let (nx, ny) = bg.elements;
    let w = wall_pressure_face_pa(&slab, nx, ny)?;
    // W as a disturbance of the background per pascal: W / P0.
    let per_pa = Disturbance {
        s_um: dist.s_um.clone(),
        d: w[nx..]
            .iter()
            .zip(&bg.p0_pa[nx..])
            .map(|(a, b)| if *b > 0.0 { a / b } else { 0.0 })
            .collect(),
        ..dist.clone()
    };
    let p0 = bg.cells(grid);
    let grasp = p0
        .iter()
        .zip(dist.cells(bg, grid, centre_um))
        .map(|(a, b)| a + b)
        .collect();
    Ok((grasp, per_pa.cells(bg, grid, centre_um)))
}

/// The vessel `dist` at `centre_um` on the background `bg`, pulsing with `pulse`: its two fields
/// ([`vessel_fields`]) on the cells of `grid` as one batch on the linear plate (`acc`'s
/// tolerance and levels; the rung is forced: the cycle superposes), then [`cycle`].
#[allow(clippy::too_many_arguments)]
pub fn vessel(
    g: &SensorGeometry,
    grid: &CellGrid,
    bg: &Background,
    dist: &Disturbance,
    centre_um: (f64, f64),
    pulse: Pulse,
    electronics: &ReadoutElectronics,
    acc: Accuracy,
) -> Result<Vessel, HiddenError> {
    check_pulse(&pulse)?;
    let (grasp, unit) = vessel_fields(bg, dist, grid, centre_um)?;
    let fields = [("vessel-grasp", &grasp[..]), ("vessel-per-pa", &unit[..])];
    let plate = acc.with_model(ModelChoice::Plate);
    let mut a = cells_answers(g, grid, &fields, plate, MeshOptions::READINGS)?.into_iter();
    let (grasp, unit) = (a.next().expect("grasp"), a.next().expect("unit"));
    cycle(g, grasp, unit, pulse, electronics, acc.tol_rel)
}

/// A usable pulse: a positive rate, 2-10,000 instants, at most 2,000,000 samples.
fn check_pulse(pulse: &Pulse) -> Result<(), HiddenError> {
    let ok = |v: f64| v.is_finite();
    let fine = pulse.freq_hz > 0.0
        && ok(pulse.freq_hz)
        && ok(pulse.mean_pa)
        && ok(pulse.amplitude_pa)
        && (2..=10_000).contains(&pulse.instants)
        && pulse.dt_s > 0.0
        && pulse.cycles > 0.0
        && pulse.cycles / (pulse.freq_hz * pulse.dt_s) <= 2e6;
    if fine {
        Ok(())
    } else {
        Err(HiddenError::Input {
            problem: format!("vessel pulse {pulse:?}"),
            hint: "a positive rate, 2-10,000 instants and at most 2,000,000 samples",
        })
    }
}

/// The cycle from the linear plate's answers to the grasp (`grasp`, the vessel at zero
/// pressure) and to 1 Pa in the vessel (`unit`): the instants V(t) = V_grasp + p(t) V_unit, the
/// electrodes' charges through the front end of `electronics`, and the plate's first mode.
pub fn cycle(
    g: &SensorGeometry,
    grasp: SceneAnswer,
    unit: SceneAnswer,
    pulse: Pulse,
    electronics: &ReadoutElectronics,
    tol_rel: f64,
) -> Result<Vessel, HiddenError> {
    check_pulse(&pulse)?;
    let electrodes: Vec<String> = g.electrodes.iter().map(|e| e.name.clone()).collect();
    let grasp_mv = grasp.voltages_mv.clone();
    let per_pa_mv = unit.voltages_mv.clone();
    let period = 1.0 / pulse.freq_hz;
    let instants = (0..pulse.instants)
        .map(|k| {
            let t = period * k as f64 / pulse.instants as f64;
            let p = pulse.p(t);
            let v = grasp_mv
                .iter()
                .zip(&per_pa_mv)
                .map(|(a, b)| a + p * b)
                .collect();
            (t, p, v)
        })
        .collect();
    // The chain: charge per pascal C_i V_W,i behind the amplifier, input p(t).
    let n = (pulse.cycles * period / pulse.dt_s).round() as usize;
    let t_s: Vec<f64> = (0..=n).map(|k| k as f64 * pulse.dt_s).collect();
    let p_pa: Vec<f64> = t_s.iter().map(|&t| pulse.p(t)).collect();
    let sources: Vec<Source> = g
        .electrodes
        .iter()
        .zip(&per_pa_mv)
        .map(|(e, v)| {
            let c_f = g.capacitance_f(e.area_um2);
            Source {
                name: e.name.clone(),
                charge_pc_per_n: v * 1e-3 * c_f * 1e12,
                capacitance_pf: c_f * 1e12,
            }
        })
        .collect();
    let amplifier = Amplifier::from_process(electronics);
    if let Some(s) = sources.iter().find(|s| {
        let c = s.capacitance_pf * 1e-12;
        !(amplifier.tau_s(c) > 0.0 && amplifier.tau_s(c).is_finite())
    }) {
        return Err(HiddenError::Input {
            problem: format!("electrode {} has no finite time constant", s.name),
            hint: "give readout.cable_capacitance_pf a value or check the electrode's area",
        });
    }
    let channels = chain(&sources, &amplifier, &t_s, &p_pa);
    let f1_hz = plate_modes(g, MODES_REPORTED, MODAL_LEVELS)?.modes[0].freq_hz;
    let auto_climbs = grasp.error.model.is_some_and(|e| e > tol_rel);
    Ok(Vessel {
        pulse,
        electrodes,
        grasp_mv,
        per_pa_mv,
        grasp,
        unit,
        tol_rel,
        auto_climbs,
        instants,
        amplifier,
        channels,
        t_s,
        p_pa,
        f1_hz,
        f1_over_pulse: f1_hz / pulse.freq_hz,
    })
}

impl Vessel {
    /// `vessel.csv`: the instants of one cycle, quasi-static electrode voltages.
    pub fn csv(&self) -> String {
        let mut s = String::from("t_s,p_vessel_pa");
        for e in &self.electrodes {
            let _ = write!(s, ",V_{e}_mv");
        }
        s.push('\n');
        for (t, p, v) in &self.instants {
            let _ = write!(s, "{t:.6},{p:.6e}");
            for x in v {
                let _ = write!(s, ",{x:.6e}");
            }
            s.push('\n');
        }
        s
    }

    /// `vessel-readout.csv`: the amplifier outputs over the record.
    pub fn readout_csv(&self) -> String {
        let mut s = String::from("t_s,p_vessel_pa");
        for c in &self.channels {
            let _ = write!(s, ",V_{}_v", c.name);
        }
        s.push('\n');
        for (k, (t, p)) in self.t_s.iter().zip(&self.p_pa).enumerate() {
            let _ = write!(s, "{t:.6},{p:.6e}");
            for c in &self.channels {
                let _ = write!(s, ",{:.6e}", c.voltage_v[k]);
            }
            s.push('\n');
        }
        s
    }

    /// `vessel.svg`: the nine amplifier outputs against time.
    pub fn svg(&self) -> String {
        use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};
        // At most ~2,000 points per line.
        let stride = (self.t_s.len() / 2000).max(1);
        let series = self
            .channels
            .iter()
            .map(|c| Series {
                name: c.name.clone(),
                points: self
                    .t_s
                    .iter()
                    .zip(&c.voltage_v)
                    .step_by(stride)
                    .map(|(t, v)| (*t, v * 1e3))
                    .collect(),
                style: Style::Line,
            })
            .collect();
        xy_svg(
            &XyPlot {
                title: format!(
                    "Pulsating vessel at {} Hz through the {}",
                    crate::plot::tick(self.pulse.freq_hz),
                    self.amplifier.name()
                ),
                x: Axis::linear("time (s)"),
                y: Axis::linear("amplifier output (mV)"),
                series,
            },
            800,
            480,
        )
    }
}
