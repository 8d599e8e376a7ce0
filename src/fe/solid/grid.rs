//! Structured hexahedral grid: element boundary lines `xs, ys, zs` (um), the lattice of 27-node
//! element nodes between them, an optional map of every node position (curved or slanted
//! geometry, e.g. a frustum's {111} sidewall) and a material per element (None = void).
//!
//! Element (i, j, k) spans [xs_i, xs_i+1] x [ys_j, ys_j+1] x [zs_k, zs_k+1] before the map. The
//! node lattice has (2 nx + 1)(2 ny + 1)(2 nz + 1) positions: even lattice indices are element
//! boundary lines, odd ones the element mid-lines. Lattice node (I, J, K) has index
//! `I + nxl (J + nyl K)`.

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
        })
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
        self.material[e] = material;
    }

    /// Sets every element's material from its centre (um, before the map).
    pub fn assign(&mut self, f: impl Fn([f64; 3]) -> Option<u16>) {
        for e in 0..self.material.len() {
            let c = self.element_centre_um(e);
            self.material[e] = f(c);
        }
    }

    /// Centre of element `e` before the map, um.
    pub fn element_centre_um(&self, e: usize) -> [f64; 3] {
        let [i, j, k] = self.element_ijk(e);
        [
            0.5 * (self.xs_um[i] + self.xs_um[i + 1]),
            0.5 * (self.ys_um[j] + self.ys_um[j + 1]),
            0.5 * (self.zs_um[k] + self.zs_um[k + 1]),
        ]
    }

    /// Size of element `e` before the map, um.
    pub fn element_size_um(&self, e: usize) -> [f64; 3] {
        let [i, j, k] = self.element_ijk(e);
        [
            self.xs_um[i + 1] - self.xs_um[i],
            self.ys_um[j + 1] - self.ys_um[j],
            self.zs_um[k + 1] - self.zs_um[k],
        ]
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
        let [i, j, k] = self.element_ijk(e);
        std::array::from_fn(|n| self.node([2 * i + n % 3, 2 * j + (n / 3) % 3, 2 * k + n / 9]))
    }

    /// Elements containing lattice node `n` (void ones included): at most 8.
    pub fn node_elements(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
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
