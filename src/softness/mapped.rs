//! The Q2/P1 (B-bar) plane-strain quadrilateral of [`super::continuum`] on arbitrary node
//! positions: the isoparametric map x(xi, eta) = sum N_k x_k (Zienkiewicz & Taylor, The Finite
//! Element Method, vol. 1, 6th ed., ch. 6), so curved edges (a hole) are meshed by quadratic
//! arcs. On a rectangle it is the structured element exactly (tested).
//!
//! The stiffness splits as in [`super::continuum::element_parts`]: K = mu K_mu + lambda K_lambda,
//! K_lambda = Bv^T G^-1 Bv with G_ab = int pi_a pi_b dA and Bv_ai = int pi_a div N_i dA,
//! pi = {1, xi, eta} (Hughes 1987, sec. 4.5); on a distorted element G is full, inverted here.

use super::continuum::{gauss, lagrange};

/// One mapped element: its stiffness parts and the projection that recovers its pressure.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedQ2 {
    /// K_mu / mu and K_lambda / lambda, 18 x 18 row-major (dofs u_x, u_y per local node).
    pub kmu: Vec<f64>,
    pub klam: Vec<f64>,
    /// G^-1 Bv (3 x 18): the projected dilatation's coefficients on {1, xi, eta}.
    proj: Vec<f64>,
    xy: [(f64, f64); 9],
}

/// Shape-function gradients (d/dx, d/dy) of the 9 nodes at (xi, eta) and det J.
#[track_caller]
fn gradients(xy: &[(f64, f64); 9], xi: f64, eta: f64) -> ([(f64, f64); 9], f64) {
    let (nx, dx) = lagrange(2, xi);
    let (ny, dy) = lagrange(2, eta);
    let mut dn = [(0.0, 0.0); 9];
    let (mut j11, mut j12, mut j21, mut j22) = (0.0, 0.0, 0.0, 0.0);
    for (k, d) in dn.iter_mut().enumerate() {
        let (a, b) = (k % 3, k / 3);
        *d = (dx[a] * ny[b], nx[a] * dy[b]);
        j11 += d.0 * xy[k].0;
        j12 += d.0 * xy[k].1;
        j21 += d.1 * xy[k].0;
        j22 += d.1 * xy[k].1;
    }
    let det = j11 * j22 - j12 * j21;
    assert!(
        det > 0.0,
        "mapped element inverted or degenerate (det J = {det}): nodes must run counter-clockwise"
    );
    let g = dn.map(|(a, b)| ((j22 * a - j12 * b) / det, (-j21 * a + j11 * b) / det));
    (g, det)
}

/// Inverse of a symmetric positive definite 3 x 3 matrix (the pressure mass G).
pub(crate) fn inverse3(m: &[f64; 9]) -> [f64; 9] {
    let c = |r: usize, s: usize| m[3 * r + s];
    let cof = [
        c(1, 1) * c(2, 2) - c(1, 2) * c(2, 1),
        c(0, 2) * c(2, 1) - c(0, 1) * c(2, 2),
        c(0, 1) * c(1, 2) - c(0, 2) * c(1, 1),
        c(1, 2) * c(2, 0) - c(1, 0) * c(2, 2),
        c(0, 0) * c(2, 2) - c(0, 2) * c(2, 0),
        c(0, 2) * c(1, 0) - c(0, 0) * c(1, 2),
        c(1, 0) * c(2, 1) - c(1, 1) * c(2, 0),
        c(0, 1) * c(2, 0) - c(0, 0) * c(2, 1),
        c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0),
    ];
    let det = c(0, 0) * cof[0] + c(0, 1) * cof[3] + c(0, 2) * cof[6];
    cof.map(|v| v / det)
}

/// The B-bar pressure projection onto pi = {1, xi, eta} (Hughes, The Finite Element Method,
/// 1987, sec. 4.5), shared by the plane ([`mapped_q2`]) and the axisymmetric
/// ([`super::axisym::axi_q2`]) Q2/P1 elements: G_ab = int pi_a pi_b w dA and Bv_ai = int pi_a
/// div N_i w dA are summed over the Gauss points with the radius weight w (1 in plane strain,
/// r in the axisymmetric element), then P = G^-1 Bv and K_lambda = Bv^T P.
pub(crate) struct Projection {
    gm: [f64; 9],
    bv: Vec<f64>,
}

impl Projection {
    pub(crate) fn new() -> Self {
        Projection {
            gm: [0.0; 9],
            bv: vec![0.0; 3 * 18],
        }
    }

    /// One Gauss point at (xi, eta) of weight `w` (Gauss weight times det J), radius weight
    /// `radius` and the divergence of each of the 18 dofs' shape functions there.
    pub(crate) fn add(&mut self, w: f64, radius: f64, xi: f64, eta: f64, div: &[f64; 18]) {
        let w = w * radius;
        let pi = [1.0, xi, eta];
        for a in 0..3 {
            for b in 0..3 {
                self.gm[3 * a + b] += w * pi[a] * pi[b];
            }
            for (i, d) in div.iter().enumerate() {
                self.bv[a * 18 + i] += w * pi[a] * d;
            }
        }
    }

    /// (P, K_lambda): G^-1 Bv (3 x 18) and Bv^T G^-1 Bv (18 x 18), row-major.
    pub(crate) fn finish(self) -> (Vec<f64>, Vec<f64>) {
        const ND: usize = 18;
        let ginv = inverse3(&self.gm);
        let mut proj = vec![0.0; 3 * ND];
        for a in 0..3 {
            for i in 0..ND {
                proj[a * ND + i] = (0..3).map(|b| ginv[3 * a + b] * self.bv[b * ND + i]).sum();
            }
        }
        let mut klam = vec![0.0; ND * ND];
        for i in 0..ND {
            for j in 0..ND {
                klam[i * ND + j] = (0..3).map(|a| self.bv[a * ND + i] * proj[a * ND + j]).sum();
            }
        }
        (proj, klam)
    }
}

/// The mapped Q2/P1 element on nodes `xy` (local node k = 3 b + a at (xi_a, eta_b), xi_a, eta_b
/// in {-1, 0, 1}; counter-clockwise). Panics on an inverted element (a meshing bug).
#[track_caller]
pub fn mapped_q2(xy: &[(f64, f64); 9]) -> MappedQ2 {
    const ND: usize = 18;
    let g3 = gauss(3);
    let mut kmu = vec![0.0; ND * ND];
    let mut projection = Projection::new();
    for &(xi, wx) in &g3 {
        for &(eta, wy) in &g3 {
            let (grad, det) = gradients(xy, xi, eta);
            let w = wx * wy * det;
            for i in 0..ND {
                let (gi, ci) = (grad[i / 2], i % 2);
                for j in 0..ND {
                    let (gj, cj) = (grad[j / 2], j % 2);
                    // eps : D_mu eps, D_mu = diag(2, 2, 1) mu on (exx, eyy, gxy).
                    let v = match (ci, cj) {
                        (0, 0) => 2.0 * gi.0 * gj.0 + gi.1 * gj.1,
                        (1, 1) => 2.0 * gi.1 * gj.1 + gi.0 * gj.0,
                        (0, _) => gi.1 * gj.0,
                        _ => gi.0 * gj.1,
                    };
                    kmu[i * ND + j] += w * v;
                }
            }
            let div: [f64; ND] = std::array::from_fn(|i| {
                if i % 2 == 0 {
                    grad[i / 2].0
                } else {
                    grad[i / 2].1
                }
            });
            projection.add(w, 1.0, xi, eta, &div);
        }
    }
    let (proj, klam) = projection.finish();
    MappedQ2 {
        kmu,
        klam,
        proj,
        xy: *xy,
    }
}

impl MappedQ2 {
    /// In-plane stress (sigma_xx, sigma_yy, tau_xy) at (xi, eta) from the element's 18 nodal
    /// displacements: sigma = 2 mu eps + lambda theta_bar I, theta_bar the projected dilatation
    /// (the B-bar element's own pressure, not the raw div u).
    pub fn stress(&self, u: &[f64; 18], lam: f64, mu: f64, xi: f64, eta: f64) -> (f64, f64, f64) {
        let (grad, _) = gradients(&self.xy, xi, eta);
        let (mut exx, mut eyy, mut gxy) = (0.0, 0.0, 0.0);
        for (k, g) in grad.iter().enumerate() {
            let (ux, uy) = (u[2 * k], u[2 * k + 1]);
            exx += g.0 * ux;
            eyy += g.1 * uy;
            gxy += g.1 * ux + g.0 * uy;
        }
        let pi = [1.0, xi, eta];
        let theta: f64 = (0..3)
            .map(|a| pi[a] * (0..18).map(|i| self.proj[a * 18 + i] * u[i]).sum::<f64>())
            .sum();
        (
            2.0 * mu * exx + lam * theta,
            2.0 * mu * eyy + lam * theta,
            mu * gxy,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::continuum::{element_parts, Order, Volumetric};
    use super::*;

    fn rectangle(x0: f64, y0: f64, hx: f64, hy: f64) -> [(f64, f64); 9] {
        std::array::from_fn(|k| {
            let (a, b) = ((k % 3) as f64, (k / 3) as f64);
            (x0 + 0.5 * hx * a, y0 + 0.5 * hy * b)
        })
    }

    #[test]
    fn on_a_rectangle_it_is_the_structured_element() {
        let (hx, hy) = (0.7, 0.3);
        let m = mapped_q2(&rectangle(2.0, -1.0, hx, hy));
        let (kmu, klam) = element_parts(Order::Q2, Volumetric::Bbar, hx, hy);
        let scale = kmu.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in m.kmu.iter().zip(&kmu).chain(m.klam.iter().zip(&klam)) {
            assert!((a - b).abs() < 1e-12 * scale, "{a} vs {b}");
        }
    }

    #[test]
    fn a_distorted_element_passes_the_patch_test() {
        // A linear displacement field on a skewed, curved-edged element: the stiffness times it
        // has no rigid-body residual (rows sum to traction only) and the stress it recovers is
        // the field's constant stress everywhere.
        let mut xy = rectangle(0.0, 0.0, 2.0, 1.0);
        xy[2].0 += 0.4;
        xy[8].1 += 0.3;
        xy[4].0 += 0.1;
        xy[7].1 += 0.05;
        let m = mapped_q2(&xy);
        let (lam, mu) = (3.0, 1.5);
        let u: [f64; 18] = std::array::from_fn(|i| {
            let (x, y) = xy[i / 2];
            if i % 2 == 0 {
                1e-3 * x + 2e-3 * y
            } else {
                -0.5e-3 * x + 4e-3 * y
            }
        });
        let (exx, eyy, gxy) = (1e-3, 4e-3, 1.5e-3);
        let want = (
            2.0 * mu * exx + lam * (exx + eyy),
            2.0 * mu * eyy + lam * (exx + eyy),
            mu * gxy,
        );
        for &(xi, eta) in &[(-1.0, -1.0), (0.3, -0.7), (1.0, 1.0)] {
            let s = m.stress(&u, lam, mu, xi, eta);
            for (a, b) in [(s.0, want.0), (s.1, want.1), (s.2, want.2)] {
                assert!((a - b).abs() < 1e-12, "{s:?} vs {want:?}");
            }
        }
        // A rigid translation and rotation carry no force.
        let rigid: [f64; 18] = std::array::from_fn(|i| {
            let (x, y) = xy[i / 2];
            if i % 2 == 0 {
                0.3 - 0.2 * y
            } else {
                -0.1 + 0.2 * x
            }
        });
        for row in 0..18 {
            let f: f64 = (0..18)
                .map(|c| (mu * m.kmu[row * 18 + c] + lam * m.klam[row * 18 + c]) * rigid[c])
                .sum();
            assert!(f.abs() < 1e-12, "row {row}: {f}");
        }
    }

    #[test]
    #[should_panic(expected = "inverted")]
    fn an_inverted_element_is_a_bug() {
        // xi and eta swapped: a mirror image, clockwise.
        let r = rectangle(0.0, 0.0, 1.0, 1.0);
        let _ = mapped_q2(&std::array::from_fn(|k| r[3 * (k % 3) + k / 3]));
    }
}
