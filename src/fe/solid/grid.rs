//! Structured hexahedral grid: element boundary lines `xs, ys, zs` (um), the lattice of 27-node
//! element nodes between them, an optional map of every node position (curved or slanted
//! geometry, e.g. a frustum's {111} sidewall) and a material per element (None = void).
//!
//! Element (i, j, k) spans [xs_i, xs_i+1] x [ys_j, ys_j+1] x [zs_k, zs_k+1] before the map. The
//! node lattice has (2 nx + 1)(2 ny + 1)(2 nz + 1) positions: even lattice indices are element
//! boundary lines, odd ones the element mid-lines. Lattice node (I, J, K) has index
//! `I + nxl (J + nyl K)`.
//!
//! Local refinement: [`HexGrid::merge`] joins a box of cells into one brick (the cells stay
//! fine around it), so a line need not cross the whole die. The merged brick's nodes are lattice
//! nodes; the finer neighbours' nodes on its faces hang and take its quadratic trace
//! ([`crate::fe::solid::hanging`]).

use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::hex27;

/// A map of node positions, um to um, applied to every lattice node.
pub type NodeMap = Arc<dyn Fn([f64; 3]) -> [f64; 3] + Send + Sync>;

/// Largest number of free and constrained dofs a solid model may have \[choice\]: ~3 million dofs
/// of 27-node bricks need tens of GB for the factor; refused before anything that size is
/// allocated.
pub const MAX_DOFS: usize = 3_000_000;

/// Largest node lattice (void nodes included) \[choice\]: bounds the position and dof tables.
pub const MAX_LATTICE_NODES: usize = 8_000_000;

/// Smallest scaled Jacobian determinant (1 for a box) accepted at a Gauss point \[choice\]: below
/// it an element is degenerate (flat) or inverted and its stiffness is meaningless.
pub const MIN_SCALED_JACOBIAN: f64 = 1e-6;

/// The grid: lines, element materials and the node map.
#[derive(Clone)]
pub struct HexGrid {
    xs_um: Vec<f64>,
    ys_um: Vec<f64>,
    zs_um: Vec<f64>,
    material: Vec<Option<u16>>,
    map: Option<NodeMap>,
    /// Merged bricks: element (its lowest cell) -> per axis the lattice indices of its first,
    /// middle and last node layer.
    merged: HashMap<usize, [[usize; 3]; 3]>,
    /// Cells inside a merged brick other than its first -> that brick's element.
    covered: HashMap<usize, usize>,
    /// How far (um) a drawn face may lie from the grid's: a builder that merges lines closer
    /// than a gap moves a face by up to that gap ([`HexGrid::with_tolerance_um`]).
    tolerance_um: f64,
}

impl fmt::Debug for HexGrid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HexGrid")
            .field("xs_um", &self.xs_um)
            .field("ys_um", &self.ys_um)
            .field("zs_um", &self.zs_um)
            .field(
                "active",
                &self.material.iter().filter(|m| m.is_some()).count(),
            )
            .field("mapped", &self.map.is_some())
            .field("merged", &self.merged.len())
            .field("tolerance_um", &self.tolerance_um)
            .finish()
    }
}

/// `n` equal intervals from `from` to `to`: n + 1 lines.
pub fn uniform_lines(from_um: f64, to_um: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|k| from_um + (to_um - from_um) * k as f64 / n.max(1) as f64)
        .collect()
}

/// More lines in one direction than any grid within [`MAX_LATTICE_NODES`] can have (the other
/// two directions at their least, two lines each).
const MAX_GRADED_LINES: usize = MAX_LATTICE_NODES / 18 + 2;

/// Lines from `from` to `to` (either order) starting at `h0` next to `from` and growing by
/// `growth` up to `h_max`; the last interval ends exactly at `to` (it may be up to 1.5 steps).
/// Sizes that would need more lines than any grid can take (a tiny `h_max`, or a `growth` of 1
/// from a tiny `h0`) stop there, before allocating the rest: [`HexGrid::new`] refuses the result.
pub fn graded_lines(from_um: f64, to_um: f64, h0_um: f64, growth: f64, h_max_um: f64) -> Vec<f64> {
    let (len, dir) = ((to_um - from_um).abs(), (to_um - from_um).signum());
    let mut out = vec![from_um];
    let (mut at, mut step) = (0.0, h0_um.min(len));
    while step > 0.0 && at + 1.5 * step < len && out.len() <= MAX_GRADED_LINES {
        at += step;
        out.push(from_um + dir * at);
        step = (step * growth).min(h_max_um);
    }
    out.push(to_um);
    out
}

/// Sorted, with near-duplicates (within 1e-9 of the extent) merged.
pub fn merged_lines(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    let tol = 1e-9 * v.last().map_or(1.0, |l| l.abs().max(1.0));
    v.dedup_by(|a, b| (*a - *b).abs() <= tol);
    v
}

fn check_lines(name: &str, lines: &[f64]) -> FeResult<()> {
    if lines.len() < 2 {
        return Err(FeError::SolidInput {
            detail: format!("{name} has {} lines", lines.len()),
            hint: "give at least two lines (one element) per direction",
        });
    }
    if let Some(v) = lines.iter().find(|v| !v.is_finite()) {
        return Err(FeError::SolidInput {
            detail: format!("{name} contains {v}"),
            hint: "grid lines must be finite numbers in um",
        });
    }
    if let Some(w) = lines.windows(2).find(|w| w[1] <= w[0]) {
        return Err(FeError::SolidInput {
            detail: format!("{name} is not strictly increasing ({} then {})", w[0], w[1]),
            hint: "sort the grid lines and remove duplicates",
        });
    }
    Ok(())
}

impl HexGrid {
    /// A grid with every element of material 0 and no map. Errors on fewer than two, non-finite
    /// or non-increasing lines and on a lattice over [`MAX_LATTICE_NODES`] (checked before any
    /// allocation).
    pub fn new(xs_um: &[f64], ys_um: &[f64], zs_um: &[f64]) -> FeResult<Self> {
        check_lines("xs", xs_um)?;
        check_lines("ys", ys_um)?;
        check_lines("zs", zs_um)?;
        let lattice = [xs_um.len(), ys_um.len(), zs_um.len()]
            .iter()
            .map(|&n| 2 * n - 1)
            .try_fold(1usize, |a, n| a.checked_mul(n))
            .unwrap_or(usize::MAX);
        if lattice > MAX_LATTICE_NODES {
            return Err(FeError::TooLarge {
                detail: format!("{lattice} lattice nodes"),
                limit: MAX_LATTICE_NODES,
                hint: "use fewer grid lines (coarser elements) or a half/quarter model",
            });
        }
        let n = (xs_um.len() - 1) * (ys_um.len() - 1) * (zs_um.len() - 1);
        Ok(HexGrid {
            xs_um: xs_um.to_vec(),
            ys_um: ys_um.to_vec(),
            zs_um: zs_um.to_vec(),
            material: vec![Some(0); n],
            map: None,
            merged: HashMap::new(),
            covered: HashMap::new(),
            tolerance_um: 0.0,
        })
    }

    /// The grid with its faces known only to within `um` of the faces its builder drew (it
    /// merged lines closer than that): a point that far outside the active elements is read on
    /// the nearest one ([`crate::fe::solid::SolidSolution::locate`]). Zero (the default): only
    /// points inside an element, within round-off, are found.
    #[track_caller]
    pub fn with_tolerance_um(mut self, um: f64) -> Self {
        assert!(
            um.is_finite() && um >= 0.0,
            "a grid's tolerance is a finite length >= 0"
        );
        self.tolerance_um = um;
        self
    }

    /// See [`HexGrid::with_tolerance_um`].
    pub fn tolerance_um(&self) -> f64 {
        self.tolerance_um
    }

    /// The grid with `map` applied to every node position (um to um). Validated when the model
    /// is built: non-finite positions and inverted elements are errors there.
    pub fn with_map(mut self, map: NodeMap) -> Self {
        self.map = Some(map);
        self
    }

    /// True if a node map is set.
    pub fn is_mapped(&self) -> bool {
        self.map.is_some()
    }

    /// Element boundary lines along x, y, z (um, before the map).
    pub fn lines_um(&self) -> [&[f64]; 3] {
        [&self.xs_um, &self.ys_um, &self.zs_um]
    }

    /// Elements per direction.
    pub fn n_elements(&self) -> [usize; 3] {
        [
            self.xs_um.len() - 1,
            self.ys_um.len() - 1,
            self.zs_um.len() - 1,
        ]
    }

    /// Number of elements, void included.
    pub fn element_count(&self) -> usize {
        self.material.len()
    }

    /// Lattice nodes per direction (2 n + 1).
    pub fn lattice(&self) -> [usize; 3] {
        self.n_elements().map(|n| 2 * n + 1)
    }

    /// Number of lattice nodes.
    pub fn node_count(&self) -> usize {
        self.lattice().iter().product()
    }

    /// Index of element (i, j, k). Panics outside the grid (misuse).
    #[track_caller]
    pub fn element(&self, [i, j, k]: [usize; 3]) -> usize {
        let [nx, ny, nz] = self.n_elements();
        assert!(
            i < nx && j < ny && k < nz,
            "element ({i}, {j}, {k}) outside the grid"
        );
        i + nx * (j + ny * k)
    }

    /// (i, j, k) of element index `e`.
    pub fn element_ijk(&self, e: usize) -> [usize; 3] {
        let [nx, ny, _] = self.n_elements();
        [e % nx, (e / nx) % ny, e / (nx * ny)]
    }

    /// Index of lattice node (I, J, K).
    pub fn node(&self, [i, j, k]: [usize; 3]) -> usize {
        let [nxl, nyl, _] = self.lattice();
        i + nxl * (j + nyl * k)
    }

    /// (I, J, K) of lattice node `n`.
    pub fn node_ijk(&self, n: usize) -> [usize; 3] {
        let [nxl, nyl, _] = self.lattice();
        [n % nxl, (n / nxl) % nyl, n / (nxl * nyl)]
    }

    /// Material of every element (index `i + nx (j + ny k)`), None = void.
    pub fn materials(&self) -> &[Option<u16>] {
        &self.material
    }

    /// Material of element `e`.
    pub fn material(&self, e: usize) -> Option<u16> {
        self.material[e]
    }

    /// Sets the material of element (i, j, k) (None = void).
    #[track_caller]
    pub fn set_material(&mut self, ijk: [usize; 3], material: Option<u16>) {
        let e = self.element(ijk);
        assert!(
            !self.covered.contains_key(&e),
            "element {ijk:?} lies inside a merged brick"
        );
        self.material[e] = material;
    }

    /// Sets every element's material from its centre (um, before the map). Panics once cells
    /// are merged (misuse: assign materials first).
    #[track_caller]
    pub fn assign(&mut self, f: impl Fn([f64; 3]) -> Option<u16>) {
        assert!(self.merged.is_empty(), "assign materials before merging");
        for e in 0..self.material.len() {
            let c = self.element_centre_um(e);
            self.material[e] = f(c);
        }
    }

    /// First and last line of element `e` per axis (a merged brick spans several cells).
    pub fn element_lines(&self, e: usize) -> [[usize; 2]; 3] {
        match self.merged.get(&e) {
            Some(b) => b.map(|[lo, _, hi]| [lo / 2, hi / 2]),
            None => self.element_ijk(e).map(|i| [i, i + 1]),
        }
    }

    /// Centre of element `e` before the map, um.
    pub fn element_centre_um(&self, e: usize) -> [f64; 3] {
        let l = self.element_lines(e);
        let lines = self.lines_um();
        std::array::from_fn(|d| 0.5 * (lines[d][l[d][0]] + lines[d][l[d][1]]))
    }

    /// Size of element `e` before the map, um.
    pub fn element_size_um(&self, e: usize) -> [f64; 3] {
        let l = self.element_lines(e);
        let lines = self.lines_um();
        std::array::from_fn(|d| lines[d][l[d][1]] - lines[d][l[d][0]])
    }

    /// Joins the cells `lo .. hi` (element indices, `hi` exclusive) into one brick, the
    /// element of cell `lo`; the others become void and [`Self::owner`] names the brick. Along
    /// an axis of more than one cell a line must halve the span (within 1e-9 of the extent): it
    /// carries the brick's middle nodes, so the brick is a box and the finer neighbours' nodes
    /// on its faces lie on its quadratic trace. Errors if the box leaves the grid, spans one
    /// cell, has no halving line, or holds a void, merged or differently made cell.
    ///
    /// Neighbouring bricks must nest: each shared face of one lies within a face of the other,
    /// as when cells merge back into the coarse cell they were bisected from. Bricks whose faces
    /// overlap only in part (offset by a cell) would share nodes without either hanging, and
    /// their traces would differ there: the dof numbering refuses them
    /// ([`crate::fe::solid::hanging::Hanging::find`]).
    pub fn merge(&mut self, lo: [usize; 3], hi: [usize; 3]) -> FeResult<usize> {
        let ne = self.n_elements();
        let bad = |detail: String| FeError::SolidInput {
            detail,
            hint: "merge boxes of cells of one material, inside the grid, not merged before, \
                   each axis one cell or halved by a line",
        };
        if (0..3).any(|d| lo[d] >= hi[d] || hi[d] > ne[d]) {
            return Err(bad(format!(
                "cells {lo:?} .. {hi:?} are empty or leave the grid of {ne:?} cells"
            )));
        }
        if (0..3).all(|d| hi[d] - lo[d] == 1) {
            return Err(bad(format!("cells {lo:?} .. {hi:?} are one cell")));
        }
        let tol = 1e-9 * self.extent_um();
        let mut layers = [[0usize; 3]; 3];
        for d in 0..3 {
            let lines = self.lines_um()[d];
            let (a, b) = (lo[d], hi[d]);
            let mid = if b - a == 1 {
                2 * a + 1
            } else {
                let want = 0.5 * (lines[a] + lines[b]);
                let m = (a + 1..b)
                    .find(|&m| (lines[m] - want).abs() <= tol)
                    .ok_or_else(|| {
                        bad(format!(
                            "no line halves cells {} .. {} along axis {d} (wanted {want} um)",
                            a, b
                        ))
                    })?;
                2 * m
            };
            layers[d] = [2 * a, mid, 2 * b];
        }
        // Under a node map the brick's quadratic trace must put every lattice node of the box
        // where the map does (an affine or bilinear map does): else the nodes hanging on its
        // faces would open gaps.
        if let Some(map) = &self.map {
            let node_at = |l: [usize; 3]| self.lattice_position_um(self.node(l));
            let corners: [[f64; 3]; hex27::NODES] = std::array::from_fn(|n| {
                map(node_at([
                    layers[0][n % 3],
                    layers[1][(n / 3) % 3],
                    layers[2][n / 9],
                ]))
            });
            let a = node_at([layers[0][0], layers[1][0], layers[2][0]]);
            let b = node_at([layers[0][2], layers[1][2], layers[2][2]]);
            for k in 2 * lo[2]..=2 * hi[2] {
                for j in 2 * lo[1]..=2 * hi[1] {
                    for i in 2 * lo[0]..=2 * hi[0] {
                        let p = node_at([i, j, k]);
                        let xi: [f64; 3] =
                            std::array::from_fn(|d| (2.0 * p[d] - a[d] - b[d]) / (b[d] - a[d]));
                        let want = map(p);
                        let got = hex27::position(&corners, xi);
                        if (0..3).any(|d| (got[d] - want[d]).abs() > tol) {
                            return Err(bad(format!(
                                "the node map bends cells {lo:?} .. {hi:?} (the node at {p:?} \
                                 um goes to {want:?}, the brick's trace to {got:?})"
                            )));
                        }
                    }
                }
            }
        }
        let first = self.element(lo);
        let material = self.material[first];
        let mut cells = Vec::new();
        for k in lo[2]..hi[2] {
            for j in lo[1]..hi[1] {
                for i in lo[0]..hi[0] {
                    let e = self.element([i, j, k]);
                    if material.is_none()
                        || self.material[e] != material
                        || self.merged.contains_key(&e)
                        || self.covered.contains_key(&e)
                    {
                        return Err(bad(format!(
                            "cell {:?} is void, of another material or merged already",
                            [i, j, k]
                        )));
                    }
                    cells.push(e);
                }
            }
        }
        for e in cells.into_iter().filter(|&e| e != first) {
            self.material[e] = None;
            self.covered.insert(e, first);
        }
        self.merged.insert(first, layers);
        Ok(first)
    }

    /// The element holding cell `e` and the affine map of the cell's local coordinates into the
    /// element's: xi_element = offset + scale xi_cell (offset 0, scale 1 for an unmerged cell).
    pub fn cell_in_owner(&self, e: usize) -> (usize, [f64; 3], [f64; 3]) {
        let owner = self.owner(e);
        if owner == e && !self.merged.contains_key(&e) {
            return (e, [0.0; 3], [1.0; 3]);
        }
        let lines = self.lines_um();
        let ijk = self.element_ijk(e);
        let (c, h) = (self.element_centre_um(owner), self.element_size_um(owner));
        let mut offset = [0.0; 3];
        let mut scale = [0.0; 3];
        for d in 0..3 {
            let (a, b) = (lines[d][ijk[d]], lines[d][ijk[d] + 1]);
            offset[d] = (a + b - 2.0 * c[d]) / h[d];
            scale[d] = (b - a) / h[d];
        }
        (owner, offset, scale)
    }

    /// Material of the element holding cell `e` (a cell inside a merged brick has the brick's).
    pub fn cell_material(&self, e: usize) -> Option<u16> {
        self.material[self.owner(e)]
    }

    /// True if some cells are merged.
    pub fn has_merged(&self) -> bool {
        !self.merged.is_empty()
    }

    /// The element holding cell `e`: the merged brick it lies in, else itself.
    pub fn owner(&self, e: usize) -> usize {
        if self.covered.is_empty() {
            return e;
        }
        self.covered.get(&e).copied().unwrap_or(e)
    }

    /// Merged bricks: (element, per axis the lattice indices of its first, middle and last node
    /// layer), by element.
    pub fn merged_bricks(&self) -> Vec<(usize, [[usize; 3]; 3])> {
        let mut v: Vec<_> = self.merged.iter().map(|(&e, &b)| (e, b)).collect();
        v.sort_unstable_by_key(|&(e, _)| e);
        v
    }

    /// Lattice coordinate before the map: even index = a line, odd = the midpoint of two, um.
    pub fn lattice_position_um(&self, node: usize) -> [f64; 3] {
        let ijk = self.node_ijk(node);
        let at = |lines: &[f64], l: usize| {
            if l.is_multiple_of(2) {
                lines[l / 2]
            } else {
                0.5 * (lines[l / 2] + lines[l / 2 + 1])
            }
        };
        [
            at(&self.xs_um, ijk[0]),
            at(&self.ys_um, ijk[1]),
            at(&self.zs_um, ijk[2]),
        ]
    }

    /// Node position after the map, um.
    pub fn node_position_um(&self, node: usize) -> [f64; 3] {
        let p = self.lattice_position_um(node);
        match &self.map {
            Some(m) => m(p),
            None => p,
        }
    }

    /// Lattice nodes of element `e` in [`hex27`] local order.
    pub fn element_nodes(&self, e: usize) -> [usize; hex27::NODES] {
        // (An empty map is checked first: this runs for every element of every assembly.)
        if let Some(b) = (!self.merged.is_empty())
            .then(|| self.merged.get(&e))
            .flatten()
        {
            return std::array::from_fn(|n| {
                self.node([b[0][n % 3], b[1][(n / 3) % 3], b[2][n / 9]])
            });
        }
        let [i, j, k] = self.element_ijk(e);
        std::array::from_fn(|n| self.node([2 * i + n % 3, 2 * j + (n / 3) % 3, 2 * k + n / 9]))
    }

    /// Elements having lattice node `n` among their nodes (void ones included): at most 8.
    pub fn node_elements(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
        let merged = !self.merged.is_empty();
        let mut seen = [usize::MAX; 8];
        let mut count = 0;
        self.lattice_cells(n)
            .filter(move |&c| {
                if !merged {
                    return true;
                }
                let e = self.owner(c);
                if seen[..count].contains(&e) || !self.element_nodes(e).contains(&n) {
                    return false;
                }
                seen[count] = e;
                count += 1;
                true
            })
            .map(move |c| self.owner(c))
    }

    /// Cells whose closure holds lattice node `n`: at most 8.
    fn lattice_cells(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
        let ijk = self.node_ijk(n);
        let ne = self.n_elements();
        let range = |d: usize| {
            let l = ijk[d];
            if l % 2 == 1 {
                l / 2..l / 2 + 1
            } else {
                (l / 2).saturating_sub(1)..(l / 2 + 1).min(ne[d])
            }
        };
        let (ri, rj, rk) = (range(0), range(1), range(2));
        rk.flat_map(move |k| {
            let ri = ri.clone();
            rj.clone()
                .flat_map(move |j| ri.clone().map(move |i| i + ne[0] * (j + ne[1] * k)))
        })
    }

    /// Active elements whose centre (before the map) lies in the box, for stress queries.
    pub fn elements_in_box(&self, min_um: [f64; 3], max_um: [f64; 3]) -> Vec<usize> {
        (0..self.material.len())
            .filter(|&e| self.material[e].is_some())
            .filter(|&e| {
                let c = self.element_centre_um(e);
                (0..3).all(|d| c[d] >= min_um[d] && c[d] <= max_um[d])
            })
            .collect()
    }

    /// Element containing the point before the map, and the local coordinates there (clamped to
    /// the grid's outer boundary only within round-off); None outside the grid.
    pub fn locate_unmapped(&self, p_um: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        let mut ijk = [0; 3];
        let mut xi = [0.0; 3];
        for (d, lines) in self.lines_um().iter().enumerate() {
            let (lo, hi) = (lines[0], lines[lines.len() - 1]);
            let tol = 1e-9 * (hi - lo);
            if !(p_um[d] >= lo - tol && p_um[d] <= hi + tol) {
                return None;
            }
            let i = lines
                .partition_point(|&v| v <= p_um[d])
                .saturating_sub(1)
                .min(lines.len() - 2);
            ijk[d] = i;
            xi[d] = (2.0 * (p_um[d] - lines[i]) / (lines[i + 1] - lines[i]) - 1.0).clamp(-1.0, 1.0);
        }
        Some((ijk, xi))
    }

    /// Largest extent of the grid before the map, um (the scale of position tolerances).
    pub fn extent_um(&self) -> f64 {
        self.lines_um()
            .iter()
            .map(|l| l[l.len() - 1] - l[0])
            .fold(0.0, f64::max)
    }
}

/// Mapped node positions of the whole lattice (um), checked finite.
pub(crate) fn node_positions_um(grid: &HexGrid) -> FeResult<Vec<[f64; 3]>> {
    let pos: Vec<[f64; 3]> = (0..grid.node_count())
        .map(|n| grid.node_position_um(n))
        .collect();
    if let Some(n) = pos.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        return Err(FeError::SolidInput {
            detail: format!(
                "the node map sends lattice node {:?} (at {:?} um) to {:?}",
                grid.node_ijk(n),
                grid.lattice_position_um(n),
                pos[n]
            ),
            hint: "the node map must return finite positions for every node in the grid",
        });
    }
    Ok(pos)
}

/// Checks every active element's Jacobian at its Gauss points: a scaled determinant under
/// [`MIN_SCALED_JACOBIAN`] (flat, inverted or folded element) is an error naming the element.
pub(crate) fn check_elements(grid: &HexGrid, pos_um: &[[f64; 3]]) -> FeResult<()> {
    use rayon::prelude::*;
    let bad = (0..grid.element_count())
        .into_par_iter()
        .filter(|&e| grid.material(e).is_some())
        .filter_map(|e| {
            let x = grid.element_nodes(e).map(|n| pos_um[n]);
            let s = hex27::min_scaled_jacobian(&x);
            (s.is_nan() || s < MIN_SCALED_JACOBIAN).then_some((e, s))
        })
        .min_by_key(|&(e, _)| e);
    match bad {
        None => Ok(()),
        Some((e, s)) => {
            let [i, j, k] = grid.element_ijk(e);
            Err(FeError::DegenerateElement {
                i,
                j,
                k,
                detail: format!("scaled Jacobian {s:.3e} at a Gauss point"),
                hint: "the node map folds or flattens this element: keep mapped lines from \
                       crossing, or use more elements where the geometry bends",
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_and_incidence() {
        let g = HexGrid::new(&[0.0, 1.0, 3.0], &[0.0, 2.0], &[0.0, 1.0, 2.0, 4.0]).unwrap();
        assert_eq!(g.lattice(), [5, 3, 7]);
        assert_eq!(g.lattice_position_um(g.node([3, 1, 5])), [2.0, 1.0, 3.0]);
        // A corner node inside the grid belongs to 2 x 1 x 2 elements here.
        let n = g.node([2, 0, 2]);
        let els: Vec<usize> = g.node_elements(n).collect();
        assert_eq!(els.len(), 4);
        for e in els {
            assert!(g.element_nodes(e).contains(&n));
        }
        // Every element's nodes list it back.
        for e in 0..g.element_count() {
            for n in g.element_nodes(e) {
                assert!(g.node_elements(n).any(|x| x == e));
            }
        }
        let (ijk, xi) = g.locate_unmapped([2.0, 0.5, 3.0]).unwrap();
        assert_eq!(ijk, [1, 0, 2]);
        assert!((xi[0]).abs() < 1e-15 && (xi[1] + 0.5).abs() < 1e-15 && xi[2].abs() < 1e-15);
        assert!(g.locate_unmapped([3.5, 0.5, 3.0]).is_none());
    }

    #[test]
    fn bad_lines_are_errors() {
        assert!(HexGrid::new(&[0.0], &[0.0, 1.0], &[0.0, 1.0]).is_err());
        assert!(HexGrid::new(&[0.0, f64::NAN], &[0.0, 1.0], &[0.0, 1.0]).is_err());
        assert!(HexGrid::new(&[0.0, 1.0, 1.0], &[0.0, 1.0], &[0.0, 1.0]).is_err());
        let big = uniform_lines(0.0, 1.0, 2000);
        let e = HexGrid::new(&big, &big, &big).unwrap_err();
        assert!(matches!(e, FeError::TooLarge { .. }), "{e}");
    }

    #[test]
    fn folded_map_is_an_error() {
        let l = uniform_lines(0.0, 10.0, 2);
        // x -> x + 8 sin(pi x / 5) folds the first element over itself.
        let g = HexGrid::new(&l, &l, &l)
            .unwrap()
            .with_map(Arc::new(|p: [f64; 3]| {
                [
                    p[0] + 8.0 * (std::f64::consts::PI * p[0] / 5.0).sin(),
                    p[1],
                    p[2],
                ]
            }));
        let pos = node_positions_um(&g).unwrap();
        let e = check_elements(&g, &pos).unwrap_err();
        assert!(matches!(e, FeError::DegenerateElement { .. }), "{e}");
        let nan = HexGrid::new(&l, &l, &l)
            .unwrap()
            .with_map(Arc::new(|p: [f64; 3]| [p[0] / (p[1] - 5.0), p[1], p[2]]));
        assert!(node_positions_um(&nan).is_err());
    }
}
