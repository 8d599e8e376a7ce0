//! Problem definition: mesh, thickness map, material, supports, prescribed dofs and load cases.
//! Inputs are in um and N; everything internal is SI (m, N, Pa).
//! Sign convention: loads are positive in the +w direction ("downward", the load direction), so a
//! positive force gives a positive deflection w; the bottom surface is the side facing +w.

use crate::fe::material::{BendingStiffness, PlateMaterial};
use crate::fe::mesh::RectMesh;
use serde::Serialize;

/// Rectangle with its own thickness (um); later regions win; an element takes the region covering
/// its centre.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ThicknessRegion {
    pub x0_um: f64,
    pub y0_um: f64,
    pub x1_um: f64,
    pub y1_um: f64,
    pub thickness_um: f64,
    /// Height of the region's own mid-plane above the base plate's (against +w): a tooth standing
    /// on the top face rises (t - t_base) / 2, 0 is centred. The large-deflection plate couples
    /// membrane and bending through it (its membrane strain is taken at the base mid-plane); the
    /// linear plate has no membrane and ignores it.
    pub rise_um: f64,
}

/// Support kind along a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SupportKind {
    /// w = 0 and the normal slope = 0 (w, w_x, w_y, w_xy fixed).
    Clamped,
    /// w = 0 along the line (w and the tangential slope fixed).
    SimplySupported,
    /// Mirror plane of a symmetric problem: the normal slope and the twist vanish, w is free
    /// (w_y = w_xy = 0 on a line along x). Carries no force.
    Symmetry,
}

/// Direction of a support line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Axis {
    /// Line along x at y = at_um, from x = from_um to to_um.
    X,
    /// Line along y at x = at_um, from y = from_um to to_um.
    Y,
}

/// A line support on a mesh line; reactions are summed per `group`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineSupport {
    pub group: String,
    pub kind: SupportKind,
    pub along: Axis,
    pub at_um: f64,
    pub from_um: f64,
    pub to_um: f64,
}

/// A film bonded under the plate across the whole problem (the PVDF under the channel floor):
/// part of the plate's bending stiffness ([`PlateProblem::bending_stiffness`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BondedFilm {
    pub material: PlateMaterial,
    pub thickness_um: f64,
}

/// An elastic support along a mesh line: a distributed spring on the deflection w and the slope
/// normal to the line, per unit length of the line (an edge on an elastic footing,
/// [`crate::fe::footing`]). Its force in the load direction is reported as the group's reaction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EdgeSpring {
    pub group: String,
    pub along: Axis,
    pub at_um: f64,
    pub from_um: f64,
    pub to_um: f64,
    /// +1 if the spring's slope theta is +dw/d(normal axis), -1 if it is -dw/d(normal axis): the
    /// slope taken pointing away from the plate, into the footing.
    pub outward: f64,
    /// Stiffness per unit length on (w, theta): [[N/m^2, N/m], [N/m, N]] (symmetric, positive
    /// definite).
    pub stiffness: [[f64; 2]; 2],
    /// For the large-deflection plate: stiffness per unit length (N/m^2) of a spring on the
    /// in-plane displacement normal to the line (the footing's in-plane give,
    /// [`crate::fe::vonkarman`]); `None` holds that displacement, as a clamp does. The
    /// displacement along the line is held either way. The linear plate has no in-plane dofs and
    /// ignores it.
    pub normal_in_plane_pa: Option<f64>,
    /// For the large-deflection plate: the full stiffness per unit length on (w, theta, u), u
    /// the in-plane displacement normal to the line towards the plate (a support that turns
    /// about a point off the mid-plane moves the plate's edge in plane as it turns); it replaces
    /// `stiffness` and `normal_in_plane_pa` there. The linear plate has no in-plane dofs and
    /// keeps `stiffness`.
    pub coupled: Option<[[f64; 3]; 3]>,
    /// A Pasternak term along the line (Pasternak's shear layer, reviewed by Kerr 1964): the
    /// energy 1/2 int q'^T G q' dt of the edge's motion q = (w, theta, u) along it, G per unit
    /// length [[N, N m, N], [N m, N m^2, N m], [N, N m, N]] (symmetric, positive
    /// semi-definite): a support that spreads a motion varying along the wall (the sensor's
    /// support sections measure it). The linear plate takes its (w, theta) block.
    pub along_wall: Option<[[f64; 3]; 3]>,
}

/// Nodal degree of freedom of the BFS element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Dof {
    /// Deflection w (m).
    W,
    /// Slope w_x.
    Wx,
    /// Slope w_y.
    Wy,
    /// Twist w_xy (1/m).
    Wxy,
}

impl Dof {
    /// Offset of the dof within a node's 4 dofs.
    pub fn offset(self) -> usize {
        match self {
            Dof::W => 0,
            Dof::Wx => 1,
            Dof::Wy => 2,
            Dof::Wxy => 3,
        }
    }
}

/// A nodal dof with a prescribed (possibly non-zero) value in SI units (patch tests, imposed
/// settlement).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PrescribedDof {
    pub group: String,
    pub x_um: f64,
    pub y_um: f64,
    pub dof: Dof,
    pub value: f64,
}

/// Axis-aligned rectangle in um.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RectUm {
    pub x0_um: f64,
    pub y0_um: f64,
    pub x1_um: f64,
    pub y1_um: f64,
}

impl RectUm {
    /// Normalised (x0 <= x1, y0 <= y1) copy.
    pub fn normalised(&self) -> Self {
        RectUm {
            x0_um: self.x0_um.min(self.x1_um),
            y0_um: self.y0_um.min(self.y1_um),
            x1_um: self.x0_um.max(self.x1_um),
            y1_um: self.y0_um.max(self.y1_um),
        }
    }
    /// Area in m^2.
    pub fn area_m2(&self) -> f64 {
        (self.x1_um - self.x0_um).abs() * (self.y1_um - self.y0_um).abs() * 1e-12
    }
}

/// A load case component. Forces are positive in the +w (load) direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Load {
    /// Point force; radius 0 = consistent nodal load at the point; radius > 0 spreads it uniformly
    /// over a square patch of equal area (side sqrt(pi) r), clipped per element.
    Point {
        x_um: f64,
        y_um: f64,
        force_n: f64,
        radius_um: f64,
    },
    /// Uniform pressure giving `total_force_n` over the rectangle (None = whole plate).
    Pressure {
        region: Option<RectUm>,
        total_force_n: f64,
    },
    /// Uniform line force giving `total_force_n` along the segment (x0,y0)-(x1,y1).
    Line {
        x0_um: f64,
        y0_um: f64,
        x1_um: f64,
        y1_um: f64,
        total_force_n: f64,
    },
    /// Rotated rectangular probe (uniform pressure over a width x height rectangle centred at (x,
    /// y), rotated by angle_deg counter-clockwise); exact polygon clipping per element.
    Probe {
        x_um: f64,
        y_um: f64,
        width_um: f64,
        height_um: f64,
        angle_deg: f64,
        total_force_n: f64,
    },
    /// Uniform pressure over a simple polygon (um, any orientation) giving `total_force_n`; the
    /// part of a probe or patch that lies over the plate after clipping at the supports.
    Polygon {
        points_um: Vec<(f64, f64)>,
        total_force_n: f64,
    },
}

/// A linear Kirchhoff plate problem with one or more load cases (each case is a list of loads).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateProblem {
    pub mesh: RectMesh,
    pub base_thickness_um: f64,
    pub thickness_regions: Vec<ThicknessRegion>,
    pub material: PlateMaterial,
    pub supports: Vec<LineSupport>,
    /// Elastic edge supports (springs on w and the normal slope along a line).
    pub edge_springs: Vec<EdgeSpring>,
    pub prescribed: Vec<PrescribedDof>,
    pub load_cases: Vec<Vec<Load>>,
    /// A film bonded under the plate, counted in its bending stiffness; None: the plate alone.
    pub bonded_film: Option<BondedFilm>,
}

impl PlateProblem {
    /// Problem with uniform thickness, no supports and no loads yet.
    pub fn new(mesh: RectMesh, thickness_um: f64, material: PlateMaterial) -> Self {
        PlateProblem {
            mesh,
            base_thickness_um: thickness_um,
            thickness_regions: Vec::new(),
            material,
            supports: Vec::new(),
            edge_springs: Vec::new(),
            prescribed: Vec::new(),
            load_cases: Vec::new(),
            bonded_film: None,
        }
    }

    /// Bending stiffness of an element of thickness `t_m` (m): the plate's own, plus a bonded
    /// film's about the element's mid-plane (its centroid (t + t_f) / 2 under it), the parallel
    /// axis theorem on the film's plane-stress stiffness (Reddy, Mechanics of Laminated Plates,
    /// Eq. 3.3.17, the laminate's D). The film's membrane-bending coupling B (a neutral-axis
    /// shift of B / A, 0.2 um on the bundled design) and its in-plane stiffness (0.5 % of the
    /// plate's) are left out.
    pub fn bending_stiffness(&self, t_m: f64) -> BendingStiffness {
        let d = self.material.bending_stiffness(t_m);
        let Some(f) = &self.bonded_film else {
            return d;
        };
        let tf = f.thickness_um * 1e-6;
        let z = 0.5 * (t_m + tf);
        let i = tf.powi(3) / 12.0 + tf * z * z;
        let m = &f.material;
        BendingStiffness {
            d11_nm: d.d11_nm + m.q11_pa * i,
            d12_nm: d.d12_nm + m.q12_pa * i,
            d22_nm: d.d22_nm + m.q22_pa * i,
            d66_nm: d.d66_nm + m.q66_pa * i,
        }
    }

    /// Add one support line per plate edge (groups "x0", "x1", "y0", "y1").
    pub fn support_all_edges(&mut self, kind: SupportKind) -> &mut Self {
        let (x0, y0, x1, y1) = self.mesh.bounds_um();
        for (g, along, at, from, to) in [
            ("y0", Axis::X, y0, x0, x1),
            ("y1", Axis::X, y1, x0, x1),
            ("x0", Axis::Y, x0, y0, y1),
            ("x1", Axis::Y, x1, y0, y1),
        ] {
            self.supports.push(LineSupport {
                group: g.into(),
                kind,
                along,
                at_um: at,
                from_um: from,
                to_um: to,
            });
        }
        self
    }

    /// Thickness (um) of every element: the last region covering the element centre, else the base.
    pub fn element_thickness_um(&self) -> Vec<f64> {
        (0..self.mesh.n_elements())
            .map(|e| {
                self.element_region(e)
                    .map_or(self.base_thickness_um, |r| r.thickness_um)
            })
            .collect()
    }

    /// Mid-plane rise (um, [`ThicknessRegion::rise_um`]) of every element, 0 on the base.
    pub fn element_rise_um(&self) -> Vec<f64> {
        (0..self.mesh.n_elements())
            .map(|e| self.element_region(e).map_or(0.0, |r| r.rise_um))
            .collect()
    }

    /// The last region covering element `e`'s centre.
    fn element_region(&self, e: usize) -> Option<&ThicknessRegion> {
        let (x0, y0, x1, y1) = self.mesh.element_bounds_um(e);
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        self.thickness_regions.iter().rev().find(|r| {
            cx >= r.x0_um.min(r.x1_um)
                && cx <= r.x0_um.max(r.x1_um)
                && cy >= r.y0_um.min(r.y1_um)
                && cy <= r.y0_um.max(r.y1_um)
        })
    }
}
