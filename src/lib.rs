//! # tactfab: from one process file to wafer, masks, sensitivity and traveler
//!
//! A PVDF tactile sensor (paper 002 in `../shared/seeds/`) is described by one YAML process file.
//! Data flows one way through the crate:
//!
//! 1. [`process`] reads the file, applies `--set` overrides, and returns a validated
//!    [`process::Process`] or every problem at once, each with `file:line:column`, the field path
//!    and what is allowed. Defaults come from `../shared/reference` and are reported with their
//!    source.
//! 2. [`etch`] turns the process into an [`etch::EtchPlan`]: etch rates (TMAH Arrhenius from a
//!    measured rate, KOH after Seidel), times, {111} sidewall run-out, undercut, streets, corner
//!    compensation, the oxide mask budget, Deal-Grove oxidation and resist thickness, plus
//!    [`etch::Check`]s: warnings and errors as values with stable codes.
//! 3. [`fe`] is a Kirchhoff plate solver (Bogner-Fox-Schmit rectangles, faer supernodal Cholesky in
//!    a nested-dissection order from the mesh grid) that knows nothing of sensors: meshes,
//!    thickness regions, line supports (clamped, simple, symmetry lines), loads, reactions,
//!    strains, mirroring a half solution back to the whole plate, and three-mesh error estimates.
//! 4. [`sensor`] builds the plate from the process, the plan (the plate thickness the recipe
//!    leaves, the tooth footprints) and the electrode pattern, splits each scene's load between the
//!    plate and the supports, and reads the nine electrodes: thickness mode Q = d33 F under the
//!    supports, extension mode Q = integral of (d31 s1 + d32 s2) under the plate, V = Q / C. It
//!    refines the mesh (every feature line kept; on request graded towards loads and tooth corners)
//!    until the estimated error is under the tolerance and says what that cost, solving only half
//!    or a quarter of the plate when the teeth and the loads are mirror-symmetric.
//! 5. [`layout`] turns process + plan into a [`layout::MaskSet`]: polygons per layer in f64 um (geo
//!    types) for the front teeth with corner compensation, the back supports, the PVDF electrodes,
//!    alignment marks and polygon labels, a die cell and a wafer of AREF-stepped dies. Every
//!    boolean goes through one adapter ([`layout::boolean`], geo 0.33 `BooleanOps`).
//! 6. [`drc`] checks the generated set (width, space, compensators, tooth bases, streets,
//!    electrodes, polygon validity) and returns violations as values; the process file may waive
//!    codes on purpose.
//! 7. [`export`] is the only place um become integer nm: GDSII (gds21), SVG per mask, KLayout .lyp.
//! 8. [`report`] puts it together: the traveler (run sheet: steps with computed values and their
//!    provenance, targets, hold points, a cross-section after each step, checks, FE summary) as
//!    Markdown and HTML, and `tactfab build`'s in-memory build and `build.json` summary.
//! 9. [`softness`] reads the tissue modulus from the middle electrode: composite beam (paper 001
//!    Eq. 7-12) and a locking-free plane-strain FE of the tissue on the plate, and the inverse.
//! 10. [`sweep`] runs the design sweep of paper 001 (15,000 plates, sharded, one symbolic
//!     factorisation per worker) and finds the family that matches the prototype.
//!
//! Nothing flows back: later stages read the process, the plan and the mask set, never change them.
//! The FE model takes its electrodes from the PVDF mask, so what is simulated is what is drawn.
//!
//! ```
//! // The bundled process, with the etch time left for tactfab to compute.
//! let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
//! let loaded = tactfab::process::load_str(&text, "mis-grasper.yaml", &["steps.tmah-etch.time_h=null".into()]).unwrap();
//! let plan = tactfab::etch::plan(&loaded.process);
//! assert!((plan.steps[0].time_h - 200.0 / 24.0).abs() < 1e-12);
//! assert!((plan.plate_thickness_um - 100.0).abs() < 1e-9);
//! let a = plan.steps[0].compensation.unwrap().side_um; // a = h / 0.544
//! assert!((a - 367.647).abs() < 1e-3);
//! // A bad value is an error with its place, not a panic.
//! let err = tactfab::process::load_str(&text, "f.yaml", &["wafer.thickness_um=-1".into()]).unwrap_err();
//! assert!(err.to_string().contains("wafer.thickness_um"));
//! ```
//!
//! The binary (`src/main.rs`, `src/cli/`) only parses arguments, calls the library and maps
//! outcomes to exit codes: 0 ok, 1 a check failed, 2 bad input or I/O error.

pub mod analysis;
pub mod design;
pub mod drc;
pub mod etch;
pub mod export;
pub mod fe;
pub mod layout;
pub mod plot;
pub mod process;
pub mod report;
pub mod sensor;
pub mod softness;
pub mod sweep;
pub mod units;
