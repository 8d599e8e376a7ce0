//! Linear 3-D elasticity on structured grids of triquadratic 27-node hexahedra: the solid rung
//! that measures the Kirchhoff plate's model error (issue 16). It knows nothing of sensors: a
//! grid of tensor lines with void elements and a node map, anisotropic materials, clamps and
//! symmetry planes, point forces and face pressures, several load cases on one factorisation.
//! Its geometrically nonlinear form ([`tl`]: Total Lagrangian, St. Venant-Kirchhoff; [`TlSolid`]:
//! Newton with load steps on the same pattern and symbolic analysis) answers large deflections
//! and rotations under dead loads. A grid refines locally by merging boxes of cells into bricks
//! ([`HexGrid::merge`]); the finer neighbours' nodes on a merged brick's faces hang on its trace
//! ([`hanging`]) and are eliminated at assembly.
//!
//! Units: positions in um, forces in N, pressures and stresses in Pa, displacements in m; SI
//! inside. Stresses in Voigt order xx, yy, zz, yz, xz, xy.
//!
//! ```
//! use tactfab::fe::solid::*;
//! // A 1000 x 100 x 100 um isotropic bar clamped at x = 0, 1 mN along -z at the free end.
//! let grid = HexGrid::new(&uniform_lines(0.0, 1000.0, 10), &[0.0, 100.0], &[0.0, 100.0]).unwrap();
//! let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(169e9, 0.0)]);
//! p.constraints.push(Constraint::clamp("root", NodeSet::Plane { axis: Axis3::X, at_um: 0.0 }));
//! p.load_cases.push(vec![SolidLoad::Point {
//!     at_um: [1000.0, 50.0, 50.0],
//!     force_n: [0.0, 0.0, -1e-3],
//!     snap: Snap::Exact,
//! }]);
//! let s = &p.solve().unwrap()[0];
//! let r = s.reaction_n("root").unwrap();
//! assert!((r[2] - 1e-3).abs() < 1e-12); // K u - f: the clamp pushes back
//! assert!(s.displacement_m([1000.0, 50.0, 50.0]).unwrap()[2] < 0.0);
//! ```

pub mod assemble;
pub mod corner;
pub mod dofs;
pub mod elasticity;
pub mod field;
pub mod grid;
pub mod hanging;
pub mod hex27;
pub mod loads;
pub mod nonlinear;
pub mod ordering;
pub mod principal;
pub mod problem;
pub mod shear_tying;
pub mod solution;
pub mod solve;
pub mod tl;
pub mod vertex;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_corner;
#[cfg(test)]
mod tests_hanging;
#[cfg(test)]
mod tests_shear_tying;
#[cfg(test)]
mod tests_tl;
#[cfg(test)]
mod tests_vertex;

pub use elasticity::Elasticity;
pub use field::SolidField;
pub use grid::{graded_lines, merged_lines, uniform_lines, HexGrid, NodeMap, MAX_DOFS};
pub use nonlinear::{NewtonIterate, TlOptions, TlSolid, TlSolution};
pub use principal::principal_stresses_pa;
pub use problem::{
    Axis3, Constraint, FaceRect, NodeSet, Outward, Prescribed, Snap, SolidLoad, SolidProblem,
};
pub use shear_tying::TransverseShear;
pub use solution::{PrincipalPeak, SolidReaction, SolidSolution};
pub use solve::{BuildTimings, Ordering, SolidModel};
