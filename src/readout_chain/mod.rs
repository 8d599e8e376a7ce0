//! The read-out chain in time (issue 17, item 4): PVDF senses change, so what the papers record
//! is each electrode's charge through a charge amplifier, a high-pass. Each electrode is a charge
//! source Q_i(t) = S_i F(t) (S_i from the linear plate at the load point, quasi-static: the
//! plate's first natural frequency, `fe::modal`, is far above the force's) with its capacitance
//! C_e; the front end ([`Amplifier`], from the process file's `readout` section) is a
//! first-order high-pass with gain and time constant tau, integrated exactly for piecewise-linear
//! input ([`high_pass`]). Force histories ([`HistoryKind`]): a grasp closing along half a sine and
//! held, the papers' 5 Hz test sinusoid, and 1 Hz pulses on a held grasp.
//!
//! ```
//! use tactfab::readout_chain::{high_pass, corner_hz};
//! // A held step decays as e^(-t / tau): the reason a held grasp fades from the record.
//! let t = [0.0, 0.0, 1.0, 2.0];
//! let y = high_pass(&t, &[0.0, 1.0, 1.0, 1.0], 1.0);
//! assert!((y[3] - (-2f64).exp()).abs() < 1e-15);
//! assert!((corner_hz(1.0) - 0.159_154_943).abs() < 1e-9);
//! ```

mod chain;
mod front_end;
mod high_pass;
mod history;
mod plot;
mod study;

pub use chain::{held_decay, run, Channel, HeldDecay, Source};
pub use front_end::{corner_hz, high_pass_response, Amplifier};
pub use high_pass::high_pass;
pub use history::{
    sample, HistoryKind, GRASP_CYCLE_S, MAX_SAMPLES, PULSE_FRACTION, PULSE_RATE_HZ, PULSE_WIDTH_S,
    TEST_FREQ_HZ,
};
pub use plot::readout_svg;
pub use study::{study, ReadoutError, ReadoutSpec, ReadoutStudy, SensitivitySource};
