//! Errors of the plate and solid solvers; every variant carries a hint on how to fix the input.

use thiserror::Error;

/// Plate solver error.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FeError {
    #[error("stiffness matrix is not positive definite ({detail})\n  hint: {hint}")]
    NotPositiveDefinite { detail: String, hint: &'static str },
    #[error(
        "the plate can still move as a rigid body ({free_modes} of 3 rigid modes unconstrained); \
         hint: {hint}"
    )]
    Underconstrained {
        free_modes: usize,
        hint: &'static str,
    },
    #[error("support '{group}' at {at_um} um is not on a mesh line\n  hint: {hint}")]
    SupportNotOnMeshLine {
        group: String,
        at_um: f64,
        hint: &'static str,
    },
    #[error("support '{group}' covers no mesh node\n  hint: {hint}")]
    EmptySupport { group: String, hint: &'static str },
    #[error(
        "prescribed dof of group '{group}' at ({x_um}, {y_um}) um is not at a mesh node\n  hint: \
         {hint}"
    )]
    PrescribedNotAtNode {
        group: String,
        x_um: f64,
        y_um: f64,
        hint: &'static str,
    },
    #[error(
        "load {index} of case {case} lies (partly) outside the plate or is degenerate\n  hint: \
         {hint}"
    )]
    LoadOutsidePlate {
        case: usize,
        index: usize,
        hint: &'static str,
    },
    #[error("element {element} has a non-positive or non-finite stiffness\n  hint: {hint}")]
    InvalidStiffness { element: usize, hint: &'static str },
    #[error("refactorisation needs the same mesh, supports and prescribed dofs\n  hint: {hint}")]
    PatternMismatch { hint: &'static str },
    #[error("sparse matrix construction failed ({detail})\n  hint: {hint}")]
    Sparse { detail: String, hint: &'static str },
    #[error("the solution is not finite\n  hint: {hint}")]
    NonFinite { hint: &'static str },
    #[error("mesh convergence study failed: {detail}\n  hint: {hint}")]
    Convergence { detail: String, hint: &'static str },
    #[error("solid model input is invalid: {detail}\n  hint: {hint}")]
    SolidInput { detail: String, hint: &'static str },
    #[error("solid element ({i}, {j}, {k}) is inverted or degenerate ({detail})\n  hint: {hint}")]
    DegenerateElement {
        i: usize,
        j: usize,
        k: usize,
        detail: String,
        hint: &'static str,
    },
    #[error("the model is too large: {detail} (limit {limit})\n  hint: {hint}")]
    TooLarge {
        detail: String,
        limit: usize,
        hint: &'static str,
    },
    #[error(
        "{what} needs {needed_mb} MB{}, more than the {budget_mb} MB {budget_source}\n  \
         hint: {hint}",
        beside(.others_mb)
    )]
    OutOfMemory {
        what: String,
        needed_mb: u64,
        budget_mb: u64,
        budget_source: &'static str,
        /// What other factorisations of the run took from the budget when this one asked.
        others_mb: u64,
        hint: &'static str,
    },
    #[error("TACTFAB_MEMORY_LIMIT_MB is `{value}`, not a positive number of MB\n  hint: {hint}")]
    MemoryLimit { value: String, hint: &'static str },
    #[error("element {element} has a non-positive or non-finite mass\n  hint: {hint}")]
    InvalidMass { element: usize, hint: &'static str },
    #[error("the natural frequencies did not converge: {detail}\n  hint: {hint}")]
    Eigen { detail: String, hint: &'static str },
    #[error("the geometrically nonlinear solve did not converge: {detail}\n  hint: {hint}")]
    Newton { detail: String, hint: &'static str },
}

impl FeError {
    /// A factor refused for memory that would fit alone: factorisations under way beside it
    /// took the room, so it can be solved once they are done
    /// ([`crate::fe::memory::in_parallel_then_alone`]).
    pub fn is_crowded_out(&self) -> bool {
        matches!(self, FeError::OutOfMemory { needed_mb, budget_mb, others_mb, .. }
            if *others_mb > 0 && needed_mb <= budget_mb)
    }
}

/// The [`FeError::OutOfMemory`] clause for what other factorisations take.
fn beside(others_mb: &u64) -> String {
    if *others_mb == 0 {
        String::new()
    } else {
        format!(" beside the {others_mb} MB that other factorisations of this run take")
    }
}

/// Result alias of the plate solver.
pub type FeResult<T> = Result<T, FeError>;
