//! The Q2/P1 (B-bar) element of [`super::mapped`] for axisymmetric bodies: meridian coordinates
//! (r, z), displacements (u_r, u_z), no twist. The strains gain the hoop term
//! e_thth = u_r / r (Zienkiewicz & Taylor, The Finite Element Method, vol. 1, 6th ed., ch. 5):
//! eps = (e_rr, e_zz, e_thth, g_rz) = (du_r/dr, du_z/dz, u_r/r, du_r/dz + du_z/dr), and every
//! integral carries the circumference, here per radian: dV = r dr dz.
//!
//! As in the plane element, K = mu K_mu + lambda K_lambda with D_mu = diag(2, 2, 2, 1) and the
//! volumetric part projected onto discontinuous pressures pi = {1, xi, eta} (Hughes, The Finite
//! Element Method, 1987, sec. 4.5): K_lambda = Bv^T G^-1 Bv, G_ab = int pi_a pi_b r dA,
//! Bv_ai = int pi_a div N_i r dA, div = e_rr + e_zz + e_thth. The weight r makes G full even on
//! a rectangle.
//!
//! The axis r = 0: the 3 x 3 Gauss points are interior, so u_r / r is never evaluated there; a
//! node on the axis must have u_r = 0 (the caller's boundary condition), and an element may be
//! collapsed to a point on the axis (a polar mesh's centre) since det J vanishes only on its edge.

use super::continuum::{gauss, lagrange};
use super::mapped::Projection;

/// One axisymmetric element: its stiffness parts (per radian) and its pressure projection.
#[derive(Debug, Clone, PartialEq)]
pub struct AxiQ2 {
    /// K_mu / mu and K_lambda / lambda, 18 x 18 row-major (dofs u_r, u_z per local node).
    pub kmu: Vec<f64>,
    pub klam: Vec<f64>,
    /// G^-1 Bv (3 x 18): the projected dilatation's coefficients on {1, xi, eta}.
    proj: Vec<f64>,
    rz: [(f64, f64); 9],
}

/// Shape functions, their (d/dr, d/dz) and r and det J at (xi, eta).
#[track_caller]
fn at(rz: &[(f64, f64); 9], xi: f64, eta: f64) -> ([f64; 9], [(f64, f64); 9], f64, f64) {
    let (nx, dx) = lagrange(2, xi);
    let (ny, dy) = lagrange(2, eta);
    let mut n = [0.0; 9];
    let mut dn = [(0.0, 0.0); 9];
    let (mut j11, mut j12, mut j21, mut j22, mut r) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in 0..9 {
        let (a, b) = (k % 3, k / 3);
        n[k] = nx[a] * ny[b];
        dn[k] = (dx[a] * ny[b], nx[a] * dy[b]);
        j11 += dn[k].0 * rz[k].0;
        j12 += dn[k].0 * rz[k].1;
        j21 += dn[k].1 * rz[k].0;
        j22 += dn[k].1 * rz[k].1;
        r += n[k] * rz[k].0;
    }
    let det = j11 * j22 - j12 * j21;
    assert!(
        det > 0.0 && r > 0.0,
        "axisymmetric element inverted, degenerate or across the axis (det J = {det}, r = {r}): \
         nodes must run counter-clockwise at r >= 0"
    );
    let g = dn.map(|(a, b)| ((j22 * a - j12 * b) / det, (-j21 * a + j11 * b) / det));
    (n, g, r, det)
}

/// The 4 strains (e_rr, e_zz, e_thth, g_rz) of dof i (node i / 2, component i % 2).
fn strain_of(i: usize, n: &[f64; 9], g: &[(f64, f64); 9], r: f64) -> [f64; 4] {
    let k = i / 2;
    if i.is_multiple_of(2) {
        [g[k].0, 0.0, n[k] / r, g[k].1]
    } else {
        [0.0, g[k].1, 0.0, g[k].0]
    }
}

/// The axisymmetric Q2/P1 element on meridian nodes `rz` (local node k = 3 b + a at
/// (xi_a, eta_b), counter-clockwise in (r, z)). Panics on an inverted element (a meshing bug).
#[track_caller]
pub fn axi_q2(rz: &[(f64, f64); 9]) -> AxiQ2 {
    const ND: usize = 18;
    let g3 = gauss(3);
    let mut kmu = vec![0.0; ND * ND];
    let mut projection = Projection::new();
    for &(xi, wx) in &g3 {
        for &(eta, wy) in &g3 {
            let (n, grad, r, det) = at(rz, xi, eta);
            let w = wx * wy * det * r;
            let b: Vec<[f64; 4]> = (0..ND).map(|i| strain_of(i, &n, &grad, r)).collect();
            for i in 0..ND {
                for j in 0..ND {
                    let (p, q) = (b[i], b[j]);
                    kmu[i * ND + j] +=
                        w * (2.0 * (p[0] * q[0] + p[1] * q[1] + p[2] * q[2]) + p[3] * q[3]);
                }
            }
            let div: [f64; ND] = std::array::from_fn(|i| b[i][0] + b[i][1] + b[i][2]);
            projection.add(wx * wy * det, r, xi, eta, &div);
        }
    }
    let (proj, klam) = projection.finish();
    AxiQ2 {
        kmu,
        klam,
        proj,
        rz: *rz,
    }
}

impl AxiQ2 {
    /// Stress (sigma_rr, sigma_zz, sigma_thth, tau_rz) at (xi, eta) inside the element from its
    /// 18 nodal displacements: sigma = 2 mu eps + lambda theta_bar I, theta_bar the projected
    /// dilatation. (xi, eta) must not lie on the axis (u_r / r): use an interior point there.
    #[track_caller]
    pub fn stress(&self, u: &[f64; 18], lam: f64, mu: f64, xi: f64, eta: f64) -> [f64; 4] {
        let (n, grad, r, _) = at(&self.rz, xi, eta);
        let mut e = [0.0; 4];
        for (i, ui) in u.iter().enumerate() {
            let b = strain_of(i, &n, &grad, r);
            for c in 0..4 {
                e[c] += b[c] * ui;
            }
        }
        let pi = [1.0, xi, eta];
        let theta: f64 = (0..3)
            .map(|a| pi[a] * (0..18).map(|i| self.proj[a * 18 + i] * u[i]).sum::<f64>())
            .sum();
        [
            2.0 * mu * e[0] + lam * theta,
            2.0 * mu * e[1] + lam * theta,
            2.0 * mu * e[2] + lam * theta,
            mu * e[3],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rectangle r0..r0 + hr x z0..z0 + hz.
    fn rectangle(r0: f64, z0: f64, hr: f64, hz: f64) -> [(f64, f64); 9] {
        std::array::from_fn(|k| {
            let (a, b) = ((k % 3) as f64, (k / 3) as f64);
            (r0 + 0.5 * hr * a, z0 + 0.5 * hz * b)
        })
    }

    #[test]
    fn a_distorted_element_passes_the_axisymmetric_patch_test() {
        // u_r = a r, u_z = c z + d (a uniform strain: e_rr = e_thth = a, e_zz = c) on a skewed,
        // curved-edged element, one on the axis: the recovered stress is the field's constant
        // everywhere, and K u is the boundary traction only, so its axial rows sum to zero
        // against a rigid axial shift.
        let (lam, mu) = (3.0, 1.5);
        let (a, c) = (1e-3, -2e-3);
        let want = [
            2.0 * mu * a + lam * (2.0 * a + c),
            2.0 * mu * c + lam * (2.0 * a + c),
            2.0 * mu * a + lam * (2.0 * a + c),
            0.0,
        ];
        let mut skew = rectangle(0.5, 0.0, 2.0, 1.0);
        skew[2].0 += 0.4;
        skew[8].1 += 0.3;
        skew[4].0 += 0.1;
        skew[7].1 += 0.05;
        for rz in [skew, rectangle(0.0, -1.0, 0.7, 0.4)] {
            let m = axi_q2(&rz);
            let u: [f64; 18] = std::array::from_fn(|i| {
                let (r, z) = rz[i / 2];
                if i % 2 == 0 {
                    a * r
                } else {
                    c * z + 0.2
                }
            });
            for &(xi, eta) in &[(-0.9, -1.0), (0.3, -0.7), (1.0, 1.0)] {
                let s = m.stress(&u, lam, mu, xi, eta);
                for q in 0..4 {
                    assert!((s[q] - want[q]).abs() < 1e-12, "{s:?} vs {want:?}");
                }
            }
            // A rigid shift along the axis carries no force (the only rigid motion: a radial
            // shift strains the hoops).
            for row in 0..18 {
                let f: f64 = (0..9)
                    .map(|k| mu * m.kmu[row * 18 + 2 * k + 1] + lam * m.klam[row * 18 + 2 * k + 1])
                    .sum();
                assert!(f.abs() < 1e-12, "row {row}: {f}");
            }
        }
    }

    #[test]
    fn the_volumetric_part_is_the_projected_dilatation() {
        // K_lambda is symmetric positive semi-definite, and a pure dilatation u_r = r / 2,
        // u_z = 0 (div u = 1) on one element gives u^T K_lambda u = int 1 r dA exactly.
        let rz = rectangle(0.3, 0.0, 0.5, 0.8);
        let m = axi_q2(&rz);
        for i in 0..18 {
            for j in 0..18 {
                let (p, q) = (m.klam[i * 18 + j], m.klam[j * 18 + i]);
                assert!((p - q).abs() < 1e-13, "{i} {j}");
            }
        }
        let u: [f64; 18] =
            std::array::from_fn(|i| if i % 2 == 0 { 0.5 * rz[i / 2].0 } else { 0.0 });
        let e: f64 = (0..18)
            .map(|i| u[i] * (0..18).map(|j| m.klam[i * 18 + j] * u[j]).sum::<f64>())
            .sum();
        // int_0.3^0.8 r dr x 0.8 = (0.64 - 0.09) / 2 x 0.8.
        let want = 0.5 * (0.8f64 * 0.8 - 0.3 * 0.3) * 0.8;
        assert!((e - want).abs() < 1e-12, "{e} vs {want}");
    }
}
