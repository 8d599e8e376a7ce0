//! The sensor: the FE plate built from the process and mask geometry, and what each of the nine
//! electrodes reads under a scene.
//!
//! [`SensorGeometry`] collects what the model needs from the process, the etch plan (the plate
//! thickness the recipe leaves, the tooth footprint) and the PVDF mask (electrode rectangles).
//! [`evaluate`] solves a scene on successively refined meshes until the estimated error is under
//! the tolerance and reports charges, voltages, deflection, stress and reactions with the cost.
//! When the teeth and every load are mirror-symmetric it solves half (or a quarter) of the plate
//! ([`Symmetry`]) and reads the electrodes on the mirrored whole-plate field. [`plate_modes`]
//! gives the plate's lowest natural frequencies: how far above the loading quasi-static holds.
//! [`support_stiffness::SupportStiffness`] states the edge stiffness the plate stood on.

mod beam_model;
mod check;
mod convergence_plot;
pub mod edge_section;
pub mod edge_stress;
mod evaluate;
pub mod footing;
mod geometry;
mod mesh_lines;
mod modal;
mod readout;
mod rung;
mod scene;
mod symmetry;
mod touch_down;

pub mod frustum_step;
pub mod solid;
#[doc(hidden)]
pub mod solid_export;
pub mod solid_mesh;
pub mod solid_readout;
pub mod support_section;
pub mod support_stiffness;

pub use beam_model::{beam_answer, beam_applies, beam_error_estimate, BeamAnswer};
pub use check::{check_scene, SensorError, MAX_PATCHES, MAX_SOLUTION_VALUES};
pub use convergence_plot::convergence_svg;
pub use evaluate::{
    evaluate, evaluate_many, evaluate_many_with, Accuracy, LevelRecord, ModelInfo, ModelKind,
    SceneReport, StressFrom,
};
pub use geometry::{silicon_material, ElectrodeArea, ElectrodeSide, SensorGeometry};
pub use mesh_lines::{level_ratios, MeshOptions, SUBDIVISIONS};
pub use modal::{
    plate_modes, ModeFrequency, PlateModes, MODAL_LEVELS, MODES_REPORTED, PULSE_RATE_HZ,
    TEST_FREQ_HZ,
};
pub use readout::{ElectrodeReading, Readout};
pub use rung::{ErrorParts, ModelChoice, QuantityError};
pub use scene::{DirectLoad, SceneLoads};
pub use symmetry::{Mirror, Symmetry};
pub use touch_down::{find_factor, TouchDown};
