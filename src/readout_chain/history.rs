//! Force histories the jaws apply, sampled on a uniform grid: a grasp that closes along half a
//! sine and is then held, the papers' 5 Hz test sinusoid, and a 1 Hz pulse train riding on a held
//! grasp (a pulsating vessel under the jaws).

use serde::Serialize;

pub use crate::sensor::{PULSE_RATE_HZ, TEST_FREQ_HZ};

/// A grasp cycle, closing and opening, takes about 1 s and looks like half a sine [paper 002
/// sec. VII.A]; the jaws close along its rising half.
pub const GRASP_CYCLE_S: f64 = 1.0;
/// \[choice\] Each pulse is half a sine this long (a systolic pressure rise; no source in
/// ../shared gives a shape).
pub const PULSE_WIDTH_S: f64 = 0.3;
/// \[choice\] Pulse height as a fraction of the held grasp force (no source in ../shared).
pub const PULSE_FRACTION: f64 = 0.1;
/// Most samples one history may have (each is a row of the CSV and 10 values per channel).
pub const MAX_SAMPLES: usize = 2_000_000;

/// Which history.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum HistoryKind {
    /// Closes along the rising half of a [`GRASP_CYCLE_S`] half sine, then held.
    HalfSine,
    /// F sin(2 pi [`TEST_FREQ_HZ`] t).
    Sine5Hz,
    /// The held grasp with a half-sine pulse of [`PULSE_FRACTION`] F every 1 / [`PULSE_RATE_HZ`]
    /// from the first full second after the jaws closed.
    Pulse,
}

impl HistoryKind {
    /// The name `--history` takes.
    pub fn name(self) -> &'static str {
        match self {
            HistoryKind::HalfSine => "half-sine",
            HistoryKind::Sine5Hz => "sine-5hz",
            HistoryKind::Pulse => "pulse",
        }
    }

    /// The default length of the record: long enough to show the held grasp's decay (5 s), five
    /// test cycles (1 s), or five pulses (6 s).
    pub fn default_duration_s(self) -> f64 {
        match self {
            HistoryKind::HalfSine => 5.0,
            HistoryKind::Sine5Hz => 1.0,
            HistoryKind::Pulse => 6.0,
        }
    }

    /// When the jaws stop closing and hold (None: nothing is held).
    pub fn hold_start_s(self) -> Option<f64> {
        match self {
            HistoryKind::HalfSine | HistoryKind::Pulse => Some(GRASP_CYCLE_S / 2.0),
            HistoryKind::Sine5Hz => None,
        }
    }

    /// The force at `t_s` for a peak (grasp) or amplitude (sine) of `force_n`.
    pub fn force_n(self, t_s: f64, force_n: f64) -> f64 {
        use std::f64::consts::PI;
        let grasp = |t: f64| {
            if t <= 0.0 {
                0.0
            } else if t < GRASP_CYCLE_S / 2.0 {
                force_n * (PI * t / GRASP_CYCLE_S).sin()
            } else {
                force_n
            }
        };
        match self {
            HistoryKind::HalfSine => grasp(t_s),
            HistoryKind::Sine5Hz => force_n * (2.0 * PI * TEST_FREQ_HZ * t_s).sin(),
            HistoryKind::Pulse => {
                let start = GRASP_CYCLE_S / 2.0 + 1.0 / PULSE_RATE_HZ;
                let period = 1.0 / PULSE_RATE_HZ;
                let pulse = if t_s >= start {
                    let phase = (t_s - start) % period;
                    if phase < PULSE_WIDTH_S {
                        PULSE_FRACTION * force_n * (PI * phase / PULSE_WIDTH_S).sin()
                    } else {
                        0.0
                    }
                } else {
                    0.0
                };
                grasp(t_s) + pulse
            }
        }
    }
}

/// The history sampled every `dt_s` over [0, `duration_s`]: (times, forces). An error (not a
/// panic) when the values are not positive and finite or the record would exceed
/// [`MAX_SAMPLES`].
pub fn sample(
    kind: HistoryKind,
    force_n: f64,
    duration_s: f64,
    dt_s: f64,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    if !(duration_s > 0.0 && duration_s.is_finite() && dt_s > 0.0 && dt_s.is_finite()) {
        return Err(format!(
            "the duration ({duration_s} s) and the time step ({dt_s} s) must be positive"
        ));
    }
    if !force_n.is_finite() {
        return Err(format!("the force {force_n} N is not finite"));
    }
    let steps = (duration_s / dt_s).ceil();
    if steps + 1.0 > MAX_SAMPLES as f64 {
        return Err(format!(
            "{duration_s} s every {dt_s} s is {steps} samples, above the limit of {MAX_SAMPLES}: \
             use a longer time step or a shorter record"
        ));
    }
    let n = steps as usize;
    let t: Vec<f64> = (0..=n).map(|k| (k as f64 * dt_s).min(duration_s)).collect();
    let f = t.iter().map(|&t| kind.force_n(t, force_n)).collect();
    Ok((t, f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histories_have_their_shapes() {
        let h = HistoryKind::HalfSine;
        assert_eq!(h.force_n(0.0, 2.0), 0.0);
        assert!((h.force_n(0.25, 2.0) - 2.0 * (std::f64::consts::PI / 4.0).sin()).abs() < 1e-15);
        assert_eq!(h.force_n(3.0, 2.0), 2.0);
        let s = HistoryKind::Sine5Hz;
        assert!((s.force_n(0.05, 1.0) - 1.0).abs() < 1e-12);
        assert!(s.force_n(0.2, 1.0).abs() < 1e-12);
        let p = HistoryKind::Pulse;
        // Held before the first pulse, peak of the pulse at the middle of its width, a period on.
        assert_eq!(p.force_n(1.2, 1.0), 1.0);
        let peak = 0.5 + 1.0 + PULSE_WIDTH_S / 2.0;
        assert!((p.force_n(peak, 1.0) - 1.1).abs() < 1e-12);
        assert!((p.force_n(peak + 1.0, 1.0) - 1.1).abs() < 1e-9);
        assert_eq!(p.force_n(1.5 + 0.5, 1.0), 1.0);
    }

    #[test]
    fn sampling_is_bounded_and_ends_at_the_duration() {
        let (t, f) = sample(HistoryKind::HalfSine, 1.0, 1.0, 0.3).unwrap();
        assert_eq!(t, vec![0.0, 0.3, 0.6, 0.8999999999999999, 1.0]);
        assert_eq!(f.len(), t.len());
        assert!(sample(HistoryKind::Pulse, 1.0, 1e4, 1e-6).is_err());
        assert!(sample(HistoryKind::Pulse, 1.0, -1.0, 1e-3).is_err());
        assert!(sample(HistoryKind::Pulse, f64::NAN, 1.0, 1e-3).is_err());
    }
}
