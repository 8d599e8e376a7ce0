//! The clamped square of the plate benchmarks (../shared/reference/fe-validation.md) as the
//! quarter the centre loads allow: the problem the large-deflection rung is checked against
//! scikit-fem on, by its test and by `vk_bench`.

use super::material::PlateMaterial;
use super::mesh::RectMesh;
use super::problem::{Axis, LineSupport, PlateProblem, SupportKind};

/// The quarter `[0, side/2]^2` of a square of side `side_um` clamped on all edges: clamped (and,
/// for the large-deflection plate, held in-plane) on x = 0 and y = 0, mirror lines through the
/// centre; `n` elements a side, spaced by `s^1.5` towards the centre (a point load's
/// singularity), no loads.
///
/// ```
/// use tactfab::fe::{quarter_square, PlateMaterial};
/// let p = quarter_square(10_000.0, 100.0, PlateMaterial::isotropic(169e9, 0.3), 8);
/// assert_eq!(p.mesh.x_um.len(), 9);
/// assert_eq!(p.supports.len(), 4);
/// ```
pub fn quarter_square(
    side_um: f64,
    thickness_um: f64,
    material: PlateMaterial,
    n: usize,
) -> PlateProblem {
    let h = side_um / 2.0;
    let lines: Vec<f64> = (0..=n)
        .map(|k| h * (1.0 - (1.0 - k as f64 / n as f64).powf(1.5)))
        .collect();
    let mesh = RectMesh {
        x_um: lines.clone(),
        y_um: lines,
    };
    let mut p = PlateProblem::new(mesh, thickness_um, material);
    for (along, group) in [(Axis::X, "y0"), (Axis::Y, "x0")] {
        p.supports.push(LineSupport {
            group: group.into(),
            kind: SupportKind::Clamped,
            along,
            at_um: 0.0,
            from_um: 0.0,
            to_um: h,
        });
        p.supports.push(LineSupport {
            group: "mirror".into(),
            kind: SupportKind::Symmetry,
            along,
            at_um: h,
            from_um: 0.0,
            to_um: h,
        });
    }
    p
}
