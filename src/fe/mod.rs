//! Finite-element Kirchhoff plate solver (Bogner-Fox-Schmit rectangles on rectilinear meshes) for
//! the PVDF tactile-sensor models: orthotropic Si plates, stepped thickness (teeth), line supports
//! and point/pressure/line/probe loads, with support reactions, surface strains and convergence
//! estimates.
//!
//! Units: inputs in um and N, everything internal in SI (m, N, Pa). Sign convention: loads positive
//! in the +w direction (downward, the load direction); deflection w positive along the load;
//! curvature kappa = (-w_xx, -w_yy, -2 w_xy); the bottom surface (facing +w) is in tension under
//! sagging.
//!
//! ```
//! use tactfab::fe::*;
//! // 10 x 10 mm Si plate, 100 um thick, clamped edges, 1 N at the centre.
//! let mesh = RectMesh::build(&[0.0, 5000.0, 10_000.0], &[0.0, 5000.0, 10_000.0], 625.0, &[]);
//! let mut p = PlateProblem::new(mesh, 100.0, PlateMaterial::silicon(DieEdge::Along110));
//! p.support_all_edges(SupportKind::Clamped);
//! p.load_cases.push(vec![Load::Point { x_um: 5000.0, y_um: 5000.0, force_n: 1.0, radius_um: 0.0 }]);
//! let s = p.solve().unwrap();
//! let total: f64 = s[0].reactions().iter().map(|r| r.force_n).sum();
//! assert!((total - 1.0).abs() < 1e-9 && s[0].max_deflection().w_m > 0.0);
//! ```

pub mod assemble;
pub mod beam;
pub mod bfs;
pub mod cholesky;
pub mod clip;
pub mod convergence;
pub mod dofs;
pub mod edge_spring;
pub mod error;
pub mod footing;
pub mod loads;
pub mod mass;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod mirror;
pub mod modal;
pub mod ordering;
pub mod problem;
pub mod quarter_square;
pub mod solid;
pub mod solution;
pub mod solve;
pub mod stress_average;
pub mod vonkarman;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_footing;
#[cfg(test)]
mod tests_in_plane_spring;
#[cfg(test)]
mod tests_leissa;
#[cfg(test)]
mod tests_modal;
#[cfg(test)]
mod tests_vonkarman;

pub use beam::{fixed_fixed_reactions, BeamReactions};
pub use convergence::{richardson, richardson_ratios, ConvergenceKind, Richardson, ThreeMesh};
pub use error::{FeError, FeResult};
pub use mass::MassModel;
pub use material::{BendingStiffness, DieEdge, PlateMaterial};
pub use mesh::{RectMesh, RefinePoint};
pub use modal::{natural_frequencies, ModalOptions, Mode, Modes};
pub use problem::{
    Axis, BondedFilm, Dof, EdgeSpring, LineSupport, Load, PlateProblem, PrescribedDof, RectUm,
    SupportKind, ThicknessRegion,
};
pub use quarter_square::quarter_square;
pub use solution::{
    DeflectionPeak, GroupReaction, PlateSolution, Resultants, SolutionSummary, StressPeak, Surface,
};
pub use solve::Factorised;
pub use vonkarman::{AtDeflection, InPlane, NewtonStats, NonlinearOptions, VonKarman};
