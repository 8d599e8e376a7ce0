//! Studies built on the sensor model: calibration tables and the load inverse (paper 002, sec. V
//! and VII), and the probe-orientation study with its fits and angle inverse (paper 000).
//!
//! Every study batches its loads into one [`crate::sensor::evaluate_many_with`] call (one
//! factorisation per mesh level) on [`crate::sensor::MeshOptions::READINGS`] (its answers are
//! readings: the tooth-base stations' mesh lines would triple each level) and uses the model's
//! linearity in force where a force sweep would only scale the same solution; the force tables
//! that claim linearity are real solves at those forces.

pub mod calibration;
pub mod error;
pub mod fit;
pub mod interp;
pub mod inverse;
pub mod noise;
pub mod orientation;
pub mod study;

pub use error::AnalysisError;
