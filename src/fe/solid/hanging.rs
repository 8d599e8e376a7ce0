//! Hanging nodes of a locally refined grid: a node of a fine brick that lies on a face or an
//! edge of a merged brick ([`HexGrid::merge`]) without being one of its 27 nodes takes the merged
//! brick's quadratic trace there, u_h = sum_a N_a(xi_h) u_a (the standard constraint of
//! non-conforming refinement, e.g. Bangerth & Kayser-Herold 2009, ACM TOMS 36, sec. 3, for
//! continuous Lagrange elements). The merged brick is a box halved by its middle lines, so its
//! trace on a face is a biquadratic in the fine bricks' own coordinates and the constraint makes
//! the mesh conforming: the fine space contains the coarse one and the patch test stays exact.
//!
//! A hanging node's masters may hang on a larger brick in turn; they are substituted until every
//! master is a node with dofs of its own.

use std::collections::BTreeMap;

use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::hex27;

/// Weights under this are dropped (a face node's shape functions vanish on the other faces).
const WEIGHT_TOL: f64 = 1e-13;

/// Substitution rounds before a chain of hanging nodes is called circular \[choice\]: each round
/// climbs one brick size, and a grid has far fewer sizes than this.
const MAX_CHAIN: usize = 32;

/// The hanging nodes of a grid, each with its masters (nodes that are not hanging) and weights.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Hanging {
    /// (hanging node, [(master node, weight)]), by node; the weights sum to 1.
    pub nodes: Vec<(usize, Vec<(usize, f64)>)>,
}

/// Errors if an active element across a face of merged brick `e` overlaps that face only in
/// part: their shared nodes would not hang and their traces would differ between them.
fn check_nested(grid: &HexGrid, e: usize) -> FeResult<()> {
    let ne = grid.n_elements();
    let b = grid.element_lines(e);
    for d in 0..3 {
        let [p, q] = [(d + 1) % 3, (d + 2) % 3];
        // The cell layer just outside each face along d.
        for outside in [b[d][0].checked_sub(1), Some(b[d][1]).filter(|&i| i < ne[d])]
            .into_iter()
            .flatten()
        {
            for i in b[p][0]..b[p][1] {
                for j in b[q][0]..b[q][1] {
                    let mut ijk = [0; 3];
                    ijk[d] = outside;
                    ijk[p] = i;
                    ijk[q] = j;
                    let n = grid.owner(grid.element(ijk));
                    if grid.material(n).is_none() {
                        continue;
                    }
                    let o = grid.element_lines(n);
                    let nests = |a: usize| {
                        (o[a][0] >= b[a][0] && o[a][1] <= b[a][1])
                            || (o[a][0] <= b[a][0] && o[a][1] >= b[a][1])
                    };
                    if !(nests(p) && nests(q)) {
                        return Err(FeError::SolidInput {
                            detail: format!(
                                "the merged bricks of cells from {:?} and from {:?} share part of \
                                 a face",
                                grid.element_ijk(e),
                                grid.element_ijk(n)
                            ),
                            hint: "merge so that neighbouring bricks nest (each shared face \
                                   within a face of the other), as merging bisected cells back \
                                   into their coarse cell does",
                        });
                    }
                }
            }
        }
    }
    Ok(())
}

impl Hanging {
    /// Finds the hanging nodes among the `active` lattice nodes (those of active elements).
    /// Errors if a hanging node does not lie on its brick's trace after the node map (a map that
    /// bends a merged brick's face) or if the chains do not resolve.
    pub fn find(grid: &HexGrid, pos_um: &[[f64; 3]], active: &[bool]) -> FeResult<Self> {
        let mut raw: BTreeMap<usize, (f64, Vec<(usize, f64)>)> = BTreeMap::new();
        let tol = 1e-7 * grid.extent_um();
        for (e, layers) in grid.merged_bricks() {
            if grid.material(e).is_none() {
                continue;
            }
            check_nested(grid, e)?;
            let nodes = grid.element_nodes(e);
            let size = grid.element_size_um(e);
            let volume = size.iter().product::<f64>();
            let centre = grid.element_centre_um(e);
            let x: [[f64; 3]; hex27::NODES] = nodes.map(|n| pos_um[n]);
            let [bx, by, bz] = layers;
            for k in bz[0]..=bz[2] {
                for j in by[0]..=by[2] {
                    for i in bx[0]..=bx[2] {
                        let on_face = i == bx[0]
                            || i == bx[2]
                            || j == by[0]
                            || j == by[2]
                            || k == bz[0]
                            || k == bz[2];
                        let n = grid.node([i, j, k]);
                        if !on_face || !active[n] || nodes.contains(&n) {
                            continue;
                        }
                        let p = grid.lattice_position_um(n);
                        let xi: [f64; 3] =
                            std::array::from_fn(|d| 2.0 * (p[d] - centre[d]) / size[d]);
                        let shape = hex27::shape(xi);
                        let at = hex27::position(&x, xi);
                        if (0..3).any(|d| (at[d] - pos_um[n][d]).abs() > tol) {
                            return Err(FeError::SolidInput {
                                detail: format!(
                                    "the node at {:?} um hangs on the merged brick of cells \
                                     from {:?}, whose trace puts it at {at:?} um",
                                    pos_um[n],
                                    grid.element_ijk(e)
                                ),
                                hint: "merge only where the node map keeps the brick a box \
                                       (or moves it affinely)",
                            });
                        }
                        let masters: Vec<(usize, f64)> = nodes
                            .iter()
                            .zip(shape)
                            .filter(|(_, w)| w.abs() > WEIGHT_TOL)
                            .map(|(&m, w)| (m, w))
                            .collect();
                        // On an edge shared by two merged bricks the larger one's trace binds
                        // (the smaller brick's edge nodes hang on it too).
                        match raw.get(&n) {
                            Some((v, _)) if *v >= volume => {}
                            _ => {
                                raw.insert(n, (volume, masters));
                            }
                        }
                    }
                }
            }
        }
        let mut nodes: BTreeMap<usize, Vec<(usize, f64)>> =
            raw.into_iter().map(|(n, (_, m))| (n, m)).collect();
        for _ in 0..MAX_CHAIN {
            let mut changed = false;
            let snapshot = nodes.clone();
            for masters in nodes.values_mut() {
                if !masters.iter().any(|(m, _)| snapshot.contains_key(m)) {
                    continue;
                }
                changed = true;
                let mut out: BTreeMap<usize, f64> = BTreeMap::new();
                for &(m, w) in masters.iter() {
                    match snapshot.get(&m) {
                        Some(sub) => {
                            for &(s, ws) in sub {
                                *out.entry(s).or_default() += w * ws;
                            }
                        }
                        None => *out.entry(m).or_default() += w,
                    }
                }
                *masters = out
                    .into_iter()
                    .filter(|(_, w)| w.abs() > WEIGHT_TOL)
                    .collect();
            }
            if !changed {
                return Ok(Hanging {
                    nodes: nodes.into_iter().collect(),
                });
            }
        }
        Err(FeError::SolidInput {
            detail: format!(
                "hanging nodes still depend on hanging nodes after {MAX_CHAIN} substitutions"
            ),
            hint: "merge bricks so that neighbouring sizes nest (no brick hangs on itself)",
        })
    }

    /// True if there is no hanging node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Sets every hanging node's displacement (3 per lattice node) from its masters.
    pub fn fill(&self, u: &mut [f64]) {
        for (h, masters) in &self.nodes {
            for d in 0..3 {
                u[3 * h + d] = masters.iter().map(|&(m, w)| w * u[3 * m + d]).sum();
            }
        }
    }

    /// Moves every hanging node's force (3 per lattice node) to its masters, T^T f: the work of
    /// the constrained field is unchanged, and the hanging entries become zero.
    pub fn reduce(&self, f: &mut [f64]) {
        for (h, masters) in &self.nodes {
            for d in 0..3 {
                let v = std::mem::take(&mut f[3 * h + d]);
                for &(m, w) in masters {
                    f[3 * m + d] += w * v;
                }
            }
        }
    }

    /// Like [`Self::reduce`] for sums of magnitudes (round-off scales): |w| instead of w.
    pub fn reduce_magnitude(&self, f: &mut [f64]) {
        for (h, masters) in &self.nodes {
            for d in 0..3 {
                let v = std::mem::take(&mut f[3 * h + d]);
                for &(m, w) in masters {
                    f[3 * m + d] += w.abs() * v;
                }
            }
        }
    }

    /// Masters of `node` if it hangs.
    pub fn masters(&self, node: usize) -> Option<&[(usize, f64)]> {
        self.nodes
            .binary_search_by_key(&node, |(n, _)| *n)
            .ok()
            .map(|i| self.nodes[i].1.as_slice())
    }
}
