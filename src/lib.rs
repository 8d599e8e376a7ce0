//! # tactfab: from one process file to wafer, masks, sensitivity and traveler
//!
//! A PVDF tactile sensor (paper 002 in `../shared/seeds/`) is described by one YAML process file.
//! Data flows one way through the crate:
//!
//! ```text
//! process/*.yaml -> process (validated) -> etch (EtchPlan) -> layout (MaskSet) -> export
//! Design {process, plan, masks} + Scene -> sensor -> fe (plate) -> readings with errors
//! studies (analysis, softness, sweep) call sensor; report (traveler, build.json) reads all
//! ```
//!
//! 1. [`process`] reads the file, applies `--set` overrides, and returns a validated
//!    [`process::Process`] or every problem at once, each with `file:line:column`, the field path
//!    and what is allowed. Defaults come from `../shared/reference` and are reported with their
//!    source.
//! 2. [`etch`] turns the process into an [`etch::EtchPlan`]: etch rates (TMAH Arrhenius from a
//!    measured rate, KOH after Seidel), times, {111} sidewall run-out, undercut, streets, corner
//!    compensation, the oxide mask budget, Deal-Grove oxidation and resist thickness, plus
//!    its findings.
//! 3. [`layout`] turns process + plan into a [`layout::MaskSet`]: polygons per layer in f64 um (geo
//!    types) for the front teeth with corner compensation, the back supports, the PVDF electrodes
//!    (each with its [`layout::ElectrodeSide`]), alignment marks and polygon labels, a die cell
//!    and a wafer of AREF-stepped dies. Every boolean goes through one adapter
//!    ([`layout::boolean`], geo 0.33 `BooleanOps`).
//! 4. [`design`] makes the [`design::Design`] once: process, plan and mask set. Everything after
//!    reads it and nothing re-derives teeth or electrodes: the sensor model takes them from the
//!    mask set, so what is simulated is what is drawn.
//! 5. [`drc`] checks the generated set (width, space, compensators, tooth bases, streets,
//!    electrodes, polygon validity) and returns violations as values; the process file may waive
//!    codes on purpose.
//! 6. [`export`] is the only place um become integer nm: GDSII (gds21), SVG per mask, KLayout .lyp
//!    and the DRC marker database (.lyrdb), the one XML escaper, and the one directory writer
//!    (a manifest of what tactfab wrote, swapped in as a unit).
//! 7. [`fe`] is a Kirchhoff plate solver (Bogner-Fox-Schmit rectangles, faer supernodal Cholesky in
//!    a nested-dissection order from the mesh grid) that knows nothing of sensors: meshes,
//!    thickness regions, line supports (clamped, simple, symmetry lines, elastic edge springs from
//!    [`fe::footing`]'s beam on a Winkler foundation), loads, reactions,
//!    strains, mirroring a half solution back to the whole plate, and the one three-mesh error
//!    estimate ([`fe::ThreeMesh`]). Its second rung, [`fe::VonKarman`], is the large-deflection
//!    plate on the same mesh (bilinear in-plane displacements beside the bending field, Newton on
//!    one symbolic analysis per mesh); [`fe::PlateSolution::averaged_principal_stress`] is the
//!    stress a plate can answer for near a step. [`fe::solid`] is the 3-D elasticity core
//!    (27-node bricks on tensor-line grids with void elements and a node map, refined locally
//!    by merged bricks whose finer neighbours' nodes hang, [`fe::solid::hanging`]; anisotropic Si;
//!    the sensor's with their transverse shears tied, [`fe::solid::shear_tying`], so thin plates
//!    on bricks of several thicknesses do not lock), linear or geometrically nonlinear ([`fe::solid::TlSolid`]: Total Lagrangian,
//!    St. Venant-Kirchhoff, Newton on the same symbolic analysis, its corrections preconditioned
//!    CG on the last factor where factorising is the cost); [`fe::solid::corner`] resolves
//!    a solved solid's field at a sharp re-entrant edge (a 2-D submodel graded into the edge),
//!    [`fe::solid::vertex`] at a frustum's base vertex (3-D submodels graded into the vertex and
//!    its edges, nested down to the critical distance on one factorisation). Every factor is
//!    sized by its symbolic analysis and refused when it cannot fit in memory ([`fe::memory`]).
//! 8. [`sensor`] builds the plate from a design ([`sensor::SensorGeometry::new`]), splits each
//!    scene's load between the plate and the supports (clamped at the etched walls, or on the
//!    supports' elastic footing, [`sensor::footing`]), pressing the upward faces only as the solid
//!    does (no load on the teeth's {111} sidewalls), and reads the electrodes: thickness mode
//!    Q = d33 F under the supports (on the footing the film bonded under the island, with the
//!    footing's pressure through it and the support's bottom strain in it), extension mode
//!    Q = integral of (d31 s1 + d32 s2) under the plate, V = Q / C. It refines the mesh until
//!    the estimated error is under the requested [`sensor::Accuracy`] and says which model
//!    answered ([`sensor::ModelKind`]), why, and what it cost, solving half or a quarter of the
//!    plate when the teeth and the loads are mirror-symmetric. The rung is the cheapest whose
//!    discretisation plus model error is under the tolerance ([`sensor::ModelChoice`]); every
//!    quantity carries both parts
//!    ([`sensor::QuantityError`]), and each scene its touch-down on the channel floor
//!    ([`sensor::TouchDown`]). [`sensor::solid`] is the top rung: the etched shape as a 3-D solid
//!    (mapped {111} frusta and channel walls, the two PVDF films, the base), electrodes read from
//!    their own film's stresses, solved linear or geometrically nonlinear as the ladder's plate
//!    rung for the scene is, graded at the base edges of the teeth that plate answer finds
//!    hottest ([`sensor::SceneReport::hot_teeth`]), and compared quantity by quantity with that
//!    rung; the sharp {111}
//!    edges' and the teeth's base vertices' stress at the critical distance
//!    ([`sensor::edge_stress`]) feeds its safety factor.
//!    The plate rungs answer the teeth's base edges from a section of the edge solved once per
//!    design ([`sensor::edge_section`]) driven by their resultants there.
//!    The footing's in-plane give holds the large-deflection plate's edges on the footing.
//!    Under `support_model: solid_section` the supports are plane-strain solid sections
//!    ([`sensor::support_section`]: bare, and under the teeth that stand on them) whose coupled
//!    springs hold the plate's edges piece by piece and whose film reads the support islands,
//!    with a Pasternak term along the wall from a slab of the section moved as a wave along it
//!    (the base spreading the load along the die, which plane strain cannot see),
//!    and each tooth's step stands where it bends as the {111} sidewall
//!    ([`sensor::frustum_step`]) with its mid-plane risen on the top face, so the
//!    large-deflection plate couples the teeth's bending to its stretching
//!    ([`fe::ThicknessRegion::rise_um`]).
//! 9. [`report`] puts it together: the traveler (run sheet: steps with computed values and their
//!    provenance, targets, hold points with a blank per reading, a cross-section per change of the
//!    stack, checks, FE summary), laid out once as a [`report::doc::Doc`] and rendered as Markdown
//!    and as printable HTML, and `tactfab build`'s in-memory build and `build.json` summary.
//! 10. The studies call the sensor: [`analysis`] (calibration, load inverse, orientation),
//!     [`softness`] (composite beam, paper 001 Eq. 7-12, beside a locking-free tissue FE, and the
//!     inverse; the tissue slab with a hidden lump, void or vessel, checked against Kirsch's
//!     hole; the spherical feature by axisymmetry, checked against Goodier's cavity and
//!     Eshelby's inclusions; the 3-D slab across the jaw with a sphere anywhere, on Q2/P1
//!     bricks), [`hidden`] (that slab's pressure through the sensor: per-cell unit
//!     responses of the linear plate, the grasp as full scenes on any plate rung, the inverse
//!     that locates and classifies the feature and flags its mirror ambiguity, the
//!     detectability map, the pulsating vessel through the read-out chain), [`sweep`] (paper
//!     001's 15,000 plates, sharded) and [`readout_chain`] (the nine channels in time through
//!     their charge amplifiers: PVDF senses change).
//!
//! Every warning, error and rule violation on the way is a [`finding::Finding`]: a code enum per
//! domain (etch plan, design rules, layout, FE scene) with one stable spelling, a severity, the
//! message and where it is. Nothing prints: the CLI and the report render findings.
//!
//! Nothing flows back: later stages read the design, never change it.
//!
//! ```
//! // The bundled process, with the etch time left for tactfab to compute.
//! let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
//! let computed = ["steps.tmah-etch.time_h=null".to_string()];
//! let loaded = tactfab::process::load_str(&text, "mis-grasper.yaml", &computed).unwrap();
//! let plan = tactfab::etch::plan(&loaded.process);
//! assert!((plan.steps[0].time_h - 200.0 / 24.0).abs() < 1e-12);
//! assert!((plan.plate_thickness_um - 100.0).abs() < 1e-9);
//! let a = plan.steps[0].compensation.unwrap().side_um; // a = h / 0.544
//! assert!((a - 367.647).abs() < 1e-3);
//! // A bad value is an error with its place, not a panic.
//! let bad = ["wafer.thickness_um=-1".to_string()];
//! let err = tactfab::process::load_str(&text, "f.yaml", &bad).unwrap_err();
//! assert!(err.to_string().contains("wafer.thickness_um"));
//! ```
//!
//! The binary (`src/main.rs`, `src/cli/`) only parses arguments (clap types and value parsers in
//! `cli/args.rs` and `cli/parse.rs`), makes one library call per subcommand and maps outcomes to
//! exit codes: 0 ok, 1 a check failed, 2 bad input or I/O error.

pub mod analysis;
pub mod design;
pub mod digest;
pub mod drc;
pub mod etch;
pub mod export;
pub mod fe;
pub mod finding;
pub mod hidden;
pub mod layout;
pub mod plot;
pub mod process;
pub mod readout_chain;
pub mod report;
pub mod sensor;
pub mod softness;
pub mod spelling;
pub mod sweep;
pub mod units;
