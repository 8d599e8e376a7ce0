//! The check of the tissue elements against a closed form with a stress concentration: a
//! circular hole of radius a in an infinite plate under far-field uniaxial tension S along x
//! (Kirsch 1898; Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 35, Eq. 61). Its hoop
//! stress at the hole's edge is S (1 - 2 cos 2 theta): 3 S at theta = 90 deg. Plane strain leaves
//! the in-plane stresses of this traction problem unchanged (they do not depend on nu).
//!
//! The FE ([`hole_hoop_stress`]) meshes a quarter annulus a <= r <= R with the mapped Q2/P1
//! elements of [`super::mapped`] (radial sizes graded geometrically, so the elements at the hole
//! are small), symmetry on both axes, and the exact Kirsch traction on r = R: the infinite plate
//! is represented exactly, so what is left is discretisation error alone.

use super::continuum::{gauss, lagrange, lame, lame_combined, pair_dofs, Assembler, DofExpr};
use super::mapped::{mapped_q2, MappedQ2};
use super::SoftnessError;

/// The closed form: hole radius and far-field tension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kirsch {
    pub radius_m: f64,
    pub stress_pa: f64,
}

impl Kirsch {
    /// (sigma_rr, sigma_thth, tau_rth) at polar (r, theta), Timoshenko & Goodier Eq. 61.
    pub fn polar(&self, r: f64, theta: f64) -> (f64, f64, f64) {
        let (s, q) = (0.5 * self.stress_pa, (self.radius_m / r).powi(2));
        let (c2, s2) = ((2.0 * theta).cos(), (2.0 * theta).sin());
        (
            s * (1.0 - q) + s * (1.0 - 4.0 * q + 3.0 * q * q) * c2,
            s * (1.0 + q) - s * (1.0 + 3.0 * q * q) * c2,
            -s * (1.0 + 2.0 * q - 3.0 * q * q) * s2,
        )
    }

    /// (sigma_xx, sigma_yy, tau_xy) at (x, y): the polar stresses rotated by theta.
    pub fn cartesian(&self, x: f64, y: f64) -> (f64, f64, f64) {
        let (r, t) = (x.hypot(y), y.atan2(x));
        let (srr, stt, srt) = self.polar(r, t);
        let (c, s) = (t.cos(), t.sin());
        (
            srr * c * c + stt * s * s - 2.0 * srt * s * c,
            srr * s * s + stt * c * c + 2.0 * srt * s * c,
            (srr - stt) * s * c + srt * (c * c - s * s),
        )
    }
}

/// The FE hoop stress at the top of the hole (r = a, theta = 90 deg), where Kirsch gives 3 S:
/// `nr` x `nt` Q2/P1 elements on the quarter annulus a <= r <= `outer` a (radial sizes growing
/// geometrically), plane strain with Poisson's ratio `nu`, E = 1 (the stresses do not depend on
/// it). Returns sigma_xx there (the hoop stress) in units of S.
pub fn hole_hoop_stress(outer: f64, nr: usize, nt: usize, nu: f64) -> Result<f64, SoftnessError> {
    if !(outer > 1.0 && outer.is_finite()) || nr == 0 || nt == 0 || nr * nt > 20_000 {
        return Err(SoftnessError::BadInput {
            field: "kirsch mesh",
            value: (nr * nt) as f64,
            hint: "an outer radius > a and 1-20,000 elements",
        });
    }
    let k = Kirsch {
        radius_m: 1.0,
        stress_pa: 1.0,
    };
    // Node lines: element boundaries graded geometrically in r, mid-nodes at the middle.
    let (rs, ts) = super::far_field::quarter_annulus(0, nr, outer, nt);
    let (ni, nj) = (rs.len(), ts.len());
    let node = |i: usize, j: usize| j * ni + i;
    let pos = |i: usize, j: usize| (rs[i] * ts[j].cos(), rs[i] * ts[j].sin());
    // Symmetry: u_y = 0 on theta = 0, u_x = 0 on theta = 90 deg.
    let mut n = 0;
    let mut dofs = Vec::with_capacity(2 * ni * nj);
    for j in 0..nj {
        for _ in 0..ni {
            for c in 0..2 {
                if (j == 0 && c == 1) || (j == nj - 1 && c == 0) {
                    dofs.push(DofExpr::fixed(0.0));
                } else {
                    dofs.push(DofExpr::free(n));
                    n += 1;
                }
            }
        }
    }
    let (lam, mu) = lame(1.0, nu);
    let mut asm = Assembler::new(n, 1);
    let mut elements: Vec<(Vec<usize>, MappedQ2)> = Vec::new();
    for ej in 0..nt {
        for ei in 0..nr {
            let nodes: Vec<usize> = (0..9)
                .map(|q| node(2 * ei + q % 3, 2 * ej + q / 3))
                .collect();
            let xy: [(f64, f64); 9] = std::array::from_fn(|q| pos(2 * ei + q % 3, 2 * ej + q / 3));
            let m = mapped_q2(&xy);
            let ke = lame_combined(&m.kmu, &m.klam, mu, lam);
            asm.add(0, &ke, &pair_dofs(&nodes, &dofs));
            elements.push((nodes, m));
        }
    }
    // The exact traction sigma . n on the outer arc, n ds = (dy/deta, -dx/deta) deta there.
    for ej in 0..nt {
        let edge: Vec<(usize, (f64, f64))> = (0..3)
            .map(|b| (node(ni - 1, 2 * ej + b), pos(ni - 1, 2 * ej + b)))
            .collect();
        for &(eta, w) in &gauss(3) {
            let (nv, dv) = lagrange(2, eta);
            let (mut x, mut y, mut tx, mut ty) = (0.0, 0.0, 0.0, 0.0);
            for (b, &(_, p)) in edge.iter().enumerate() {
                x += nv[b] * p.0;
                y += nv[b] * p.1;
                tx += dv[b] * p.0;
                ty += dv[b] * p.1;
            }
            let (sxx, syy, sxy) = k.cartesian(x, y);
            let (fx, fy) = (sxx * ty - sxy * tx, sxy * ty - syy * tx);
            for (b, &(q, _)) in edge.iter().enumerate() {
                asm.force(&dofs[2 * q], w * nv[b] * fx);
                asm.force(&dofs[2 * q + 1], w * nv[b] * fy);
            }
        }
    }
    let u = asm.finish()?.solve(&[1.0])?;
    let value = |e: &DofExpr| e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>();
    // The hole's top is local node (xi, eta) = (-1, 1) of the element at r = a, theta = 90 deg.
    let (nodes, m) = &elements[(nt - 1) * nr];
    let ue: [f64; 18] = std::array::from_fn(|i| value(&dofs[2 * nodes[i / 2] + i % 2]));
    Ok(m.stress(&ue, lam, mu, -1.0, 1.0).0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closed_form_is_kirsch() {
        let k = Kirsch {
            radius_m: 2.0,
            stress_pa: 5.0,
        };
        // Hoop 3 S at 90 deg, -S at 0 deg; traction-free hole; far field (S, 0, 0).
        assert!((k.polar(2.0, std::f64::consts::FRAC_PI_2).1 - 15.0).abs() < 1e-12);
        assert!((k.polar(2.0, 0.0).1 + 5.0).abs() < 1e-12);
        for t in [0.1, 0.7, 1.3] {
            let (srr, _, srt) = k.polar(2.0, t);
            assert!(srr.abs() < 1e-12 && srt.abs() < 1e-12);
        }
        let (sxx, syy, sxy) = k.cartesian(3e3, 4e3);
        assert!((sxx - 5.0).abs() < 1e-5 && syy.abs() < 1e-5 && sxy.abs() < 1e-5);
    }

    #[test]
    fn the_hole_concentrates_the_hoop_stress_three_times() {
        // Quarter annulus to R = 20 a with Kirsch's traction there; nu 0.3 and the nearly
        // incompressible 0.49 of the tissue (B-bar must not lock).
        let mut errs = Vec::new();
        for nu in [0.3, 0.49] {
            let e: Vec<f64> = [(8, 6), (16, 12), (32, 24)]
                .iter()
                .map(|&(nr, nt)| (hole_hoop_stress(20.0, nr, nt, nu).unwrap() / 3.0 - 1.0).abs())
                .collect();
            eprintln!("nu {nu}: |K_t / 3 - 1| on 8x6, 16x12, 32x24: {e:?}");
            errs.push(e);
        }
        // Measured: nu 0.3: 8.6e-3, 2.0e-3, 5.3e-4; nu 0.49: 1.1e-2, 3.0e-3, 8.3e-4 (second
        // order: each halving of the elements divides the error by ~4).
        for e in &errs {
            assert!(e[1] < 0.4 * e[0] && e[2] < 0.4 * e[1], "{e:?}");
            assert!(e[2] < 1e-3, "{e:?}");
        }
    }
}
