//! The 27-node brick in the Total Lagrangian formulation with the St. Venant-Kirchhoff material:
//! large displacements and rotations, strains small enough for a linear S-E law (geometric
//! nonlinearity only).
//!
//! Everything refers to the undeformed configuration X (Bathe, Finite Element Procedures, 1996,
//! sec. 6.2.3 and Table 6.4; Belytschko, Liu & Moran, Nonlinear Finite Elements for Continua and
//! Structures, ch. 4, the total Lagrangian formulation):
//! - deformation gradient F = I + grad_X u = I + sum_n u_n (dN_n/dX)^T;
//! - Green-Lagrange strain E = (F^T F - I) / 2, in Voigt order with engineering shears (2 E_ij);
//! - second Piola-Kirchhoff stress S = C E with the same (anisotropic) C as the linear core;
//! - strain energy W = integral of E C E / 2 dV0;
//! - virtual strain dE = B_NL du, where for node a, component i the column of B_NL is
//!   sym(F^T (e_i dN_a/dX^T)) (the linear B with F folded in);
//! - internal force f_int = integral of B_NL^T S dV0 = dW/du;
//! - tangent K_T = integral of B_NL^T C B_NL dV0 (material) + integral of
//!   (dN_a/dX . S dN_b/dX) I_3 dV0 (geometric, initial-stress) = d f_int / du.
//!
//! Quadrature: the linear core's 3x3x3 Gauss rule. Positions in m, forces in N, stresses in Pa.

// Index loops read like the tensor formulas they implement.
#![allow(clippy::needless_range_loop)]

use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::hex27::{self, DOFS, NODES};
use crate::fe::solid::shear_tying::{self, TransverseShear};

/// The displacement gradient H = sum_n u_n (dN_n/dX)^T, `[i][j]` = du_i / dX_j.
pub fn displacement_gradient(dn_dx: &[[f64; 3]; NODES], u_m: &[f64; DOFS]) -> [[f64; 3]; 3] {
    let mut h = [[0.0; 3]; 3];
    for (n, g) in dn_dx.iter().enumerate() {
        for i in 0..3 {
            let u = u_m[3 * n + i];
            for j in 0..3 {
                h[i][j] += u * g[j];
            }
        }
    }
    h
}

/// F = I + H, `[i][j]` = dx_i / dX_j (Bathe sec. 6.2.3).
pub fn deformation_gradient(dn_dx: &[[f64; 3]; NODES], u_m: &[f64; DOFS]) -> [[f64; 3]; 3] {
    let mut f = displacement_gradient(dn_dx, u_m);
    for (i, row) in f.iter_mut().enumerate() {
        row[i] += 1.0;
    }
    f
}

/// Green-Lagrange strain E = (H + H^T + H^T H) / 2 (= (F^T F - I) / 2) from the displacement
/// gradient, in Voigt order xx, yy, zz, yz, xz, xy with engineering shears (2 E_ij), so the
/// energy density is E C E / 2 as in the linear core. From H, not F: F^T F - I cancels the
/// identity and leaves a strain of 1e-7 with only ~9 digits, which stalled Newton at small loads.
pub fn green_lagrange(h: &[[f64; 3]; 3]) -> [f64; 6] {
    let e = |a: usize, b: usize| h[a][b] + h[b][a] + (0..3).map(|k| h[k][a] * h[k][b]).sum::<f64>();
    [
        0.5 * e(0, 0),
        0.5 * e(1, 1),
        0.5 * e(2, 2),
        e(1, 2),
        e(0, 2),
        e(0, 1),
    ]
}

/// A symmetric tensor from Voigt components (stress convention: no factor 2 on the shears).
pub fn voigt_tensor(s: &[f64; 6]) -> [[f64; 3]; 3] {
    [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
}

/// The column of B_NL of node gradient `g` (dN_a/dX) and displacement component `i`: the
/// variation of the Voigt strain, dE_jk = (F_ij g_k + F_ik g_j) / 2 (shears doubled).
fn b_column(f: &[[f64; 3]; 3], g: &[f64; 3], i: usize) -> [f64; 6] {
    let r = f[i];
    [
        r[0] * g[0],
        r[1] * g[1],
        r[2] * g[2],
        r[1] * g[2] + r[2] * g[1],
        r[0] * g[2] + r[2] * g[0],
        r[0] * g[1] + r[1] * g[0],
    ]
}

/// An element whose deformation gradient has det F <= 0 (or not finite) at a Gauss point: the
/// iterate has inverted it, and the Newton step that produced it is rejected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inverted {
    /// Smallest det F found.
    pub det_f: f64,
}

/// One tying point's share of a tied transverse shear: the shape gradients there, its
/// Green-Lagrange shear and that shear's B_NL row (the Voigt row it ties).
struct Tie {
    dn_dx: [[f64; 3]; NODES],
    strain: f64,
    b: [f64; DOFS],
}

impl Tie {
    fn at(nodes_m: &[[f64; 3]; NODES], u_m: &[f64; DOFS], pt: [f64; 3], row: usize) -> Tie {
        let gt = hex27::geometry(nodes_m, pt);
        let ht = displacement_gradient(&gt.dn_dx, u_m);
        let ft = deformation_gradient(&gt.dn_dx, u_m);
        Tie {
            strain: green_lagrange(&ht)[row],
            b: std::array::from_fn(|p| b_column(&ft, &gt.dn_dx[p / 3], p % 3)[row]),
            dn_dx: gt.dn_dx,
        }
    }
}

/// The brick's 36 distinct tying points, each evaluated once: the 27 Gauss points' 108 tying
/// points are the lines xi = -+1/sqrt 3 at the 9 (eta, zeta) of the rule (gamma_xz) and eta =
/// -+1/sqrt 3 at its 9 (xi, zeta) (gamma_yz). `xz[s][j + 3 k]`, `yz[s][i + 3 k]` for the Gauss
/// point i + 3 j + 9 k, s the line (the order of [`shear_tying::tying_points`]).
struct Ties {
    xz: [[Tie; 9]; 2],
    yz: [[Tie; 9]; 2],
}

impl Ties {
    fn new(nodes_m: &[[f64; 3]; NODES], u_m: &[f64; DOFS]) -> Box<Ties> {
        let gp = hex27::gauss_points();
        // The same points [`shear_tying::tying_points`] gives each Gauss point, bit for bit.
        let pt = |n: usize, k: usize| shear_tying::tying_points(gp[n].0)[k].0;
        Box::new(Ties {
            xz: std::array::from_fn(|s| {
                std::array::from_fn(|jk| {
                    Tie::at(nodes_m, u_m, pt(3 * (jk % 3) + 9 * (jk / 3), s), 4)
                })
            }),
            yz: std::array::from_fn(|s| {
                std::array::from_fn(|ik| Tie::at(nodes_m, u_m, pt(ik % 3 + 9 * (ik / 3), 2 + s), 3))
            }),
        })
    }

    /// Gauss point `n`'s four tying points in [`shear_tying::tying_points`]' order.
    fn of(&self, n: usize) -> [&Tie; 4] {
        let (i, j, k) = (n % 3, (n / 3) % 3, n / 9);
        [
            &self.xz[0][j + 3 * k],
            &self.xz[1][j + 3 * k],
            &self.yz[0][i + 3 * k],
            &self.yz[1][i + 3 * k],
        ]
    }
}

/// Internal force f_int = sum_g w_g det J0 B_NL^T S (N, 81 values) and, if `tangent` is given
/// (81 x 81 row-major), the consistent tangent K_T = K_material + K_geometric (module doc). The
/// reference geometry is the caller's to check (det J0 > 0, as the linear core does).
/// Panics if `tangent` is not 81 x 81 (misuse).
#[track_caller]
pub fn internal_force(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    shear: TransverseShear,
    mut tangent: Option<&mut [f64]>,
) -> Result<[f64; DOFS], Inverted> {
    if let Some(k) = tangent.as_deref_mut() {
        assert_eq!(k.len(), DOFS * DOFS, "the tangent is 81 x 81");
        k.fill(0.0);
    }
    let c = &material.c_pa;
    // Each tying point serves three Gauss points: evaluated once per call, not per Gauss point.
    let ties_cache = shear_tying::ties(nodes_m, shear).then(|| Ties::new(nodes_m, u_m));
    let mut fint = [0.0; DOFS];
    for (n, (xi, w)) in hex27::gauss_points().into_iter().enumerate() {
        let g = hex27::geometry(nodes_m, xi);
        let dv = w * g.det_j;
        let h = displacement_gradient(&g.dn_dx, u_m);
        let f = deformation_gradient(&g.dn_dx, u_m);
        let det_f = hex27::det3(&f);
        if det_f.is_nan() || det_f <= 0.0 {
            return Err(Inverted { det_f });
        }
        let mut e = green_lagrange(&h);
        let mut b: [[f64; 6]; DOFS] = std::array::from_fn(|p| b_column(&f, &g.dn_dx[p / 3], p % 3));
        // Tied shears: E_xz (row 4) and E_yz (row 3), their variations and, for the geometric
        // part, the tying points' gradients (shear_tying; the strain is the weighted sum of the
        // tying points' Green-Lagrange strains, so every derivative is the same sum).
        // (Voigt row, weight, point) of this Gauss point's four tying points.
        let ties: Option<[(usize, f64, &Tie); 4]> = ties_cache.as_ref().map(|cache| {
            let (at, pts) = (cache.of(n), shear_tying::tying_points(xi));
            std::array::from_fn(|k| (if k < 2 { 4 } else { 3 }, pts[k].1, at[k]))
        });
        if let Some(ties) = &ties {
            e[3] = 0.0;
            e[4] = 0.0;
            for bp in b.iter_mut() {
                bp[3] = 0.0;
                bp[4] = 0.0;
            }
            for &(row, wt, tie) in ties {
                e[row] += wt * tie.strain;
                for (bp, tb) in b.iter_mut().zip(&tie.b) {
                    bp[row] += wt * tb;
                }
            }
        }
        let s = material.stress_pa(&e);
        for (fp, bp) in fint.iter_mut().zip(&b) {
            *fp += dv * (0..6).map(|r| bp[r] * s[r]).sum::<f64>();
        }
        let Some(k) = tangent.as_deref_mut() else {
            continue;
        };
        // Material part, upper triangle: B^T (C B), C B stored by Voigt row so the inner loop
        // runs along contiguous columns (vectorised; the same sums in the same order).
        let cb: [[f64; DOFS]; 6] = std::array::from_fn(|r| {
            std::array::from_fn(|q| (0..6).map(|t| c[r][t] * b[q][t]).sum())
        });
        for p in 0..DOFS {
            let bp = &b[p];
            let row = &mut k[p * DOFS + p..(p + 1) * DOFS];
            let cols = (
                &cb[0][p..],
                &cb[1][p..],
                &cb[2][p..],
                &cb[3][p..],
                &cb[4][p..],
                &cb[5][p..],
            );
            for (q, kq) in row.iter_mut().enumerate() {
                *kq += dv
                    * (bp[0] * cols.0[q]
                        + bp[1] * cols.1[q]
                        + bp[2] * cols.2[q]
                        + bp[3] * cols.3[q]
                        + bp[4] * cols.4[q]
                        + bp[5] * cols.5[q]);
            }
        }
        // Geometric part: (g_a . S g_b) on the diagonal of each 3 x 3 node block; tied shears
        // take theirs from the tying points' gradients.
        let mut st = voigt_tensor(&s);
        let ties: &[(usize, f64, &Tie)] = ties.as_ref().map_or(&[], |t| &t[..]);
        if !ties.is_empty() {
            for (i, j) in [(1, 2), (0, 2)] {
                st[i][j] = 0.0;
                st[j][i] = 0.0;
            }
        }
        for a in 0..NODES {
            let ga = g.dn_dx[a];
            let sa: [f64; 3] = std::array::from_fn(|r| (0..3).map(|t| st[r][t] * ga[t]).sum());
            for bn in a..NODES {
                let gb = g.dn_dx[bn];
                let mut v = sa[0] * gb[0] + sa[1] * gb[1] + sa[2] * gb[2];
                for (row, wt, tie) in ties {
                    let gt = &tie.dn_dx;
                    let i = if *row == 4 { 0 } else { 1 };
                    let (ta, tb) = (gt[a], gt[bn]);
                    v += wt * s[*row] * (ta[i] * tb[2] + ta[2] * tb[i]);
                }
                let v = dv * v;
                for i in 0..3 {
                    k[(3 * a + i) * DOFS + 3 * bn + i] += v;
                }
            }
        }
    }
    if let Some(k) = tangent {
        for p in 0..DOFS {
            for q in 0..p {
                k[p * DOFS + q] = k[q * DOFS + p];
            }
        }
    }
    Ok(fint)
}

/// Strain energy W = sum_g w_g det J0 E C E / 2 (J), straight from the kinematics: the quantity
/// whose gradient [`internal_force`] is.
pub fn strain_energy(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    shear: TransverseShear,
) -> f64 {
    hex27::gauss_points()
        .iter()
        .map(|&(xi, w)| {
            let e = strain_at(nodes_m, u_m, xi, shear);
            let s = material.stress_pa(&e);
            0.5 * w * hex27::geometry(nodes_m, xi).det_j * (0..6).map(|r| e[r] * s[r]).sum::<f64>()
        })
        .sum()
}

/// Green-Lagrange strain (Voigt, engineering shears) at local point `xi`, the transverse shears
/// taken as `shear` says ([`shear_tying`]).
pub fn strain_at(
    nodes_m: &[[f64; 3]; NODES],
    u_m: &[f64; DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [f64; 6] {
    let at = |p: [f64; 3]| {
        green_lagrange(&displacement_gradient(
            &hex27::geometry(nodes_m, p).dn_dx,
            u_m,
        ))
    };
    let mut e = at(xi);
    if shear_tying::ties(nodes_m, shear) {
        e[3] = 0.0;
        e[4] = 0.0;
        for (k, (pt, wt)) in shear_tying::tying_points(xi).into_iter().enumerate() {
            let row = if k < 2 { 4 } else { 3 };
            e[row] += wt * at(pt)[row];
        }
    }
    e
}

/// Second Piola-Kirchhoff stress S = C E (Voigt, Pa) at local point `xi`.
pub fn second_piola_kirchhoff_pa(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [f64; 6] {
    material.stress_pa(&strain_at(nodes_m, u_m, xi, shear))
}

/// First Piola-Kirchhoff (nominal) stress P = F S (Pa; `P[i][J]`: force along i per undeformed
/// area of normal J) at local point `xi` (Bathe sec. 6.2): what a cut through the undeformed body
/// transmits, so its integral over a reference face is the force through it.
pub fn first_piola_kirchhoff_pa(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [[f64; 3]; 3] {
    let dn_dx = hex27::geometry(nodes_m, xi).dn_dx;
    let f = deformation_gradient(&dn_dx, u_m);
    let s = voigt_tensor(&material.stress_pa(&strain_at(nodes_m, u_m, xi, shear)));
    std::array::from_fn(|i| std::array::from_fn(|k| (0..3).map(|m| f[i][m] * s[m][k]).sum()))
}

/// Cauchy stress sigma = F S F^T / det F (Voigt, Pa) at local point `xi`: the push-forward of S
/// (Bathe sec. 6.2; Belytschko, Liu & Moran ch. 3), in the fixed x, y, z axes.
pub fn cauchy_pa(
    nodes_m: &[[f64; 3]; NODES],
    material: &Elasticity,
    u_m: &[f64; DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [f64; 6] {
    let dn_dx = hex27::geometry(nodes_m, xi).dn_dx;
    let f = deformation_gradient(&dn_dx, u_m);
    let s = voigt_tensor(&material.stress_pa(&strain_at(nodes_m, u_m, xi, shear)));
    let j = hex27::det3(&f);
    let fs: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|k| (0..3).map(|m| f[i][m] * s[m][k]).sum()));
    let sig = |i: usize, l: usize| (0..3).map(|k| fs[i][k] * f[l][k]).sum::<f64>() / j;
    [
        sig(0, 0),
        sig(1, 1),
        sig(2, 2),
        sig(1, 2),
        sig(0, 2),
        sig(0, 1),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curved 2 x 1.5 x 1 m element (mid-side and interior nodes moved), as in hex27's tests.
    fn curved() -> [[f64; 3]; NODES] {
        std::array::from_fn(|n| {
            let (i, j, k) = (n % 3, (n / 3) % 3, n / 9);
            let mut p = [1.0 * i as f64, 0.75 * j as f64, 0.5 * k as f64];
            if i == 1 || j == 1 || k == 1 {
                p[0] += 0.1 * (n as f64 * 0.7).sin();
                p[1] += 0.08 * (n as f64 * 1.3).cos();
                p[2] += 0.05 * (n as f64 * 0.4).sin();
            }
            p
        })
    }

    /// Rotation by `deg` about the unit axis `n` (Rodrigues).
    pub(crate) fn rotation(n: [f64; 3], deg: f64) -> [[f64; 3]; 3] {
        let (s, c) = deg.to_radians().sin_cos();
        let k = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]];
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let kk: f64 = (0..3).map(|m| k[i][m] * k[m][j]).sum();
                f64::from(u8::from(i == j)) + s * k[i][j] + (1.0 - c) * kk
            })
        })
    }

    fn anisotropic() -> Elasticity {
        // Si in crystal axes (Hopcroft et al. 2010, as in elasticity.rs), rotated off every axis.
        let (s, c) = 0.5_f64.sin_cos();
        Elasticity::cubic(165.7e9, 63.9e9, 79.6e9)
            .rotated_about_z(30.0)
            .rotated(&[[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
    }

    /// A large displacement: rotation by 50 deg about a skew axis, 8 % stretch, and a smooth
    /// non-affine part (strains of a few %).
    fn large_u(x: &[[f64; 3]; NODES]) -> [f64; DOFS] {
        let r = rotation([0.48, 0.6, 0.64], 50.0);
        std::array::from_fn(|d| {
            let (n, i) = (d / 3, d % 3);
            let p = x[n];
            let stretched = [1.08 * p[0], p[1] - 0.03 * p[0], 0.97 * p[2]];
            let rotated: f64 = (0..3).map(|j| r[i][j] * stretched[j]).sum();
            rotated - p[i] + 0.02 * ((n * 7 + i) as f64).sin() * (1.0 + p[0])
        })
    }

    /// f_int = dW/du and K_T = d f_int / du by central differences, on a curved anisotropic
    /// element under a large rotation and stretch, with either transverse shear; K_T symmetric.
    #[test]
    fn force_and_tangent_are_the_energy_derivatives() {
        force_and_tangent_check(&curved(), TransverseShear::Displacement);
        // Tying applies to parallelepipeds only (shear_tying): a sheared, skewed one.
        let skewed: [[f64; 3]; NODES] = std::array::from_fn(|n| {
            let p = [n % 3, (n / 3) % 3, n / 9].map(|a| 0.5 * a as f64);
            [
                2.0 * p[0] + 0.3 * p[2],
                1.5 * p[1] - 0.2 * p[0],
                p[2] + 0.1 * p[1],
            ]
        });
        assert!(shear_tying::ties(&skewed, TransverseShear::Tied));
        force_and_tangent_check(&skewed, TransverseShear::Tied);
    }

    fn force_and_tangent_check(x: &[[f64; 3]; NODES], shear: TransverseShear) {
        let x = *x;
        let mat = anisotropic();
        let u = large_u(&x);
        let mut k = vec![0.0; DOFS * DOFS];
        let f = internal_force(&x, &mat, &u, shear, Some(&mut k)).unwrap();
        let fmax = f.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let kmax = k.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let h = 1e-6;
        let (mut worst_f, mut worst_k): (f64, f64) = (0.0, 0.0);
        for p in 0..DOFS {
            let (mut up, mut um) = (u, u);
            up[p] += h;
            um[p] -= h;
            let dw = (strain_energy(&x, &mat, &up, shear) - strain_energy(&x, &mat, &um, shear))
                / (2.0 * h);
            worst_f = worst_f.max((dw - f[p]).abs() / fmax);
            let fp = internal_force(&x, &mat, &up, shear, None).unwrap();
            let fm = internal_force(&x, &mat, &um, shear, None).unwrap();
            for q in 0..DOFS {
                let d = (fp[q] - fm[q]) / (2.0 * h);
                worst_k = worst_k.max((d - k[q * DOFS + p]).abs() / kmax);
            }
        }
        eprintln!("{shear:?}: finite differences: force {worst_f:.2e}, tangent {worst_k:.2e}");
        assert!(worst_f < 1e-6, "force vs dW/du: {worst_f:e}");
        assert!(worst_k < 1e-6, "tangent vs df/du: {worst_k:e}");
        for p in 0..DOFS {
            for q in 0..DOFS {
                assert_eq!(k[p * DOFS + q], k[q * DOFS + p]);
            }
        }
        // The geometric part matters here: the linear stiffness is far from K_T.
        let k0 = hex27::stiffness(&x, &mat, shear);
        let diff = (0..DOFS * DOFS)
            .map(|i| (k0[i] - k[i]).abs())
            .fold(0.0, f64::max);
        assert!(diff > 0.1 * kmax, "{diff:e}");
    }

    /// A rigid rotation (90 deg about a skew axis) gives no strain, no stress and no force, with
    /// either transverse shear; the linearised strain of the same field is of order one.
    #[test]
    fn rigid_rotation_is_stress_free() {
        for shear in [TransverseShear::Displacement, TransverseShear::Tied] {
            rigid_rotation_check(shear);
        }
    }

    fn rigid_rotation_check(shear: TransverseShear) {
        let x = curved();
        let mat = anisotropic();
        let r = rotation([0.6, 0.0, 0.8], 90.0);
        let t = [0.3, -0.2, 0.1];
        let u: [f64; DOFS] = std::array::from_fn(|d| {
            let (p, i) = (x[d / 3], d % 3);
            (0..3).map(|j| r[i][j] * p[j]).sum::<f64>() - p[i] + t[i]
        });
        let f = internal_force(&x, &mat, &u, shear, None).unwrap();
        let scale = 165.7e9 * 3.0; // C times the element's volume: the force of a unit strain
        assert!(f.iter().all(|v| v.abs() < 1e-12 * scale), "{f:?}");
        assert!(strain_energy(&x, &mat, &u, shear).abs() < 1e-12 * scale);
        for xi in [[0.0; 3], [0.7, -0.2, 1.0]] {
            let s = second_piola_kirchhoff_pa(&x, &mat, &u, xi, shear);
            let sig = cauchy_pa(&x, &mat, &u, xi, shear);
            assert!(s.iter().chain(&sig).all(|v| v.abs() < 1e-12 * 165.7e9));
            let lin = hex27::stress_pa(&x, &mat, &u, xi, shear);
            assert!(lin.iter().any(|v| v.abs() > 0.1 * 165.7e9), "{lin:?}");
        }
        // And Cauchy = R S R^T for a rotated uniaxial stretch: a stretch along X then the
        // rotation puts the stress along R e_x.
        let ux: [f64; DOFS] = std::array::from_fn(|d| {
            let (p, i) = (x[d / 3], d % 3);
            let q = [1.01 * p[0], p[1], p[2]];
            (0..3).map(|j| r[i][j] * q[j]).sum::<f64>() - p[i]
        });
        let iso = Elasticity::isotropic(100e9, 0.0);
        let s = second_piola_kirchhoff_pa(&x, &iso, &ux, [0.1, 0.2, 0.3], shear);
        let sig = voigt_tensor(&cauchy_pa(&x, &iso, &ux, [0.1, 0.2, 0.3], shear));
        // S_xx = E (1.01^2 - 1)/2; sigma = F S F^T / J = 1.01^2 S_xx / 1.01 along R e_x.
        let sxx = 100e9 * (1.01f64.powi(2) - 1.0) / 2.0;
        assert!((s[0] - sxx).abs() < 1e-9 * sxx && s[1].abs() < 1e-9 * sxx);
        for i in 0..3 {
            for j in 0..3 {
                let expect = 1.01 * sxx * r[i][0] * r[j][0];
                assert!((sig[i][j] - expect).abs() < 1e-9 * sxx, "{sig:?}");
            }
        }
    }

    #[test]
    fn inverted_state_is_reported() {
        let x = curved();
        // u = -2 X: F = -I, det F = -1.
        let u: [f64; DOFS] = std::array::from_fn(|d| -2.0 * x[d / 3][d % 3]);
        let e = internal_force(
            &x,
            &Elasticity::isotropic(1e9, 0.3),
            &u,
            TransverseShear::Tied,
            None,
        )
        .unwrap_err();
        assert!(e.det_f < 0.0);
    }
}
