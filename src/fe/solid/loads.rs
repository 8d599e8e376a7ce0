//! Load vectors of the solid: point forces on nodes and consistent nodal forces of uniform face
//! pressures, f_a = -p integral N_a n dA over the (mapped) faces (Hughes, The Finite Element
//! Method, Eq. 3.9.7, 3x3 Gauss on each face).

use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::dofs::{position_tol_um, SolidDofs};
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::hex27::{self, NODES};
use crate::fe::solid::problem::{Axis3, FaceRect, Outward, Snap, SolidLoad};

/// Index of the grid line at `at` (within 1e-9 of the extent), if any.
fn line_index(lines: &[f64], at: f64, tol: f64) -> Option<usize> {
    let k = lines.partition_point(|&v| v < at - tol);
    (k < lines.len() && (lines[k] - at).abs() <= tol).then_some(k)
}

/// Node receiving a point load at `at_um`.
pub(crate) fn load_node(
    pos_um: &[[f64; 3]],
    dofs: &SolidDofs,
    at_um: [f64; 3],
    snap: Snap,
    tol_um: f64,
) -> Option<usize> {
    let d2 = |p: &[f64; 3]| (0..3).map(|d| (p[d] - at_um[d]).powi(2)).sum::<f64>();
    let best = (0..pos_um.len())
        .filter(|&n| dofs.active[n])
        .min_by(|&a, &b| d2(&pos_um[a]).total_cmp(&d2(&pos_um[b])))?;
    match snap {
        Snap::Nearest => Some(best),
        Snap::Exact => (d2(&pos_um[best]).sqrt() <= tol_um).then_some(best),
    }
}

/// The part of an element's face a load covers: the element, and in its local coordinates the
/// plane's xi along the axis and the ranges along the two others (the whole face, [-1, 1]^2,
/// unless the cell lies inside a merged brick).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FacePart {
    pub element: usize,
    pub xi_axis: f64,
    pub range: [[f64; 2]; 2],
}

/// Elements and local face coordinates of a face rectangle; errors if its values are not grid
/// lines or it covers no active element.
pub(crate) fn face_elements(
    grid: &HexGrid,
    face: &FaceRect,
    case: usize,
    index: usize,
) -> FeResult<Vec<FacePart>> {
    let lines = grid.lines_um();
    let tol = position_tol_um(grid);
    let ax = face.axis.index();
    let [p, q] = face.axis.others();
    let bad = |what: &str| FeError::SolidInput {
        detail: format!("pressure {index} of load case {case}: {what}"),
        hint: "a pressure rectangle's plane and edges must be grid lines (before the node map), \
               with from < to, on the side of some active elements",
    };
    let l =
        line_index(lines[ax], face.at_um, tol).ok_or_else(|| bad("plane not on a grid line"))?;
    let layer = match face.outward {
        Outward::Plus => l.checked_sub(1),
        Outward::Minus => (l + 1 < lines[ax].len()).then_some(l),
    }
    .ok_or_else(|| bad("no elements on the loaded side of the plane"))?;
    let range = |d: usize, k: usize| -> FeResult<(usize, usize)> {
        let a = line_index(lines[d], face.from_um[k], tol);
        let b = line_index(lines[d], face.to_um[k], tol);
        match (a, b) {
            (Some(a), Some(b)) if a < b => Ok((a, b)),
            _ => Err(bad("rectangle edges not on grid lines or empty")),
        }
    };
    let (rp, rq) = (range(p, 0)?, range(q, 1)?);
    let mut out = Vec::new();
    for iq in rq.0..rq.1 {
        for ip in rp.0..rp.1 {
            let mut ijk = [0; 3];
            ijk[ax] = layer;
            ijk[p] = ip;
            ijk[q] = iq;
            let cell = grid.element(ijk);
            if grid.cell_material(cell).is_some() {
                let (element, offset, scale) = grid.cell_in_owner(cell);
                let side = match face.outward {
                    Outward::Plus => 1.0,
                    Outward::Minus => -1.0,
                };
                let span = |d: usize| [offset[d] - scale[d], offset[d] + scale[d]];
                out.push(FacePart {
                    element,
                    xi_axis: offset[ax] + scale[ax] * side,
                    range: [span(p), span(q)],
                });
            }
        }
    }
    if out.is_empty() {
        return Err(bad("every element under the rectangle is void"));
    }
    Ok(out)
}

/// Consistent nodal forces (N, 3 per element node) of pressure `p_pa` on the part `range`
/// (local coordinates along the two other axes) of the element's section at xi = `xi_axis` (a
/// face at +-1; a part of a merged brick's face over one cell): f_a = -p sum_g w_g N_a (x_,p x
/// x_,q) s with s orienting the normal outward.
pub(crate) fn face_part_forces(
    nodes_m: &[[f64; 3]; NODES],
    axis: Axis3,
    outward: Outward,
    p_pa: f64,
    xi_axis: f64,
    range: [[f64; 2]; 2],
) -> [[f64; 3]; NODES] {
    let ax = axis.index();
    let [p, q] = axis.others();
    // e_p x e_q is +e_ax for x and z, -e_y for y (the others are in increasing order).
    let orient = if axis == Axis3::Y { -1.0 } else { 1.0 };
    let s = match outward {
        Outward::Plus => orient,
        Outward::Minus => -orient,
    };
    let g = hex27::gauss3();
    let mid = range.map(|[a, b]| 0.5 * (a + b));
    let half = range.map(|[a, b]| 0.5 * (b - a));
    let mut f = [[0.0; 3]; NODES];
    for (a, wa) in g {
        for (b, wb) in g {
            let (wa, wb) = (wa * half[0], wb * half[1]);
            let mut xi = [0.0; 3];
            xi[ax] = xi_axis;
            xi[p] = mid[0] + half[0] * a;
            xi[q] = mid[1] + half[1] * b;
            let n = hex27::shape(xi);
            let dn = hex27::shape_derivatives(xi);
            let tp: [f64; 3] =
                std::array::from_fn(|d| (0..NODES).map(|k| dn[k][p] * nodes_m[k][d]).sum());
            let tq: [f64; 3] =
                std::array::from_fn(|d| (0..NODES).map(|k| dn[k][q] * nodes_m[k][d]).sum());
            let normal = [
                tp[1] * tq[2] - tp[2] * tq[1],
                tp[2] * tq[0] - tp[0] * tq[2],
                tp[0] * tq[1] - tp[1] * tq[0],
            ];
            for (k, fk) in f.iter_mut().enumerate() {
                for d in 0..3 {
                    fk[d] -= p_pa * wa * wb * n[k] * s * normal[d];
                }
            }
        }
    }
    f
}

/// Global load vector (N, 3 per lattice node) of one load case.
pub(crate) fn load_vector(
    grid: &HexGrid,
    pos_um: &[[f64; 3]],
    dofs: &SolidDofs,
    loads: &[SolidLoad],
    case: usize,
) -> FeResult<Vec<f64>> {
    let tol = position_tol_um(grid);
    let mut f = vec![0.0; 3 * pos_um.len()];
    for (index, load) in loads.iter().enumerate() {
        match load {
            SolidLoad::Point {
                at_um,
                force_n,
                snap,
            } => {
                if at_um.iter().chain(force_n).any(|v| !v.is_finite()) {
                    return Err(FeError::SolidInput {
                        detail: format!("point load {index} of case {case} is not finite"),
                        hint: "positions (um) and forces (N) must be finite",
                    });
                }
                let n = load_node(pos_um, dofs, *at_um, *snap, tol).ok_or_else(|| {
                    FeError::SolidInput {
                        detail: format!(
                            "point load {index} of case {case} at {at_um:?} um is not on a node"
                        ),
                        hint: "put the point on a node (a grid line crossing or mid-line) or use \
                               Snap::Nearest",
                    }
                })?;
                for d in 0..3 {
                    f[3 * n + d] += force_n[d];
                }
            }
            SolidLoad::Pressure { face, pressure_pa } => {
                if !pressure_pa.is_finite() {
                    return Err(FeError::SolidInput {
                        detail: format!("pressure {index} of case {case} is {pressure_pa}"),
                        hint: "pressures (Pa) must be finite",
                    });
                }
                for part in face_elements(grid, face, case, index)? {
                    let nodes = grid.element_nodes(part.element);
                    let x = nodes.map(|n| pos_um[n].map(|v| v * 1e-6));
                    let fe = face_part_forces(
                        &x,
                        face.axis,
                        face.outward,
                        *pressure_pa,
                        part.xi_axis,
                        part.range,
                    );
                    for (k, &n) in nodes.iter().enumerate() {
                        for d in 0..3 {
                            f[3 * n + d] += fe[k][d];
                        }
                    }
                }
            }
        }
    }
    // A force on a hanging node acts on its masters.
    dofs.hanging.reduce(&mut f);
    Ok(f)
}
