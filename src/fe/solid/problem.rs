//! The solid problem: grid, materials, constraints (clamps, symmetry planes, prescribed linear
//! fields) and load cases (point forces, face pressures). Positions in um, forces in N, pressures
//! in Pa, displacements in m.

use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::shear_tying::TransverseShear;

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis3 {
    X,
    Y,
    Z,
}

impl Axis3 {
    /// 0, 1, 2 for x, y, z.
    pub fn index(self) -> usize {
        match self {
            Axis3::X => 0,
            Axis3::Y => 1,
            Axis3::Z => 2,
        }
    }

    /// The other two axes in increasing order (x: y, z; y: x, z; z: x, y).
    pub fn others(self) -> [usize; 2] {
        match self {
            Axis3::X => [1, 2],
            Axis3::Y => [0, 2],
            Axis3::Z => [0, 1],
        }
    }
}

/// A set of nodes selected by their (mapped) position; matching uses a tolerance of 1e-9 of the
/// grid's extent. Nodes of void elements only are never selected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeSet {
    /// Every node on the plane `axis = at_um`.
    Plane { axis: Axis3, at_um: f64 },
    /// Every node inside the box (boundary included).
    Box { min_um: [f64; 3], max_um: [f64; 3] },
}

impl NodeSet {
    /// True if a node at `p_um` belongs to the set, with tolerance `tol_um`.
    pub fn contains(&self, p_um: [f64; 3], tol_um: f64) -> bool {
        match *self {
            NodeSet::Plane { axis, at_um } => (p_um[axis.index()] - at_um).abs() <= tol_um,
            NodeSet::Box { min_um, max_um } => {
                (0..3).all(|d| p_um[d] >= min_um[d] - tol_um && p_um[d] <= max_um[d] + tol_um)
            }
        }
    }
}

/// Values of the constrained components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Prescribed {
    /// Held at zero (clamps, supports, symmetry planes).
    Zero,
    /// u_i = u0_i + sum_j G_ij x_j with x the node position in m (patch tests, imposed strain).
    Linear {
        u0_m: [f64; 3],
        gradient: [[f64; 3]; 3],
    },
}

/// Fixes the chosen displacement components of every node in a set; reactions are summed per
/// `group`. A dof constrained twice keeps the first constraint listed.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    pub group: String,
    pub nodes: NodeSet,
    /// Which of u_x, u_y, u_z are fixed.
    pub fixed: [bool; 3],
    pub value: Prescribed,
}

impl Constraint {
    /// All three components held at zero (a clamp).
    pub fn clamp(group: &str, nodes: NodeSet) -> Self {
        Constraint {
            group: group.into(),
            nodes,
            fixed: [true; 3],
            value: Prescribed::Zero,
        }
    }

    /// Plane strain across x: u_x held at zero at every node (a section one element thick).
    pub fn plane_strain_x(group: &str) -> Self {
        let big = 1e9;
        Constraint {
            group: group.into(),
            nodes: NodeSet::Box {
                min_um: [-big; 3],
                max_um: [big; 3],
            },
            fixed: [true, false, false],
            value: Prescribed::Zero,
        }
    }

    /// A symmetry plane `axis = at_um`: the normal component held at zero.
    pub fn symmetry(group: &str, axis: Axis3, at_um: f64) -> Self {
        let mut fixed = [false; 3];
        fixed[axis.index()] = true;
        Constraint {
            group: group.into(),
            nodes: NodeSet::Plane { axis, at_um },
            fixed,
            value: Prescribed::Zero,
        }
    }
}

/// Which side of the face layer the loaded elements are on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outward {
    /// The face's outward normal points along +axis: the loaded elements lie below the plane.
    Plus,
    /// Outward normal along -axis: the elements lie above the plane.
    Minus,
}

/// A rectangle on a grid plane: `axis = at_um`, spanning `from_um..to_um` in the other two axes
/// (in increasing axis order, see [`Axis3::others`]). All four values are grid lines (before the
/// node map), so the rectangle is a union of element faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceRect {
    pub axis: Axis3,
    pub at_um: f64,
    pub outward: Outward,
    pub from_um: [f64; 2],
    pub to_um: [f64; 2],
}

/// How a point load finds its node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Snap {
    /// The point must be a node (within 1e-9 of the extent): an error otherwise.
    Exact,
    /// The nearest node of an active element.
    Nearest,
}

/// One load of a load case.
#[derive(Debug, Clone, PartialEq)]
pub enum SolidLoad {
    /// A force vector (N) on one node.
    Point {
        at_um: [f64; 3],
        force_n: [f64; 3],
        snap: Snap,
    },
    /// Uniform pressure (Pa, positive pushing into the material, against the outward normal) on
    /// the faces of the active elements in a rectangle, as consistent nodal forces over the
    /// (mapped) faces.
    Pressure { face: FaceRect, pressure_pa: f64 },
}

/// A linear elastic solid with one or more load cases.
#[derive(Debug, Clone)]
pub struct SolidProblem {
    pub grid: HexGrid,
    /// Material `m` of the grid's elements is `materials[m]`.
    pub materials: Vec<Elasticity>,
    pub constraints: Vec<Constraint>,
    pub load_cases: Vec<Vec<SolidLoad>>,
    /// How the bricks take their transverse shear strains (the plain brick unless set).
    pub shear: TransverseShear,
}

impl SolidProblem {
    /// A problem without constraints and loads.
    pub fn new(grid: HexGrid, materials: Vec<Elasticity>) -> Self {
        SolidProblem {
            grid,
            materials,
            constraints: Vec::new(),
            load_cases: Vec::new(),
            shear: TransverseShear::default(),
        }
    }
}
