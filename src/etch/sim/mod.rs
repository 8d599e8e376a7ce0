//! Anisotropic wet-etch simulation of the drawn front mask (issue 19): the orientation-dependent
//! rate R(n) over the surface normal ([`rate_table`]), the 2.5-D level-set advance of the silicon
//! surface under the oxide mask ([`level_set`]), the tooth's symmetry cell taken from the
//! generated [`crate::layout::MaskSet`] (`cell`) and what is read off the etched surface
//! ([`readout`]).

pub mod back;
pub mod back_cell;
pub mod cell;
pub mod level_set;
pub mod rate_table;
pub mod readout;
pub mod richardson;
pub mod run;
pub mod section;
pub mod sensitivity;
pub mod sizing;
pub mod svg;
pub mod tooth;

#[cfg(test)]
mod tests_back;
#[cfg(test)]
mod tests_bars;
#[cfg(test)]
mod tests_closed_form;
#[cfg(test)]
mod tests_sizing;
#[cfg(test)]
mod tests_tooth;

pub use back::BackSimulation;
pub use level_set::{Grid, Stepper, Surface};
pub use rate_table::{RateModel, RateTable};
pub use run::{finding, simulate, simulate_back, simulate_with};
pub use tooth::{CornerShape, ToothSimulation};

/// Why a simulation could not run. Each says what to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error(
        "the etch-simulation grid would have {nodes:.0} nodes (at most {max})\n  hint: use a \
         coarser grid step than {step_um} um"
    )]
    GridTooLarge {
        nodes: f64,
        max: usize,
        step_um: f64,
    },
    #[error("the etch-simulation grid is not usable: {what}\n  hint: a positive finite step")]
    BadGrid { what: String },
    #[error(
        "the etch simulation would take {steps:.0} time steps (at most {max})\n  hint: a coarser \
         grid step, or a shorter etch"
    )]
    TooManySteps { steps: f64, max: usize },
    #[error(
        "the process draws no teeth, so there is no tooth corner to simulate\n  hint: \
         geometry.teeth.pattern checkered or matrix"
    )]
    NoTeeth,
    #[error(
        "no tooth of the {count_x} x {count_y} cells has teeth on every side, so no symmetry cell \
         of the pattern can be simulated\n  hint: at least 4 x 4 tooth cells"
    )]
    NoInteriorTooth { count_x: u32, count_y: u32 },
    #[error("the process has no front-side silicon etch to simulate")]
    NoFrontEtch,
}
