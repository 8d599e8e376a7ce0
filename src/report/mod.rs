//! Reports of a process: the traveler (run sheet) as Markdown and self-contained HTML, and the
//! one-command build with its JSON summary.
//!
//! [`build::build`] computes everything in memory (plan, masks, DRC, FE of the declared scenes,
//! traveler); [`traveler`] is the run sheet as data, [`sheet`] lays it out once as a [`doc::Doc`]
//! that [`markdown`] and [`html`] render,
//! [`section`] draws the cross-section after each step from the etch plan, [`inventory`] lists
//! the masks with their SHA-256, [`fe`] summarises the FE scenes, [`limits`] checks their
//! pass/fail limits, [`summary`](mod@summary) is `build.json`; [`calibration`] and [`orientation`] render the studies' CSV
//! and SVG files. Outputs are byte-identical for the same input:
//! no wall times are stored.

pub mod build;
pub mod calibration;
pub mod doc;
pub mod fe;
pub mod html;
pub mod inventory;
pub mod limits;
pub mod markdown;
pub mod orientation;
pub mod origin;
pub mod section;
pub mod sheet;
pub mod summary;
pub mod traveler;

pub use build::{build, Built, Options, ReportError, SolidCheck, Stage};
pub use limits::{check_limits, limit_failures, LimitCheck};
pub use origin::Origin;
pub use summary::{summary, BuildSummary};
pub use traveler::Traveler;
