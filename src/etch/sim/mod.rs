//! Anisotropic wet-etch simulation of the drawn front mask (issue 19): the orientation-dependent
//! rate R(n) over the surface normal ([`rate_table`]), the 2.5-D level-set advance of the silicon
//! surface under the oxide mask ([`level_set`]), the tooth's symmetry cell taken from the
//! generated [`crate::layout::MaskSet`] (`cell`) and what is read off the etched surface
//! ([`readout`]).

pub mod level_set;
pub mod rate_table;
pub mod readout;

#[cfg(test)]
mod tests_closed_form;

pub use level_set::{Grid, Stepper, Surface};
pub use rate_table::{RateModel, RateTable};

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
}
