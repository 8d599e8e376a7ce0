//! The footing's in-plane give on the large-deflection plate: a distributed spring, per unit
//! length of an edge-spring line, on the plate's in-plane displacement normal to the line
//! ([`crate::fe::EdgeSpring::normal_in_plane_pa`]). Along the line that displacement is the
//! bilinear element's own (linear between nodes), so the spring is integrated exactly with it
//! and adds no dofs: it couples the two nodes of each segment, which the stencil already holds.

use crate::fe::assemble::Pattern;
use crate::fe::edge_spring::{segment_dofs, segments, shape_rows, shape_rows_dt, GAUSS4};
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::{Axis, EdgeSpring, PlateProblem};

/// One segment of a line with an in-plane spring: the normal in-plane dof of its two nodes and
/// its stiffness times its length, k h (N/m).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct InPlaneSegment {
    pub dofs: [usize; 2],
    pub k_h_n_per_m: f64,
    /// The Pasternak term along the line on the in-plane displacement ([`EdgeSpring::along_wall`]),
    /// G_uu / h (N/m).
    pub g_over_h_n_per_m: f64,
    /// The coupling of a [`EdgeSpring::coupled`] spring: its 10 x 10 block over the segment's
    /// 8 bending dofs and its 2 normal in-plane dofs (zero diagonal blocks).
    pub cross: Option<([usize; 10], Vec<f64>)>,
    /// Index of the spring in the problem's `edge_springs`.
    pub spring: usize,
}

/// int (k_wu (N_w^T N_u + N_u^T N_w) + k_tu (N_t^T N_u + N_u^T N_t)) dt over the segment, the
/// in-plane shape linear, its sign towards the plate (against `outward`), plus the same of the
/// shapes' derivatives with the Pasternak term's g_wu, g_tu; 4-point Gauss is exact.
fn cross_block(s: &EdgeSpring, h_m: f64, k: [f64; 2], g: [f64; 2]) -> Vec<f64> {
    let mut m = vec![0.0; 100];
    let sign = -s.outward;
    for (xi, wq) in GAUSS4 {
        let (nw, nt) = shape_rows(s, xi, h_m);
        let (dw, dt) = shape_rows_dt(s, xi, h_m);
        let nu = [sign * (1.0 - xi), sign * xi];
        let du = [-sign / h_m, sign / h_m];
        for i in 0..8 {
            let a = k[0] * nw[i] + k[1] * nt[i];
            let b = g[0] * dw[i] + g[1] * dt[i];
            for j in 0..2 {
                let v = wq * h_m * (a * nu[j] + b * du[j]);
                m[i * 10 + 8 + j] += v;
                m[(8 + j) * 10 + i] += v;
            }
        }
    }
    m
}

/// The segments of every edge spring with an in-plane stiffness; `m` dofs per node with u, v
/// at 4 and 5. An error if a stiffness is not positive and finite (a spring that is not one).
pub(super) fn in_plane_segments(problem: &PlateProblem, m: usize) -> FeResult<Vec<InPlaneSegment>> {
    let mut out = Vec::new();
    for (spring, s) in problem.edge_springs.iter().enumerate() {
        let Some(k) = s.coupled.map(|c| c[2][2]).or(s.normal_in_plane_pa) else {
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
            let h_m = (seg.t_um[1] - seg.t_um[0]) * 1e-6;
            let dofs = seg.nodes.map(|n| m * n + normal);
            let g = s.along_wall.unwrap_or_default();
            let cross = (s.coupled.is_some() || s.along_wall.is_some()).then(|| {
                let c = s.coupled.unwrap_or_default();
                let bend = segment_dofs(&seg, m);
                let all: [usize; 10] =
                    std::array::from_fn(|i| if i < 8 { bend[i] } else { dofs[i - 8] });
                let block = cross_block(s, h_m, [c[0][2], c[1][2]], [g[0][2], g[1][2]]);
                (all, block)
            });
            out.push(InPlaneSegment {
                dofs,
                k_h_n_per_m: k * h_m,
                g_over_h_n_per_m: g[2][2] / h_m,
                cross,
                spring,
            });
        }
    }
    Ok(out)
}

/// int (k N^T N + G N'^T N') dt for the linear field along the segment: k h [[1/3, 1/6], [1/6,
/// 1/3]] + G / h [[1, -1], [-1, 1]].
fn matrix(seg: &InPlaneSegment) -> [f64; 4] {
    let (d, o) = (seg.k_h_n_per_m / 3.0, seg.k_h_n_per_m / 6.0);
    let g = seg.g_over_h_n_per_m;
    [d + g, o - g, o - g, d + g]
}

/// Adds the springs' forces K u to the internal force `r`.
pub(super) fn add_forces(segs: &[InPlaneSegment], u: &[f64], r: &mut [f64]) {
    for seg in segs {
        let k = matrix(seg);
        let [a, b] = seg.dofs;
        r[a] += k[0] * u[a] + k[1] * u[b];
        r[b] += k[2] * u[a] + k[3] * u[b];
        if let Some((dofs, m)) = &seg.cross {
            for i in 0..10 {
                r[dofs[i]] += (0..10).map(|j| m[i * 10 + j] * u[dofs[j]]).sum::<f64>();
            }
        }
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
        if let Some((dofs, m)) = &seg.cross {
            pattern.add_dof_block(vals, mesh, free_index, dofs, m);
        }
    }
}

/// The coupling's force at the w dofs of each coupled segment's two nodes, (spring index, node,
/// force N): the part of a coupled spring's reaction the bending block does not hold; `m` dofs
/// per node.
pub(super) fn nodal_w_forces(
    segs: &[InPlaneSegment],
    u: &[f64],
    m: usize,
) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::new();
    for seg in segs {
        let Some((dofs, k)) = &seg.cross else {
            continue;
        };
        for row in [0, 4] {
            let f: f64 = (0..10).map(|j| k[row * 10 + j] * u[dofs[j]]).sum();
            out.push((seg.spring, dofs[row] / m, f));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pasternak_terms_on_the_in_plane_displacement_store_g_k2_over_a_wave() {
        // u = c cos(k x) towards the plate and w = a cos(k x) over a half wavelength: the
        // in-plane block and the coupling store 1/2 int (G_uu u'^2 + 2 G_wu w' u') dx =
        // (G_uu c^2 + 2 G_wu a c) k^2 L / 4; the linear u makes the u-u term converge as h^2.
        let g = [[0.0, 0.0, -781.0], [0.0, 0.0, 0.0], [-781.0, 0.0, 7944.0]];
        let l_um: f64 = 9_710.0;
        let k = std::f64::consts::PI / (l_um * 1e-6);
        let (a, c) = (1e-6, 3e-8);
        let exact = (g[2][2] * c * c + 2.0 * g[0][2] * a * c) * k * k * (l_um * 1e-6) / 4.0;
        let mut errors = Vec::new();
        for n in [32, 64] {
            let (s, segs) = crate::fe::edge_spring::tests::pasternak_line(g, n, l_um);
            let mut e = 0.0;
            for sg in &segs {
                let h_m = (sg.t_um[1] - sg.t_um[0]) * 1e-6;
                let at = |x: f64| ((k * x * 1e-6).cos(), (k * x * 1e-6).sin());
                // The normal in-plane dof is +y; towards the plate (y > 0, outward -1) too.
                let uu = sg.t_um.map(|x| c * at(x).0);
                let seg = InPlaneSegment {
                    dofs: [0, 1],
                    k_h_n_per_m: 0.0,
                    g_over_h_n_per_m: g[2][2] / h_m,
                    cross: None,
                    spring: 0,
                };
                let m = matrix(&seg);
                e += 0.5
                    * (uu[0] * (m[0] * uu[0] + m[1] * uu[1])
                        + uu[1] * (m[2] * uu[0] + m[3] * uu[1]));
                let bend: Vec<f64> = sg
                    .t_um
                    .iter()
                    .flat_map(|&x| {
                        let (cs, sn) = at(x);
                        [a * cs, -a * k * sn, 0.0, 0.0]
                    })
                    .collect();
                let cross = cross_block(&s, h_m, [0.0, 0.0], [g[0][2], g[1][2]]);
                let q: Vec<f64> = bend.iter().copied().chain(uu).collect();
                for i in 0..10 {
                    for j in 0..10 {
                        e += 0.5 * q[i] * cross[i * 10 + j] * q[j];
                    }
                }
            }
            errors.push((e - exact).abs() / exact.abs());
        }
        assert!(
            errors[1] < 1e-3 && errors[1] < 0.3 * errors[0],
            "{errors:?}"
        );
    }
}
