//! Errors of the plate solver; every variant carries a hint on how to fix the input.

use thiserror::Error;

/// Plate solver error.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FeError {
    #[error("stiffness matrix is not positive definite ({detail}); hint: {hint}")]
    NotPositiveDefinite { detail: String, hint: &'static str },
    #[error(
        "the plate can still move as a rigid body ({free_modes} of 3 rigid modes unconstrained); \
         hint: {hint}"
    )]
    Underconstrained {
        free_modes: usize,
        hint: &'static str,
    },
    #[error("support '{group}' at {at_um} um is not on a mesh line; hint: {hint}")]
    SupportNotOnMeshLine {
        group: String,
        at_um: f64,
        hint: &'static str,
    },
    #[error("support '{group}' covers no mesh node; hint: {hint}")]
    EmptySupport { group: String, hint: &'static str },
    #[error(
        "prescribed dof of group '{group}' at ({x_um}, {y_um}) um is not at a mesh node; hint: \
         {hint}"
    )]
    PrescribedNotAtNode {
        group: String,
        x_um: f64,
        y_um: f64,
        hint: &'static str,
    },
    #[error(
        "load {index} of case {case} lies (partly) outside the plate or is degenerate; hint: \
         {hint}"
    )]
    LoadOutsidePlate {
        case: usize,
        index: usize,
        hint: &'static str,
    },
    #[error("element {element} has a non-positive or non-finite stiffness; hint: {hint}")]
    InvalidStiffness { element: usize, hint: &'static str },
    #[error("refactorisation needs the same mesh, supports and prescribed dofs; hint: {hint}")]
    PatternMismatch { hint: &'static str },
    #[error("sparse matrix construction failed ({detail}); hint: {hint}")]
    Sparse { detail: String, hint: &'static str },
    #[error("the solution is not finite; hint: {hint}")]
    NonFinite { hint: &'static str },
    #[error("mesh convergence study failed: {detail}; hint: {hint}")]
    Convergence { detail: String, hint: &'static str },
}

/// Result alias of the plate solver.
pub type FeResult<T> = Result<T, FeError>;
