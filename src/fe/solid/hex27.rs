//! The triquadratic 27-node Lagrange hexahedron (isoparametric, 3 displacement dofs per node):
//! shape functions, Jacobian, strain-displacement matrix B, stiffness by 3x3x3 Gauss-Legendre and
//! stress at a local point (Hughes, The Finite Element Method, sec. 3.5-3.9: Lagrange elements as
//! tensor products, Eq. 3.5.6 for the 1-D quadratic; B for 3-D elasticity, Eq. 2.8.23).
//!
//! Local node (a, b, c), each in {0, 1, 2} at xi = -1, 0, 1, is node `a + 3 b + 9 c`; local dof
//! `3 n + d` is displacement component d of node n. Coordinates in metres.

use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::shear_tying::{self, NodeB, TransverseShear};

/// Nodes per element.
pub const NODES: usize = 27;
/// Dofs per element.
pub const DOFS: usize = 81;

/// 1-D quadratic Lagrange on nodes -1, 0, 1: (xi(xi-1)/2, 1-xi^2, xi(xi+1)/2) (Hughes Eq. 3.5.6).
pub fn lagrange2(xi: f64) -> [f64; 3] {
    [0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)]
}

/// Derivatives of [`lagrange2`].
pub fn lagrange2_derivative(xi: f64) -> [f64; 3] {
    [xi - 0.5, -2.0 * xi, xi + 0.5]
}

/// Local coordinate of the 1-D node index 0, 1, 2.
pub fn node_coordinate(a: usize) -> f64 {
    a as f64 - 1.0
}

/// Shape functions N_n(xi, eta, zeta) = l_a(xi) l_b(eta) l_c(zeta).
pub fn shape(xi: [f64; 3]) -> [f64; NODES] {
    let (l0, l1, l2) = (lagrange2(xi[0]), lagrange2(xi[1]), lagrange2(xi[2]));
    std::array::from_fn(|n| l0[n % 3] * l1[(n / 3) % 3] * l2[n / 9])
}

/// Derivatives dN_n / dxi_i of the shape functions, `[n][i]`.
pub fn shape_derivatives(xi: [f64; 3]) -> [[f64; 3]; NODES] {
    let (l0, l1, l2) = (lagrange2(xi[0]), lagrange2(xi[1]), lagrange2(xi[2]));
    let (d0, d1, d2) = (
        lagrange2_derivative(xi[0]),
        lagrange2_derivative(xi[1]),
        lagrange2_derivative(xi[2]),
    );
    std::array::from_fn(|n| {
        let (a, b, c) = (n % 3, (n / 3) % 3, n / 9);
        [
            d0[a] * l1[b] * l2[c],
            l0[a] * d1[b] * l2[c],
            l0[a] * l1[b] * d2[c],
        ]
    })
}

/// 3-point Gauss-Legendre rule on [-1, 1]: points 0, +-sqrt(3/5), weights 8/9, 5/9 (Hughes
/// Table 3.8.1); exact to degree 5.
pub fn gauss3() -> [(f64, f64); 3] {
    let p = (0.6_f64).sqrt();
    [(-p, 5.0 / 9.0), (0.0, 8.0 / 9.0), (p, 5.0 / 9.0)]
}

/// The 27 points and weights of the 3x3x3 tensor Gauss rule, point `a + 3 b + 9 c`.
pub fn gauss_points() -> [([f64; 3], f64); 27] {
    let g = gauss3();
    std::array::from_fn(|n| {
        let (a, b, c) = (g[n % 3], g[(n / 3) % 3], g[n / 9]);
        ([a.0, b.0, c.0], a.1 * b.1 * c.1)
    })
}

/// Shape function gradients in physical space at one local point.
#[derive(Debug, Clone, Copy)]
pub struct PointGeometry {
    /// dN_n / dx_j, `[n][j]`, 1/m.
    pub dn_dx: [[f64; 3]; NODES],
    /// det J = dV / (dxi deta dzeta), m^3.
    pub det_j: f64,
    /// det J divided by the product of the Jacobian's row lengths: 1 for a rectangular box, 0 for
    /// a flat element, negative for an inverted one.
    pub scaled_det_j: f64,
}

/// Isoparametric geometry at `xi`: J_ij = sum_n dN_n/dxi_i x_n,j and dN/dx = J^-1 dN/dxi (Hughes
/// Eq. 3.9.3). With det J <= 0 the gradients are not finite; callers check `det_j` first.
pub fn geometry(nodes_m: &[[f64; 3]; NODES], xi: [f64; 3]) -> PointGeometry {
    let dn = shape_derivatives(xi);
    let j = jacobian_from(&dn, nodes_m);
    let det = det3(&j);
    let norms: f64 = j
        .iter()
        .map(|r| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt())
        .product();
    let inv = inverse3(&j, det);
    // dN/dx_c = sum_r (J^-1)_{c r} dN/dxi_r.
    let dn_dx = std::array::from_fn(|n| {
        std::array::from_fn(|c| (0..3).map(|r| inv[c][r] * dn[n][r]).sum())
    });
    PointGeometry {
        dn_dx,
        det_j: det,
        scaled_det_j: if norms > 0.0 { det / norms } else { 0.0 },
    }
}

/// Jacobian J_ij = dx_j / dxi_i at `xi` (nodes in any length unit).
pub fn jacobian(nodes: &[[f64; 3]; NODES], xi: [f64; 3]) -> [[f64; 3]; 3] {
    jacobian_from(&shape_derivatives(xi), nodes)
}

fn jacobian_from(dn: &[[f64; 3]; NODES], nodes: &[[f64; 3]; NODES]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (d, x) in dn.iter().zip(nodes) {
        for r in 0..3 {
            for c in 0..3 {
                j[r][c] += d[r] * x[c];
            }
        }
    }
    j
}

/// Solves J^T dxi = r (one Newton step of the inverse map x(xi) = p), Cramer's rule; None if J
/// is singular.
pub fn solve_transposed(j: &[[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let t: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| j[b][a]));
    let det = det3(&t);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(std::array::from_fn(|k| {
        let mut m = t;
        for (row, v) in m.iter_mut().zip(r) {
            row[k] = v;
        }
        det3(&m) / det
    }))
}

/// Determinant of a 3 x 3 matrix.
pub(crate) fn det3(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Inverse of a 3 x 3 matrix by its adjugate, given its determinant.
pub(crate) fn inverse3(m: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    let mut inv = [[0.0; 3]; 3];
    for (r, row) in inv.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            // Adjugate: cofactor of (c, r).
            let (r1, r2) = ((c + 1) % 3, (c + 2) % 3);
            let (c1, c2) = ((r + 1) % 3, (r + 2) % 3);
            *v = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
        }
    }
    inv
}

/// The smallest scaled Jacobian determinant over the 27 Gauss points (see
/// [`PointGeometry::scaled_det_j`]).
pub fn min_scaled_jacobian(nodes_m: &[[f64; 3]; NODES]) -> f64 {
    gauss_points()
        .iter()
        .map(|(xi, _)| geometry(nodes_m, *xi).scaled_det_j)
        .fold(f64::INFINITY, f64::min)
}

/// Strain (Voigt, engineering shears) from element displacements: eps = B u with B_n =
/// `[[Nx,0,0],[0,Ny,0],[0,0,Nz],[0,Nz,Ny],[Nz,0,Nx],[Ny,Nx,0]]` (Hughes Eq. 2.8.23, our Voigt
/// order).
pub fn strain(dn_dx: &[[f64; 3]; NODES], u_m: &[f64; DOFS]) -> [f64; 6] {
    let mut e = [0.0; 6];
    for (n, g) in dn_dx.iter().enumerate() {
        let (ux, uy, uz) = (u_m[3 * n], u_m[3 * n + 1], u_m[3 * n + 2]);
        e[0] += g[0] * ux;
        e[1] += g[1] * uy;
        e[2] += g[2] * uz;
        e[3] += g[2] * uy + g[1] * uz;
        e[4] += g[2] * ux + g[0] * uz;
        e[5] += g[1] * ux + g[0] * uy;
    }
    e
}

/// Element stiffness K = sum_g w_g B^T C B det J (3x3x3 Gauss, Hughes Eq. 3.9.4), row-major
/// 81 x 81, N/m, with the transverse shears taken as `shear` says ([`shear_tying`]). The caller
/// has checked that det J > 0 at every Gauss point.
pub fn stiffness(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    shear: TransverseShear,
) -> Vec<f64> {
    let c = &material.c_pa;
    let mut k = vec![0.0; DOFS * DOFS];
    let tied = shear_tying::ties(nodes_m, shear);
    for (xi, w) in gauss_points() {
        let (g, bn) = shear_tying::b_at(nodes_m, xi, tied);
        let f = w * g.det_j;
        // C B_b for every node b: 6 x 3 blocks (columns u_x, u_y, u_z; B's zeros skipped).
        let cb: [[[f64; 3]; 6]; NODES] = std::array::from_fn(|b| {
            let NodeB {
                n: [nx, ny, nz],
                yz,
                xz,
            } = bn[b];
            std::array::from_fn(|r| {
                let row = &c[r];
                [
                    row[0] * nx + row[4] * xz[0] + row[5] * ny,
                    row[1] * ny + row[3] * yz[0] + row[5] * nx,
                    row[2] * nz + row[3] * yz[1] + row[4] * xz[1],
                ]
            })
        });
        for a in 0..NODES {
            let NodeB {
                n: [nx, ny, nz],
                yz,
                xz,
            } = bn[a];
            for (b, x) in cb.iter().enumerate().skip(a) {
                // B_a^T X, using the sparsity of B_a.
                for j in 0..3 {
                    let r0 = nx * x[0][j] + xz[0] * x[4][j] + ny * x[5][j];
                    let r1 = ny * x[1][j] + yz[0] * x[3][j] + nx * x[5][j];
                    let r2 = nz * x[2][j] + yz[1] * x[3][j] + xz[1] * x[4][j];
                    k[(3 * a) * DOFS + 3 * b + j] += f * r0;
                    k[(3 * a + 1) * DOFS + 3 * b + j] += f * r1;
                    k[(3 * a + 2) * DOFS + 3 * b + j] += f * r2;
                }
            }
        }
    }
    // Lower node blocks from the upper ones (K is symmetric).
    for a in 0..NODES {
        for b in 0..a {
            for i in 0..3 {
                for j in 0..3 {
                    k[(3 * a + i) * DOFS + 3 * b + j] = k[(3 * b + j) * DOFS + 3 * a + i];
                }
            }
        }
    }
    k
}

/// Stress sigma = C B(xi) u (Voigt, Pa) at local point `xi`, the shears taken as `shear` says.
pub fn stress_pa(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [f64; 6] {
    material.stress_pa(&shear_tying::strain_at(nodes_m, u_m, xi, shear))
}

/// Position x(xi) = sum_n N_n(xi) x_n.
pub fn position(nodes: &[[f64; 3]; NODES], xi: [f64; 3]) -> [f64; 3] {
    let n = shape(xi);
    std::array::from_fn(|d| (0..NODES).map(|k| n[k] * nodes[k][d]).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box element [0, a] x [0, b] x [0, c] (m) with an optional distortion of the inner nodes.
    fn box_nodes(a: f64, b: f64, c: f64) -> [[f64; 3]; NODES] {
        std::array::from_fn(|n| {
            let (i, j, k) = (n % 3, (n / 3) % 3, n / 9);
            [0.5 * a * i as f64, 0.5 * b * j as f64, 0.5 * c * k as f64]
        })
    }

    fn curved() -> [[f64; 3]; NODES] {
        let mut x = box_nodes(2.0, 1.5, 1.0);
        for (n, p) in x.iter_mut().enumerate() {
            let (i, j, k) = (n % 3, (n / 3) % 3, n / 9);
            // Move mid-side and interior nodes: curved edges and faces.
            if i == 1 || j == 1 || k == 1 {
                p[0] += 0.1 * (n as f64 * 0.7).sin();
                p[1] += 0.08 * (n as f64 * 1.3).cos();
                p[2] += 0.05 * (n as f64 * 0.4).sin();
            }
        }
        x
    }

    #[test]
    fn partition_of_unity_and_kronecker() {
        let xi = [0.3, -0.7, 0.55];
        let n = shape(xi);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        let dn = shape_derivatives(xi);
        for i in 0..3 {
            assert!(dn.iter().map(|d| d[i]).sum::<f64>().abs() < 1e-14);
        }
        for m in 0..NODES {
            let at = [
                node_coordinate(m % 3),
                node_coordinate((m / 3) % 3),
                node_coordinate(m / 9),
            ];
            let n = shape(at);
            for (k, v) in n.iter().enumerate() {
                assert!((v - if k == m { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
        // Derivatives against central differences.
        let h = 1e-6;
        for i in 0..3 {
            let (mut p, mut q) = (xi, xi);
            p[i] += h;
            q[i] -= h;
            let (np, nq) = (shape(p), shape(q));
            for k in 0..NODES {
                assert!(((np[k] - nq[k]) / (2.0 * h) - dn[k][i]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn volume_and_rigid_modes() {
        let x = curved();
        let vol: f64 = gauss_points()
            .iter()
            .map(|(xi, w)| w * geometry(&x, *xi).det_j)
            .sum();
        // The box's volume is 3; the perturbation changes it, the unperturbed box gives it exactly.
        let vb: f64 = gauss_points()
            .iter()
            .map(|(xi, w)| w * geometry(&box_nodes(2.0, 1.5, 1.0), *xi).det_j)
            .sum();
        assert!((vb - 3.0).abs() < 1e-13 && (vol - 3.0).abs() < 0.3);
        for shear in [TransverseShear::Displacement, TransverseShear::Tied] {
            rigid_modes_check(&x, &stiffness(&x, &Elasticity::isotropic(1e9, 0.3), shear));
        }
    }

    fn rigid_modes_check(x: &[[f64; 3]; NODES], k: &[f64]) {
        // Six rigid modes (3 translations, 3 rotations) give zero force.
        for mode in 0..6 {
            let u: Vec<f64> = (0..DOFS)
                .map(|d| {
                    let p = x[d / 3];
                    let r = [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]];
                    if mode < 3 {
                        f64::from(u8::from(d % 3 == mode))
                    } else {
                        r[d % 3][mode - 3]
                    }
                })
                .collect();
            let f = (0..DOFS)
                .map(|i| (0..DOFS).map(|j| k[i * DOFS + j] * u[j]).sum::<f64>().abs())
                .fold(0.0, f64::max);
            assert!(f < 1e-6 * 1e9, "mode {mode}: {f}");
        }
        // Symmetric, positive diagonal.
        for i in 0..DOFS {
            assert!(k[i * DOFS + i] > 0.0);
            for j in 0..DOFS {
                assert!((k[i * DOFS + j] - k[j * DOFS + i]).abs() < 1e-6);
            }
        }
    }

    /// A linear displacement field gives its constant strain at every point, and the energy
    /// u^T K u / 2 equals eps C eps V / 2 (an independent check of B and of the quadrature).
    #[test]
    fn linear_field_strain_and_energy() {
        let x = curved();
        let c = Elasticity::cubic(165.7e9, 63.9e9, 79.6e9).rotated_about_z(30.0);
        let g = [
            [1e-3, 2e-4, -3e-4],
            [5e-4, -2e-3, 1e-4],
            [-4e-4, 6e-4, 1.5e-3],
        ];
        let u: [f64; DOFS] = std::array::from_fn(|d| {
            let p = x[d / 3];
            (0..3).map(|j| g[d % 3][j] * p[j]).sum()
        });
        let eps = crate::fe::solid::tests::voigt_strain(&g);
        for xi in [[0.1, 0.2, -0.9], [-1.0, 1.0, 0.0]] {
            let e = strain(&geometry(&x, xi).dn_dx, &u);
            for (a, b) in e.iter().zip(&eps) {
                assert!((a - b).abs() < 1e-13, "{e:?}");
            }
        }
        for shear in [TransverseShear::Displacement, TransverseShear::Tied] {
            for xi in [[0.1, 0.2, -0.9], [-1.0, 1.0, 0.0]] {
                let e = shear_tying::strain_at(&x, &u, xi, shear);
                for (a, b) in e.iter().zip(&eps) {
                    assert!((a - b).abs() < 1e-13, "{shear:?} {e:?}");
                }
            }
            energy_check(&x, &c, &u, &eps, &stiffness(&x, &c, shear));
        }
    }

    fn energy_check(
        x: &[[f64; 3]; NODES],
        c: &Elasticity,
        u: &[f64; DOFS],
        eps: &[f64; 6],
        k: &[f64],
    ) {
        let energy: f64 = (0..DOFS)
            .map(|i| u[i] * (0..DOFS).map(|j| k[i * DOFS + j] * u[j]).sum::<f64>())
            .sum::<f64>()
            * 0.5;
        let vol: f64 = gauss_points()
            .iter()
            .map(|(xi, w)| w * geometry(x, *xi).det_j)
            .sum();
        let s = c.stress_pa(eps);
        let expect = 0.5 * vol * (0..6).map(|i| s[i] * eps[i]).sum::<f64>();
        assert!(
            (energy - expect).abs() < 1e-10 * expect,
            "{energy} {expect}"
        );
    }

    #[test]
    fn scaled_jacobian_flags_inverted() {
        assert!((min_scaled_jacobian(&box_nodes(1.0, 2.0, 3.0)) - 1.0).abs() < 1e-14);
        let mut x = box_nodes(1.0, 1.0, 1.0);
        // Push the mid-edge node of an x edge past the far corner: inverted near that corner.
        x[1][0] = 1.5;
        assert!(min_scaled_jacobian(&x) < 0.0);
    }
}
