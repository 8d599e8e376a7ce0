//! The 3-D Q2/P1 (B-bar) brick for nearly incompressible tissue: the 27-node triquadratic
//! hexahedron of [`crate::fe::solid::hex27`] (isoparametric, shape functions and Jacobian reused)
//! with a linear discontinuous pressure per element condensed out.
//!
//! Formulation (Hughes, The Finite Element Method, 1987, sec. 4.5; the 3-D form of the plane
//! element of [`super::continuum`]): K = mu K_mu + lambda K_lambda with
//! K_mu = int B^T D_mu B dV, D_mu = diag(2, 2, 2, 1, 1, 1) on (e_xx, e_yy, e_zz, g_yz, g_zx, g_xy),
//! and the volumetric part replaced by its projection onto discontinuous pressures
//! pi = {1, (x - x_c) / s, (y - y_c) / s, (z - z_c) / s} (physical coordinates about the element's
//! node mean x_c, scaled by its largest extent s): K_lambda = Bv^T G^-1 Bv,
//! G_ab = int pi_a pi_b dV, Bv_ai = int pi_a div N_i dV. This is the mixed Q2/P1 element
//! (inf-sup stable, Brezzi & Fortin 1991) with the pressure eliminated per element; a physical
//! (unmapped) P1 keeps its approximation order on distorted bricks (Arnold, Boffi & Falk 2002).
//! The material is the caller's per element (K = (1 - f) K_tissue + f K_lump by volume share in
//! [`super::slab3d`]), so the element returns the two parts K_mu / mu and K_lambda / lambda.
//!
//! Local node (a, b, c) is node a + 3 b + 9 c (hex27's order), dof 3 n + d.

use crate::fe::solid::hex27::{self, DOFS, NODES};

/// One brick: its stiffness parts and its pressure projection.
#[derive(Debug, Clone, PartialEq)]
pub struct BrickQ2 {
    /// K_mu / mu and K_lambda / lambda, 81 x 81 row-major.
    pub kmu: Vec<f64>,
    pub klam: Vec<f64>,
    /// G^-1 Bv (4 x 81): the projected dilatation's coefficients on pi.
    proj: Vec<f64>,
    nodes: [[f64; 3]; NODES],
    centre: [f64; 3],
    scale: f64,
}

/// Solves the 4 x 4 symmetric positive definite system G x = b for each column of `b` (4 x n,
/// row-major) by Cholesky.
fn solve4(g: &[f64; 16], b: &[f64], n: usize) -> Vec<f64> {
    let mut l = [0.0; 16];
    for i in 0..4 {
        for j in 0..=i {
            let s: f64 = g[4 * i + j] - (0..j).map(|k| l[4 * i + k] * l[4 * j + k]).sum::<f64>();
            l[4 * i + j] = if i == j { s.sqrt() } else { s / l[4 * j + j] };
        }
    }
    let mut x = b.to_vec();
    for c in 0..n {
        for i in 0..4 {
            let s: f64 = (0..i).map(|k| l[4 * i + k] * x[k * n + c]).sum();
            x[i * n + c] = (x[i * n + c] - s) / l[4 * i + i];
        }
        for i in (0..4).rev() {
            let s: f64 = (i + 1..4).map(|k| l[4 * k + i] * x[k * n + c]).sum();
            x[i * n + c] = (x[i * n + c] - s) / l[4 * i + i];
        }
    }
    x
}

impl BrickQ2 {
    fn pi(&self, p: [f64; 3]) -> [f64; 4] {
        let s = self.scale;
        [
            1.0,
            (p[0] - self.centre[0]) / s,
            (p[1] - self.centre[1]) / s,
            (p[2] - self.centre[2]) / s,
        ]
    }

    /// Stress (Voigt: s_xx, s_yy, s_zz, t_yz, t_zx, t_xy, Pa) at local point `xi` from the 81
    /// nodal displacements: sigma = 2 mu eps + lambda theta_bar I (theta_bar the projected
    /// dilatation), shear mu gamma.
    pub fn stress(&self, u: &[f64; DOFS], lam: f64, mu: f64, xi: [f64; 3]) -> [f64; 6] {
        let g = hex27::geometry(&self.nodes, xi);
        let e = hex27::strain(&g.dn_dx, u);
        let pi = self.pi(hex27::position(&self.nodes, xi));
        let theta: f64 = (0..4)
            .map(|a| {
                pi[a]
                    * (0..DOFS)
                        .map(|i| self.proj[a * DOFS + i] * u[i])
                        .sum::<f64>()
            })
            .sum();
        [
            2.0 * mu * e[0] + lam * theta,
            2.0 * mu * e[1] + lam * theta,
            2.0 * mu * e[2] + lam * theta,
            mu * e[3],
            mu * e[4],
            mu * e[5],
        ]
    }
}

/// The Q2/P1 (B-bar) brick on `nodes_m` (hex27's local order), 3 x 3 x 3 Gauss. Panics on an
/// inverted or degenerate element (a meshing bug).
#[track_caller]
pub fn brick_q2(nodes_m: &[[f64; 3]; NODES]) -> BrickQ2 {
    let centre: [f64; 3] =
        std::array::from_fn(|d| nodes_m.iter().map(|p| p[d]).sum::<f64>() / NODES as f64);
    let scale = (0..3)
        .map(|d| {
            let (lo, hi) = nodes_m
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                    (a.0.min(p[d]), a.1.max(p[d]))
                });
            hi - lo
        })
        .fold(0.0, f64::max);
    let mut kmu = vec![0.0; DOFS * DOFS];
    let mut gm = [0.0; 16];
    let mut bv = vec![0.0; 4 * DOFS];
    let mut out = BrickQ2 {
        kmu: Vec::new(),
        klam: Vec::new(),
        proj: Vec::new(),
        nodes: *nodes_m,
        centre,
        scale,
    };
    for (xi, wq) in hex27::gauss_points() {
        let geo = hex27::geometry(nodes_m, xi);
        assert!(
            geo.det_j > 0.0 && geo.scaled_det_j > 1e-8,
            "brick inverted or degenerate (det J = {}): a meshing bug",
            geo.det_j
        );
        let w = wq * geo.det_j;
        let g = &geo.dn_dx;
        // 2 mu eps:eps = mu (u_d,k u_d,k + u_d,k u_k,d): node pair (n, m), components (d, e):
        // delta_de sum_k g_n,k g_m,k + g_n,e g_m,d.
        for n in 0..NODES {
            for m in 0..NODES {
                let dot = g[n][0] * g[m][0] + g[n][1] * g[m][1] + g[n][2] * g[m][2];
                for d in 0..3 {
                    let row = (3 * n + d) * DOFS + 3 * m;
                    for e in 0..3 {
                        let diag = if d == e { dot } else { 0.0 };
                        kmu[row + e] += w * (diag + g[n][e] * g[m][d]);
                    }
                }
            }
        }
        let pi = out.pi(hex27::position(nodes_m, xi));
        for a in 0..4 {
            for c in 0..4 {
                gm[4 * a + c] += w * pi[a] * pi[c];
            }
            for n in 0..NODES {
                for d in 0..3 {
                    bv[a * DOFS + 3 * n + d] += w * pi[a] * g[n][d];
                }
            }
        }
    }
    let proj = solve4(&gm, &bv, DOFS);
    let mut klam = vec![0.0; DOFS * DOFS];
    for i in 0..DOFS {
        for j in 0..DOFS {
            klam[i * DOFS + j] = (0..4).map(|a| bv[a * DOFS + i] * proj[a * DOFS + j]).sum();
        }
    }
    out.kmu = kmu;
    out.klam = klam;
    out.proj = proj;
    out
}

/// The nodes of the box [x0, x0 + h_x] x [y0, y0 + h_y] x [z0, z0 + h_z] in hex27's order.
pub fn box_nodes(origin_m: [f64; 3], size_m: [f64; 3]) -> [[f64; 3]; NODES] {
    std::array::from_fn(|n| {
        let abc = [n % 3, (n / 3) % 3, n / 9];
        std::array::from_fn(|d| origin_m[d] + 0.5 * size_m[d] * abc[d] as f64)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A skewed brick with curved edges and faces: corners moved, mid-side, face and centre
    /// nodes off their straight positions.
    fn distorted() -> [[f64; 3]; NODES] {
        let mut p = box_nodes([0.2, -0.1, 0.3], [2.0, 1.0, 1.5]);
        for (n, q) in p.iter_mut().enumerate() {
            let (x, y, z) = (q[0], q[1], q[2]);
            q[0] += 0.15 * y + 0.05 * z * z + 0.02 * (n % 5) as f64;
            q[1] += 0.1 * x * z - 0.03 * (n % 3) as f64;
            q[2] += 0.12 * x - 0.04 * y * y + 0.01 * (n % 7) as f64;
        }
        p
    }

    fn apply(k: &[f64], u: &[f64]) -> Vec<f64> {
        (0..DOFS)
            .map(|i| (0..DOFS).map(|j| k[i * DOFS + j] * u[j]).sum())
            .collect()
    }

    #[test]
    fn a_distorted_brick_passes_the_patch_test() {
        // A uniform strain u = E x + c (E general, not symmetric: a rotation part too) on a
        // skewed, curved brick: the recovered stress is the constant of the field at every
        // point, and the rigid motions (translations, infinitesimal rotations) carry no force.
        let (lam, mu) = (7.0, 1.3);
        let grad = [
            [1e-3, 2e-4, -3e-4],
            [5e-4, -2e-3, 1e-4],
            [-4e-4, 3e-4, 1.5e-3],
        ];
        let eps = |i: usize, j: usize| 0.5 * (grad[i][j] + grad[j][i]);
        let tr = eps(0, 0) + eps(1, 1) + eps(2, 2);
        let want = [
            2.0 * mu * eps(0, 0) + lam * tr,
            2.0 * mu * eps(1, 1) + lam * tr,
            2.0 * mu * eps(2, 2) + lam * tr,
            2.0 * mu * eps(1, 2),
            2.0 * mu * eps(2, 0),
            2.0 * mu * eps(0, 1),
        ];
        let nodes = distorted();
        let b = brick_q2(&nodes);
        let u: [f64; DOFS] = std::array::from_fn(|i| {
            let (n, d) = (i / 3, i % 3);
            (0..3).map(|j| grad[d][j] * nodes[n][j]).sum::<f64>() + 0.01 * d as f64
        });
        let mut worst: f64 = 0.0;
        for xi in [
            [-0.9, -1.0, 0.2],
            [0.3, -0.7, 0.8],
            [1.0, 1.0, 1.0],
            [0.0; 3],
        ] {
            let s = b.stress(&u, lam, mu, xi);
            for q in 0..6 {
                worst = worst.max((s[q] - want[q]).abs());
            }
        }
        eprintln!("patch test: worst stress error {worst:.2e} (stress scale ~1e-2)");
        assert!(worst < 1e-13, "{worst}");
        let k: Vec<f64> = b
            .kmu
            .iter()
            .zip(&b.klam)
            .map(|(a, c)| mu * a + lam * c)
            .collect();
        for rigid in 0..6 {
            let v: Vec<f64> = (0..DOFS)
                .map(|i| {
                    let (x, d) = (nodes[i / 3], i % 3);
                    if rigid < 3 {
                        f64::from(u8::from(d == rigid))
                    } else {
                        // omega x r about axis rigid - 3.
                        let a = rigid - 3;
                        let (p, q) = ((a + 1) % 3, (a + 2) % 3);
                        if d == p {
                            -x[q]
                        } else if d == q {
                            x[p]
                        } else {
                            0.0
                        }
                    }
                })
                .collect();
            let f = apply(&k, &v);
            let worst = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(worst < 1e-12, "rigid {rigid}: {worst}");
        }
    }

    #[test]
    fn the_parts_are_symmetric_and_the_volumetric_part_is_the_projected_dilatation() {
        let nodes = distorted();
        let b = brick_q2(&nodes);
        let big = b.kmu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..DOFS {
            for j in 0..DOFS {
                assert!((b.kmu[i * DOFS + j] - b.kmu[j * DOFS + i]).abs() < 1e-12 * big);
                assert!((b.klam[i * DOFS + j] - b.klam[j * DOFS + i]).abs() < 1e-12 * big);
            }
        }
        // u = x / 3 (div u = 1): u^T K_lambda u = int 1 dV = the volume (sum of w det J), and
        // u^T K_mu u = int 2 |eps_dev + I/3|^2 = 2 x 3 x (1/3)^2 V = 2 V / 3.
        let vol: f64 = hex27::gauss_points()
            .iter()
            .map(|(xi, w)| w * hex27::geometry(&nodes, *xi).det_j)
            .sum();
        let u: Vec<f64> = (0..DOFS).map(|i| nodes[i / 3][i % 3] / 3.0).collect();
        let el: f64 = u.iter().zip(apply(&b.klam, &u)).map(|(a, c)| a * c).sum();
        let em: f64 = u.iter().zip(apply(&b.kmu, &u)).map(|(a, c)| a * c).sum();
        assert!((el / vol - 1.0).abs() < 1e-12, "{el} vs {vol}");
        assert!((em / (2.0 * vol / 3.0) - 1.0).abs() < 1e-12, "{em}");
        // An isochoric field (u = (y, 0, 0), div u = 0, linear so exactly in the P1 space):
        // no volumetric energy.
        let u: Vec<f64> = (0..DOFS)
            .map(|i| if i % 3 == 0 { nodes[i / 3][1] } else { 0.0 })
            .collect();
        let el: f64 = u.iter().zip(apply(&b.klam, &u)).map(|(a, c)| a * c).sum();
        assert!(el.abs() < 1e-12 * vol, "{el}");
    }

    #[test]
    fn the_box_brick_matches_a_separable_check() {
        // On a box, with u_x = x^2 (div u = 2 x: linear, so the projection is exact):
        // u^T K_lambda u = int (2x)^2 dV and u^T K_mu u = int 2 (2 x)^2 dV (one strain e_xx).
        let (h, o) = ([0.7, 1.1, 0.4], [0.3, -0.2, 0.5]);
        let nodes = box_nodes(o, h);
        let b = brick_q2(&nodes);
        let u: Vec<f64> = (0..DOFS)
            .map(|i| {
                if i % 3 == 0 {
                    nodes[i / 3][0].powi(2)
                } else {
                    0.0
                }
            })
            .collect();
        let (x0, x1) = (o[0], o[0] + h[0]);
        let int_x2 = (x1.powi(3) - x0.powi(3)) / 3.0 * h[1] * h[2];
        let el: f64 = u.iter().zip(apply(&b.klam, &u)).map(|(a, c)| a * c).sum();
        let em: f64 = u.iter().zip(apply(&b.kmu, &u)).map(|(a, c)| a * c).sum();
        assert!((el / (4.0 * int_x2) - 1.0).abs() < 1e-12, "{el}");
        assert!((em / (8.0 * int_x2) - 1.0).abs() < 1e-12, "{em}");
        // A quadratic dilatation (u_x = x^3 / 3 is not in Q2; u_x = x^2 y: div = 2 x y, not in
        // P1) is projected: the volumetric energy is below the full integral.
        let u: Vec<f64> = (0..DOFS)
            .map(|i| {
                let p = nodes[i / 3];
                if i % 3 == 0 {
                    p[0] * p[0] * p[1]
                } else {
                    0.0
                }
            })
            .collect();
        let el: f64 = u.iter().zip(apply(&b.klam, &u)).map(|(a, c)| a * c).sum();
        let (y0, y1) = (o[1], o[1] + h[1]);
        let full = 4.0 * (x1.powi(3) - x0.powi(3)) / 3.0 * (y1.powi(3) - y0.powi(3)) / 3.0 * h[2];
        assert!(el < full * (1.0 - 1e-3) && el > 0.0, "{el} vs {full}");
    }

    #[test]
    #[should_panic(expected = "inverted")]
    fn an_inverted_brick_is_a_meshing_bug() {
        let mut p = box_nodes([0.0; 3], [1.0; 3]);
        for q in p.iter_mut() {
            q[0] = -q[0];
        }
        brick_q2(&p);
    }
}
