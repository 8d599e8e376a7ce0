//! Plane-stress reduced stiffness of the plate material and its bending stiffness.

use serde::Serialize;

/// Orientation of the die edges on a (100) wafer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum DieEdge {
    /// Edges along <110> (the usual case): crystal axes rotated 45 deg about \[001\].
    Along110,
    /// Edges along <100>: die axes coincide with the crystal axes.
    Along100,
}

/// Plane-stress reduced stiffness Q_ij in die axes (orthotropic, no 16/26 coupling), in Pa.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlateMaterial {
    pub q11_pa: f64,
    pub q12_pa: f64,
    pub q22_pa: f64,
    pub q66_pa: f64,
}

/// Bending stiffness D_ij = Q_ij t^3 / 12 (Kirchhoff plate, Reddy, Mechanics of Laminated Plates,
/// Eq. 3.3.17), in N m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BendingStiffness {
    pub d11_nm: f64,
    pub d12_nm: f64,
    pub d22_nm: f64,
    pub d66_nm: f64,
}

impl PlateMaterial {
    /// Cubic crystal (e.g. Si, Hopcroft et al. JMEMS 2010) on a (100) wafer; plane-stress reduction
    /// Q11 = C11 - C12^2/C11, Q12 = C12 - C12^2/C11, Q66 = C44 (Jones, Mechanics of Composite
    /// Materials, Eq. 2.61), then rotated by 45 deg about \[001\] for <110> die edges.
    pub fn from_cubic(c11_pa: f64, c12_pa: f64, c44_pa: f64, die_edge: DieEdge) -> Self {
        assert!(
            c11_pa > 0.0 && c44_pa > 0.0,
            "cubic stiffness must be positive"
        );
        let q11 = c11_pa - c12_pa * c12_pa / c11_pa;
        let q12 = c12_pa - c12_pa * c12_pa / c11_pa;
        let crystal = PlateMaterial {
            q11_pa: q11,
            q12_pa: q12,
            q22_pa: q11,
            q66_pa: c44_pa,
        };
        match die_edge {
            DieEdge::Along100 => crystal,
            DieEdge::Along110 => crystal.rotated(45.0),
        }
    }

    /// Silicon (Hopcroft, Nix, Kenny, JMEMS 19(2) 2010: C11 = 165.7, C12 = 63.9, C44 = 79.6 GPa).
    pub fn silicon(die_edge: DieEdge) -> Self {
        Self::from_cubic(165.7e9, 63.9e9, 79.6e9, die_edge)
    }

    /// Isotropic: Q11 = Q22 = E/(1-nu^2), Q12 = nu E/(1-nu^2), Q66 = E/(2(1+nu)) (Timoshenko &
    /// Woinowsky-Krieger, Eq. 1.3).
    pub fn isotropic(e_pa: f64, nu: f64) -> Self {
        assert!(
            e_pa > 0.0 && nu > -1.0 && nu < 0.5,
            "isotropic material needs E > 0 and -1 < nu < 0.5"
        );
        let q = e_pa / (1.0 - nu * nu);
        PlateMaterial {
            q11_pa: q,
            q12_pa: nu * q,
            q22_pa: q,
            q66_pa: e_pa / (2.0 * (1.0 + nu)),
        }
    }

    /// In-plane rotation of an orthotropic Q by theta (transformed reduced stiffness Q-bar,
    /// Jones, Mechanics of Composite Materials, Eq. 2.85); only valid where Q16 = Q26 = 0 after
    /// rotation (theta = 0, 45, 90 deg for cubic symmetry).
    pub fn rotated(&self, theta_deg: f64) -> Self {
        let (s, c) = theta_deg.to_radians().sin_cos();
        let (c2, s2) = (c * c, s * s);
        let (q11, q12, q22, q66) = (self.q11_pa, self.q12_pa, self.q22_pa, self.q66_pa);
        PlateMaterial {
            q11_pa: q11 * c2 * c2 + 2.0 * (q12 + 2.0 * q66) * s2 * c2 + q22 * s2 * s2,
            q12_pa: (q11 + q22 - 4.0 * q66) * s2 * c2 + q12 * (s2 * s2 + c2 * c2),
            q22_pa: q11 * s2 * s2 + 2.0 * (q12 + 2.0 * q66) * s2 * c2 + q22 * c2 * c2,
            q66_pa: (q11 + q22 - 2.0 * q12 - 2.0 * q66) * s2 * c2 + q66 * (s2 * s2 + c2 * c2),
        }
    }

    /// D_ij = Q_ij t^3 / 12 (Reddy, Eq. 3.3.17) for thickness t in metres.
    pub fn bending_stiffness(&self, thickness_m: f64) -> BendingStiffness {
        let f = thickness_m.powi(3) / 12.0;
        BendingStiffness {
            d11_nm: self.q11_pa * f,
            d12_nm: self.q12_pa * f,
            d22_nm: self.q22_pa * f,
            d66_nm: self.q66_pa * f,
        }
    }

    /// True if the reduced stiffness is positive definite (Q11 > 0, Q66 > 0, Q11 Q22 > Q12^2).
    pub fn is_positive_definite(&self) -> bool {
        self.q11_pa > 0.0
            && self.q22_pa > 0.0
            && self.q66_pa > 0.0
            && self.q11_pa * self.q22_pa > self.q12_pa * self.q12_pa
            && self.q11_pa.is_finite()
            && self.q22_pa.is_finite()
            && self.q12_pa.is_finite()
            && self.q66_pa.is_finite()
    }

    /// In-plane stress from strain: sigma = Q eps (engineering shear strain gamma_xy), Pa.
    pub fn stress(&self, eps_x: f64, eps_y: f64, gamma_xy: f64) -> [f64; 3] {
        [
            self.q11_pa * eps_x + self.q12_pa * eps_y,
            self.q12_pa * eps_x + self.q22_pa * eps_y,
            self.q66_pa * gamma_xy,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gpa(x: f64) -> f64 {
        x / 1e9
    }

    #[test]
    fn silicon_110_reproduces_reference() {
        let m = PlateMaterial::silicon(DieEdge::Along110);
        assert!((gpa(m.q11_pa) - 169.76).abs() < 0.01, "{m:?}");
        assert!((gpa(m.q22_pa) - 169.76).abs() < 0.01);
        assert!((gpa(m.q12_pa) - 10.56).abs() < 0.01);
        assert!((gpa(m.q66_pa) - 50.90).abs() < 0.01);
    }

    #[test]
    fn silicon_100_reproduces_reference() {
        let m = PlateMaterial::silicon(DieEdge::Along100);
        assert!((gpa(m.q11_pa) - 141.1).abs() < 0.05, "{m:?}");
        assert!((gpa(m.q12_pa) - 39.3).abs() < 0.05);
        assert!((gpa(m.q66_pa) - 79.6).abs() < 0.05);
    }

    #[test]
    fn isotropic_rotation_invariant_and_d() {
        let m = PlateMaterial::isotropic(1e6, 0.25);
        let r = m.rotated(30.0);
        assert!((r.q11_pa - m.q11_pa).abs() < 1e-9 * m.q11_pa);
        assert!((r.q66_pa - m.q66_pa).abs() < 1e-9 * m.q11_pa);
        let d = m.bending_stiffness(1e-3);
        let d_ref = 1e6 * 1e-9 / (12.0 * (1.0 - 0.0625));
        assert!((d.d11_nm - d_ref).abs() < 1e-12 * d_ref);
    }
}
