//! The footing's in-plane give on the large-deflection plate: a distributed spring, per unit
//! length of an edge-spring line, on the plate's in-plane displacement normal to the line
//! ([`crate::fe::EdgeSpring::normal_in_plane_pa`]). Along the line that displacement is the
//! bilinear element's own (linear between nodes), so the spring is integrated exactly with it
//! and adds no dofs: it couples the two nodes of each segment, which the stencil already holds.

use crate::fe::assemble::Pattern;
use crate::fe::edge_spring::segments;
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::{Axis, PlateProblem};

/// One segment of a line with an in-plane spring: the normal in-plane dof of its two nodes and
/// its stiffness times its length, k h (N/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct InPlaneSegment {
    pub dofs: [usize; 2],
    pub k_h_n_per_m: f64,
}

/// The segments of every edge spring with an in-plane stiffness; `m` dofs per node with u, v
/// at 4 and 5. An error if a stiffness is not positive and finite (a spring that is not one).
pub(super) fn in_plane_segments(problem: &PlateProblem, m: usize) -> FeResult<Vec<InPlaneSegment>> {
    let mut out = Vec::new();
    for s in &problem.edge_springs {
        let Some(k) = s.normal_in_plane_pa else {
            continue;
        };
        if !(k > 0.0 && k.is_finite()) {
            return Err(FeError::NotPositiveDefinite {
                detail: format!("in-plane spring stiffness {k} N/m^2 on '{}'", s.group),
                hint: "an in-plane spring needs a positive, finite stiffness (None holds the edge)",
            });
        }
        let normal = match s.along {
            Axis::X => 5,
            Axis::Y => 4,
        };
        for seg in segments(&problem.mesh, s)? {
            out.push(InPlaneSegment {
                dofs: seg.nodes.map(|n| m * n + normal),
                k_h_n_per_m: k * (seg.t_um[1] - seg.t_um[0]) * 1e-6,
            });
        }
    }
    Ok(out)
}

/// int k N^T N dt for the linear field along the segment: k h [[1/3, 1/6], [1/6, 1/3]].
fn matrix(seg: &InPlaneSegment) -> [f64; 4] {
    let (d, o) = (seg.k_h_n_per_m / 3.0, seg.k_h_n_per_m / 6.0);
    [d, o, o, d]
}

/// Adds the springs' forces K u to the internal force `r`.
pub(super) fn add_forces(segs: &[InPlaneSegment], u: &[f64], r: &mut [f64]) {
    for seg in segs {
        let k = matrix(seg);
        let [a, b] = seg.dofs;
        r[a] += k[0] * u[a] + k[1] * u[b];
        r[b] += k[2] * u[a] + k[3] * u[b];
    }
}

/// Adds the springs' stiffness to the tangent's values.
pub(super) fn add_to_values(
    pattern: &Pattern,
    vals: &mut [f64],
    mesh: &RectMesh,
    free_index: &[usize],
    segs: &[InPlaneSegment],
) {
    for seg in segs {
        pattern.add_dof_block(vals, mesh, free_index, &seg.dofs, &matrix(seg));
    }
}
