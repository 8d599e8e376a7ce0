//! What a read-out needs of a solved solid, linear or geometrically nonlinear: the grid, the
//! displacement field, and the stress the read-outs use. The sensor's electrode charges, reactions
//! and stress checks are written once against this trait.

use crate::fe::solid::corner::DriverKinematics;
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::hex27;
use crate::fe::solid::nonlinear::TlSolution;
use crate::fe::solid::principal::principal_stresses_pa;
use crate::fe::solid::solution::{PrincipalPeak, SolidSolution};

/// A solved displacement field on a [`HexGrid`] with a stress at every material point.
/// `Sync`: the read-outs' submodels run in parallel on one field.
pub trait SolidField: Sync {
    /// The grid solved.
    fn grid(&self) -> &HexGrid;
    /// Undeformed node positions (after the node map), um.
    fn node_positions_um(&self) -> &[[f64; 3]];
    /// Displacement of lattice node `n`, m.
    fn node_displacement_m(&self, n: usize) -> [f64; 3];
    /// Element and local point holding the undeformed point `p_um`; None outside the active
    /// elements.
    fn locate(&self, p_um: [f64; 3]) -> Option<([usize; 3], [f64; 3])>;
    /// Displacement (m) at local point `xi` of element (i, j, k); None if void.
    fn displacement_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]>;
    /// The stress the read-outs use (Voigt, Pa): the linear model's C eps; the nonlinear model's
    /// second Piola-Kirchhoff S = C E, in the material's own (undeformed) axes, which is what a
    /// film poled across its thickness responds to when it rotates with the plate.
    fn stress_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]>;
    /// Force (x, y, z) per undeformed area across a cut of normal z, Pa: the nominal stress's
    /// third column, whose integral over a horizontal section is the force through it (the
    /// linear model: sigma_xz, sigma_yz, sigma_zz).
    fn traction_z_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        let s = self.stress_at(element, xi)?;
        Some([s[4], s[3], s[2]])
    }

    /// How a corner submodel reads this field ([`crate::fe::solid::corner`]): as it is, or with
    /// its local rigid rotation taken out (a geometrically nonlinear field).
    fn kinematics(&self) -> DriverKinematics {
        DriverKinematics::Linear
    }

    /// Displacement (m) of the material point at undeformed position `p_um`.
    fn displacement_m(&self, p_um: [f64; 3]) -> Option<[f64; 3]> {
        let (e, xi) = self.locate(p_um)?;
        self.displacement_at(e, xi)
    }

    /// The largest principal [`Self::stress_at`] over the 27 Gauss points of each given element
    /// (void ones skipped); None if no element is active.
    fn max_principal_stress(
        &self,
        elements: impl IntoIterator<Item = usize>,
    ) -> Option<PrincipalPeak>
    where
        Self: Sized,
    {
        let grid = self.grid();
        let pos = self.node_positions_um();
        let mut best: Option<PrincipalPeak> = None;
        for e in elements {
            let ijk = grid.element_ijk(e);
            if grid.material(e).is_none() {
                continue;
            }
            let x = grid.element_nodes(e).map(|n| pos[n]);
            for (xi, _) in hex27::gauss_points() {
                let Some(st) = self.stress_at(ijk, xi) else {
                    continue;
                };
                let s = principal_stresses_pa(&st)[0];
                if best.is_none_or(|b| s > b.stress_pa) {
                    best = Some(PrincipalPeak {
                        stress_pa: s,
                        element: ijk,
                        xi,
                        position_um: hex27::position(&x, xi),
                    });
                }
            }
        }
        best
    }
}

impl SolidField for SolidSolution {
    fn grid(&self) -> &HexGrid {
        SolidSolution::grid(self)
    }
    fn node_positions_um(&self) -> &[[f64; 3]] {
        SolidSolution::node_positions_um(self)
    }
    fn node_displacement_m(&self, n: usize) -> [f64; 3] {
        SolidSolution::node_displacement_m(self, n)
    }
    fn locate(&self, p_um: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        SolidSolution::locate(self, p_um)
    }
    fn displacement_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        SolidSolution::displacement_at(self, element, xi)
    }
    fn stress_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        SolidSolution::stress_at(self, element, xi)
    }
}

impl SolidField for TlSolution {
    fn grid(&self) -> &HexGrid {
        TlSolution::grid(self)
    }
    fn node_positions_um(&self) -> &[[f64; 3]] {
        TlSolution::node_positions_um(self)
    }
    fn node_displacement_m(&self, n: usize) -> [f64; 3] {
        TlSolution::node_displacement_m(self, n)
    }
    fn locate(&self, p_um: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        self.linear_field().locate(p_um)
    }
    fn displacement_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        TlSolution::displacement_at(self, element, xi)
    }
    fn stress_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        self.second_piola_kirchhoff_at(element, xi)
    }
    fn kinematics(&self) -> DriverKinematics {
        DriverKinematics::Corotated
    }
    fn traction_z_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        let p = self.first_piola_kirchhoff_at(element, xi)?;
        Some([p[0][2], p[1][2], p[2][2]])
    }
}
