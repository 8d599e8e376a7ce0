//! The whole-plate solution of a mirror-symmetric problem from the solution of one half.
//!
//! A problem whose plate, supports, thickness map, material and loads are symmetric about a line
//! has a symmetric solution (uniqueness of the linear elastic solution): w(x, 2c - y) = w(x, y).
//! Solving one half with [`crate::fe::SupportKind::Symmetry`] on the mirror line and mirroring
//! the nodal values back gives the whole-plate field at half the cost, exact to round-off on the
//! mirrored mesh (tested against the whole-plate solve).

use std::sync::Arc;

use crate::fe::mesh::RectMesh;
use crate::fe::problem::Axis;
use crate::fe::solution::{GroupReaction, NodalReaction, PlateSolution, SolutionContext};

/// Lines of the mirrored axis and, per whole-plate line and element, the half's index and
/// whether it is a mirror image.
struct AxisMap {
    lines: Vec<f64>,
    node: Vec<(usize, bool)>,
    element: Vec<usize>,
}

#[track_caller]
fn mirror_axis(lines: &[f64], at_um: f64) -> AxisMap {
    let n = lines.len();
    let tol = 1e-9 * (lines[n - 1] - lines[0]).abs().max(1.0);
    let ne = n - 1;
    if (lines[n - 1] - at_um).abs() <= tol {
        let mut full = lines.to_vec();
        full.extend(lines[..n - 1].iter().rev().map(|v| 2.0 * at_um - v));
        let node = (0..2 * n - 1)
            .map(|k| {
                if k < n {
                    (k, false)
                } else {
                    (2 * (n - 1) - k, true)
                }
            })
            .collect();
        let element = (0..2 * ne)
            .map(|k| if k < ne { k } else { 2 * ne - 1 - k })
            .collect();
        AxisMap {
            lines: full,
            node,
            element,
        }
    } else if (lines[0] - at_um).abs() <= tol {
        let mut full: Vec<f64> = lines[1..].iter().rev().map(|v| 2.0 * at_um - v).collect();
        full.extend_from_slice(lines);
        let node = (0..2 * n - 1)
            .map(|k| {
                if k < n - 1 {
                    (n - 1 - k, true)
                } else {
                    (k - (n - 1), false)
                }
            })
            .collect();
        let element = (0..2 * ne)
            .map(|k| if k < ne { ne - 1 - k } else { k - ne })
            .collect();
        AxisMap {
            lines: full,
            node,
            element,
        }
    } else {
        panic!(
            "the mirror line {at_um} um must be an edge of the half mesh ({} .. {} um)",
            lines[0],
            lines[n - 1]
        );
    }
}

impl PlateSolution {
    /// The solution on the whole plate: this half joined to its mirror image about the line along
    /// `along` at `at_um`, which must be an edge of this half's mesh. Slopes normal to the line and
    /// the twist change sign in the image. The image's support reactions go to the group
    /// `rename(group)`; a reaction on the mirror line itself is counted once, doubled (both halves
    /// load that node).
    #[track_caller]
    pub fn mirrored(
        &self,
        along: Axis,
        at_um: f64,
        rename: impl Fn(&str) -> String,
    ) -> PlateSolution {
        let half = self.mesh();
        let ctx = self.context();
        let (xs, ys) = match along {
            Axis::X => (None, Some(mirror_axis(&half.y_um, at_um))),
            Axis::Y => (Some(mirror_axis(&half.x_um, at_um)), None),
        };
        let identity = |lines: &[f64]| AxisMap {
            lines: lines.to_vec(),
            node: (0..lines.len()).map(|k| (k, false)).collect(),
            element: (0..lines.len() - 1).collect(),
        };
        let xm = xs.unwrap_or_else(|| identity(&half.x_um));
        let ym = ys.unwrap_or_else(|| identity(&half.y_um));
        let mesh = RectMesh {
            x_um: xm.lines.clone(),
            y_um: ym.lines.clone(),
        };
        // Dofs w, w_x, w_y, w_xy: the slope across the line and the twist are odd.
        let sign: [f64; 4] = match along {
            Axis::X => [1.0, 1.0, -1.0, -1.0],
            Axis::Y => [1.0, -1.0, 1.0, -1.0],
        };
        // In-plane (u, v): the displacement across the line is odd.
        let sign_uv: [f64; 2] = match along {
            Axis::X => [1.0, -1.0],
            Axis::Y => [-1.0, 1.0],
        };
        let u_half = self.dofs();
        let uv_half = self.membrane();
        let mut u = Vec::with_capacity(4 * mesh.n_nodes());
        let mut uv = Vec::with_capacity(2 * mesh.n_nodes());
        for &(j, fy) in &ym.node {
            for &(i, fx) in &xm.node {
                let node = half.node(i, j);
                for d in 0..4 {
                    let flip = if fx || fy { sign[d] } else { 1.0 };
                    u.push(flip * u_half[4 * node + d]);
                }
                if let Some(m) = uv_half {
                    for d in 0..2 {
                        let flip = if fx || fy { sign_uv[d] } else { 1.0 };
                        uv.push(flip * m[2 * node + d]);
                    }
                }
            }
        }
        let whole_of = |v: &[f64]| -> Vec<f64> {
            if v.is_empty() {
                return Vec::new();
            }
            ym.element
                .iter()
                .flat_map(|&j| xm.element.iter().map(move |&i| (i, j)))
                .map(|(i, j)| v[half.element(i, j)])
                .collect()
        };
        let (thickness_um, rise_um) = (whole_of(&ctx.thickness_um), whole_of(&ctx.rise_um));
        let on_line = |r: &NodalReaction| {
            let c = match along {
                Axis::X => r.y_um,
                Axis::Y => r.x_um,
            };
            (c - at_um).abs() <= 1e-9 * at_um.abs().max(1.0)
        };
        let mut nodal = Vec::new();
        let mut groups = ctx.groups.clone();
        for r in self.all_nodal_reactions() {
            if on_line(r) {
                nodal.push(NodalReaction {
                    force_n: 2.0 * r.force_n,
                    ..r.clone()
                });
                continue;
            }
            nodal.push(r.clone());
            let (x_um, y_um) = match along {
                Axis::X => (r.x_um, 2.0 * at_um - r.y_um),
                Axis::Y => (2.0 * at_um - r.x_um, r.y_um),
            };
            let group = rename(&r.group);
            if !groups.contains(&group) {
                groups.push(group.clone());
            }
            nodal.push(NodalReaction {
                group,
                x_um,
                y_um,
                force_n: r.force_n,
            });
        }
        let mut reactions: Vec<GroupReaction> = groups
            .iter()
            .map(|g| GroupReaction {
                group: g.clone(),
                force_n: 0.0,
            })
            .collect();
        for r in &nodal {
            if let Some(g) = reactions.iter_mut().find(|g| g.group == r.group) {
                g.force_n += r.force_n;
            }
        }
        // Groups without nodal w reactions (a symmetry line) keep their (zero) totals.
        let ctx = Arc::new(SolutionContext {
            mesh,
            thickness_um,
            rise_um,
            material: ctx.material,
            groups,
        });
        let whole =
            PlateSolution::new(ctx, u, reactions, 2.0 * self.applied_force_n()).with_nodal(nodal);
        if uv_half.is_some() {
            whole.with_membrane(uv)
        } else {
            whole
        }
    }
}
