//! Linear elastic stiffness C (6x6, Voigt notation) of the solid materials: cubic crystals (Si),
//! isotropic solids (PVDF, Plexiglas) and their rotation about the wafer normal.
//!
//! Voigt order xx, yy, zz, yz, xz, xy with engineering shear strains (gamma = 2 eps), so
//! sigma = C eps and the strain energy is eps^T C eps / 2 (Auld, Acoustic Fields and Waves in
//! Solids, vol. 1, Eq. 3.15-3.20; Nye, Physical Properties of Crystals, ch. VIII).

// Index loops read like the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use crate::fe::material::{DieEdge, PlateMaterial};

/// Index pairs (i, j) of the Voigt components, in Voigt order.
pub const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// Elastic stiffness in Voigt notation, Pa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elasticity {
    /// C_IJ, symmetric, Pa.
    pub c_pa: [[f64; 6]; 6],
}

impl Elasticity {
    /// Cubic crystal in its crystal axes: C11 = C22 = C33, C12 = C13 = C23, C44 = C55 = C66
    /// (Nye, Table 9; Auld Eq. 3.33 and Appendix 2).
    pub fn cubic(c11_pa: f64, c12_pa: f64, c44_pa: f64) -> Self {
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = if i == j { c11_pa } else { c12_pa };
            }
            c[i + 3][i + 3] = c44_pa;
        }
        Elasticity { c_pa: c }
    }

    /// Isotropic solid: Lame lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)),
    /// C11 = lambda + 2 mu, C12 = lambda, C44 = mu (Auld Eq. 3.36; Timoshenko & Goodier, Theory of
    /// Elasticity, sec. 6).
    pub fn isotropic(e_pa: f64, nu: f64) -> Self {
        let mu = e_pa / (2.0 * (1.0 + nu));
        let lambda = e_pa * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        Self::cubic(lambda + 2.0 * mu, lambda, mu)
    }

    /// Silicon (Hopcroft, Nix, Kenny, JMEMS 19(2) 2010: C11 = 165.7, C12 = 63.9, C44 = 79.6 GPa,
    /// as in `fe-validation.md`) in the die axes of a (100) wafer.
    pub fn silicon(die_edge: DieEdge) -> Self {
        Self::cubic(165.7e9, 63.9e9, 79.6e9).in_die_axes(die_edge)
    }

    /// A cubic crystal's stiffness (given in crystal axes) in the die axes of a (100) wafer: die
    /// edges along <110> are the crystal axes rotated by 45 deg about \[001\]; along <100> they
    /// coincide.
    pub fn in_die_axes(&self, die_edge: DieEdge) -> Self {
        match die_edge {
            DieEdge::Along100 => *self,
            DieEdge::Along110 => self.rotated_about_z(45.0),
        }
    }

    /// The stiffness in axes rotated by `theta_deg` counter-clockwise about z: C' = M C M^T with the
    /// Bond stress transformation matrix M of the direction cosines a (new axis i along
    /// a_i = (cos, sin, 0), (-sin, cos, 0), (0, 0, 1)) (Auld, vol. 1, Eq. 3.32-3.34; Bond 1943).
    pub fn rotated_about_z(&self, theta_deg: f64) -> Self {
        let (s, c) = theta_deg.to_radians().sin_cos();
        self.rotated(&[[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    }

    /// C' = M C M^T for the direction cosine matrix `a` (row i = new axis i in old axes), with
    /// M_IJ = a_ik a_jk for J = (k, k) and a_ik a_jl + a_il a_jk for J = (k, l), k != l, I = (i, j)
    /// (Auld Eq. 3.32, written for any rotation).
    pub fn rotated(&self, a: &[[f64; 3]; 3]) -> Self {
        let m = bond_matrix(a);
        let mut mc = [[0.0; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                mc[i][j] = (0..6).map(|k| m[i][k] * self.c_pa[k][j]).sum();
            }
        }
        let mut out = [[0.0; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                out[i][j] = (0..6).map(|k| mc[i][k] * m[j][k]).sum();
            }
        }
        // Exact symmetry (round-off in M C M^T leaves ~1e-16 relative asymmetry).
        for i in 0..6 {
            for j in 0..i {
                let v = 0.5 * (out[i][j] + out[j][i]);
                out[i][j] = v;
                out[j][i] = v;
            }
        }
        Elasticity { c_pa: out }
    }

    /// Cholesky factor of C, or None if C is not symmetric positive definite (or not finite).
    fn cholesky(&self) -> Option<[[f64; 6]; 6]> {
        let c = &self.c_pa;
        let scale = (0..6).map(|i| c[i][i].abs()).fold(0.0, f64::max);
        for i in 0..6 {
            for j in 0..6 {
                if !c[i][j].is_finite() || (c[i][j] - c[j][i]).abs() > 1e-12 * scale {
                    return None;
                }
            }
        }
        let mut l = [[0.0; 6]; 6];
        for j in 0..6 {
            let d = c[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
            if d.partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            l[j][j] = d.sqrt();
            for i in j + 1..6 {
                l[i][j] = (c[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
            }
        }
        Some(l)
    }

    /// True if C is finite, symmetric and positive definite (a stable material).
    pub fn is_positive_definite(&self) -> bool {
        self.cholesky().is_some()
    }

    /// Compliance S = C^-1 (1/Pa), or None if C is not positive definite.
    pub fn compliance_per_pa(&self) -> Option<[[f64; 6]; 6]> {
        let l = self.cholesky()?;
        let mut s = [[0.0; 6]; 6];
        for col in 0..6 {
            // Solve L L^T x = e_col.
            let mut y = [0.0; 6];
            for i in 0..6 {
                let b = if i == col { 1.0 } else { 0.0 };
                y[i] = (b - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
            }
            let mut x = [0.0; 6];
            for i in (0..6).rev() {
                x[i] = (y[i] - (i + 1..6).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
            }
            for i in 0..6 {
                s[i][col] = x[i];
            }
        }
        Some(s)
    }

    /// Young's modulus along the x axis, E_x = 1 / S11 (Nye, ch. VIII sec. 5), Pa.
    pub fn young_x_pa(&self) -> Option<f64> {
        self.compliance_per_pa().map(|s| 1.0 / s[0][0])
    }

    /// Plane-stress reduced stiffness (sigma_zz = 0) of the in-plane components (xx, yy, xy):
    /// Q_ij = C_ij - C_i3 C_j3 / C33 (Jones, Mechanics of Composite Materials, Eq. 2.61 written
    /// through C; exact when the out-of-plane shears decouple, C_i4 = C_i5 = 0 for i = 1, 2, 6).
    pub fn plane_stress_pa(&self) -> [[f64; 3]; 3] {
        const IDX: [usize; 3] = [0, 1, 5];
        let c = &self.c_pa;
        let mut q = [[0.0; 3]; 3];
        for (a, &i) in IDX.iter().enumerate() {
            for (b, &j) in IDX.iter().enumerate() {
                q[a][b] = c[i][j] - c[i][2] * c[j][2] / c[2][2];
            }
        }
        q
    }

    /// The plate material of the plane-stress reduction (Q16 = Q26 = 0 assumed, as for cubic
    /// crystals in <100> or <110> die axes and isotropic solids).
    pub fn plate_material(&self) -> PlateMaterial {
        let q = self.plane_stress_pa();
        PlateMaterial {
            q11_pa: q[0][0],
            q12_pa: q[0][1],
            q22_pa: q[1][1],
            q66_pa: q[2][2],
        }
    }

    /// sigma = C eps (Voigt, engineering shear strains), Pa.
    pub fn stress_pa(&self, strain: &[f64; 6]) -> [f64; 6] {
        std::array::from_fn(|i| (0..6).map(|j| self.c_pa[i][j] * strain[j]).sum())
    }
}

/// Bond stress transformation matrix M (6x6) of a direction cosine matrix (Auld Eq. 3.32).
pub fn bond_matrix(a: &[[f64; 3]; 3]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    for (row, &(i, j)) in VOIGT.iter().enumerate() {
        for (col, &(k, l)) in VOIGT.iter().enumerate() {
            m[row][col] = if k == l {
                a[i][k] * a[j][k]
            } else {
                a[i][k] * a[j][l] + a[i][l] * a[j][k]
            };
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn si_crystal() -> Elasticity {
        // fe-validation.md (Hopcroft et al. 2010).
        Elasticity::cubic(165.7e9, 63.9e9, 79.6e9)
    }

    /// Independent of the Bond matrix: the fourth-order tensor rotated index by index,
    /// C'_ijkl = a_ip a_jq a_kr a_ls C_pqrs (Nye, Eq. 8.4).
    fn rotate_tensor(e: &Elasticity, a: &[[f64; 3]; 3]) -> [[f64; 6]; 6] {
        let voigt = |i: usize, j: usize| VOIGT.iter().position(|&p| p == (i.min(j), i.max(j)));
        let t = |p: usize, q: usize, r: usize, s: usize| {
            e.c_pa[voigt(p, q).unwrap()][voigt(r, s).unwrap()]
        };
        let mut out = [[0.0; 6]; 6];
        for (row, &(i, j)) in VOIGT.iter().enumerate() {
            for (col, &(k, l)) in VOIGT.iter().enumerate() {
                let mut sum = 0.0;
                for p in 0..3 {
                    for q in 0..3 {
                        for r in 0..3 {
                            for s in 0..3 {
                                sum += a[i][p] * a[j][q] * a[k][r] * a[l][s] * t(p, q, r, s);
                            }
                        }
                    }
                }
                out[row][col] = sum;
            }
        }
        out
    }

    fn max_diff(a: &[[f64; 6]; 6], b: &[[f64; 6]; 6]) -> f64 {
        (0..36)
            .map(|k| (a[k / 6][k % 6] - b[k / 6][k % 6]).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn e_along_110_is_169_gpa() {
        let e = si_crystal().rotated_about_z(45.0).young_x_pa().unwrap();
        // fe-validation.md: E<110> = 169.1 GPa.
        assert!((e / 1e9 - 169.1).abs() < 0.05, "{e}");
        // Along <100>: 1/S11 = (C11 - C12)(C11 + 2 C12)/(C11 + C12) (Nye, cubic inversion).
        let (c11, c12) = (165.7e9, 63.9e9);
        let e100 = (c11 - c12) * (c11 + 2.0 * c12) / (c11 + c12);
        let got = si_crystal().young_x_pa().unwrap();
        assert!((got - e100).abs() < 1e-9 * e100, "{got} {e100}");
        assert!((e100 / 1e9 - 130.2).abs() < 0.1);
    }

    #[test]
    fn bond_rotation_equals_tensor_rotation() {
        // An arbitrary rotation (about z, then about x'): the Bond matrix and the tensor agree.
        let (s, c) = 0.4_f64.sin_cos();
        let (s2, c2) = 1.1_f64.sin_cos();
        let rz = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
        let rx = [[1.0, 0.0, 0.0], [0.0, c2, s2], [0.0, -s2, c2]];
        let a: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| rx[i][k] * rz[k][j]).sum())
        });
        let e = si_crystal();
        let d = max_diff(&e.rotated(&a).c_pa, &rotate_tensor(&e, &a));
        assert!(d < 1e-6 * 165.7e9, "{d}");
        // And the z rotation by the named constructor.
        let d = max_diff(
            &e.rotated_about_z(23.0).c_pa,
            &rotate_tensor(&e, &{
                let (s, c) = 23.0_f64.to_radians().sin_cos();
                [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
            }),
        );
        assert!(d < 1e-6 * 165.7e9, "{d}");
    }

    #[test]
    fn plane_stress_matches_plate_material() {
        for edge in [DieEdge::Along110, DieEdge::Along100] {
            let q = Elasticity::silicon(edge).plate_material();
            let p = PlateMaterial::from_cubic(165.7e9, 63.9e9, 79.6e9, edge);
            for (a, b) in [
                (q.q11_pa, p.q11_pa),
                (q.q12_pa, p.q12_pa),
                (q.q22_pa, p.q22_pa),
                (q.q66_pa, p.q66_pa),
            ] {
                assert!((a - b).abs() < 1e-9 * p.q11_pa, "{edge:?}: {q:?} vs {p:?}");
            }
            let full = Elasticity::silicon(edge).plane_stress_pa();
            assert!(full[0][2].abs() < 1e-12 * full[0][0] && full[1][2].abs() < 1e-12 * full[0][0]);
        }
        // fe-validation.md, <110>: Q11 = 169.76, Q12 = 10.56, Q66 = 50.90 GPa.
        let q = Elasticity::silicon(DieEdge::Along110).plate_material();
        assert!((q.q11_pa / 1e9 - 169.76).abs() < 0.01 && (q.q66_pa / 1e9 - 50.90).abs() < 0.01);
    }

    #[test]
    fn cubic_is_invariant_under_90_deg_and_isotropic_under_any() {
        let e = si_crystal();
        assert!(max_diff(&e.rotated_about_z(90.0).c_pa, &e.c_pa) < 1e-12 * 165.7e9);
        assert!(max_diff(&e.rotated_about_z(45.0).c_pa, &e.c_pa) > 1e9);
        let iso = Elasticity::isotropic(3e9, 0.35);
        assert!(max_diff(&iso.rotated_about_z(33.0).c_pa, &iso.c_pa) < 1e-12 * 3e9);
        // E and nu come back from the compliance.
        let s = iso.compliance_per_pa().unwrap();
        assert!((1.0 / s[0][0] - 3e9).abs() < 1e-3);
        assert!((-s[0][1] / s[0][0] - 0.35).abs() < 1e-12);
    }

    #[test]
    fn stays_symmetric_positive_definite() {
        for deg in [0.0, 10.0, 45.0, 77.0, 90.0, 180.0] {
            let e = si_crystal().rotated_about_z(deg);
            assert!(e.is_positive_definite(), "{deg}");
            for i in 0..6 {
                for j in 0..6 {
                    assert_eq!(e.c_pa[i][j], e.c_pa[j][i]);
                }
            }
        }
        // Unstable materials are detected: nu = 0.5 (incompressible), C12 > C11, NaN.
        assert!(!Elasticity::isotropic(1e9, 0.5).is_positive_definite());
        assert!(!Elasticity::cubic(1e9, 2e9, 1e9).is_positive_definite());
        assert!(!Elasticity::cubic(f64::NAN, 0.0, 1e9).is_positive_definite());
        assert!(Elasticity::isotropic(1e9, 0.5)
            .compliance_per_pa()
            .is_none());
    }
}
