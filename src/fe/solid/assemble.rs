//! Element stiffness matrices (shared between identical unmapped elements) and the assembly of
//! the free-free stiffness into a lower-triangle CSC pattern built once per grid and constraint
//! set.

use std::collections::HashMap;
use std::sync::Arc;

use faer::sparse::SymbolicSparseColMat;
use rayon::prelude::*;

use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::dofs::SolidDofs;
use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::hex27::{self, DOFS, NODES};
use crate::fe::solid::shear_tying::TransverseShear;

/// Marker of a void element in [`ElementMatrices::kind`].
pub const VOID: u32 = u32::MAX;

/// The 81 x 81 stiffness (row-major, N/m) of every active element, shared by kind.
#[derive(Debug, Clone)]
pub struct ElementMatrices {
    /// Index into `matrices` of every element, or [`VOID`].
    pub kind: Vec<u32>,
    pub matrices: Vec<Arc<Vec<f64>>>,
}

/// True if no node of element `e` is moved by the node map (its geometry is the lattice box).
fn is_box(grid: &HexGrid, pos_um: &[[f64; 3]], e: usize) -> bool {
    let tol = 1e-12 * grid.extent_um();
    grid.element_nodes(e).iter().all(|&n| {
        let p = grid.lattice_position_um(n);
        (0..3).all(|d| (pos_um[n][d] - p[d]).abs() <= tol)
    })
}

/// Element node positions in m.
pub(crate) fn element_nodes_m(grid: &HexGrid, pos_um: &[[f64; 3]], e: usize) -> [[f64; 3]; NODES] {
    grid.element_nodes(e).map(|n| pos_um[n].map(|v| v * 1e-6))
}

/// Errors if a material is not positive definite or an element names a material not given.
pub(crate) fn check_materials(grid: &HexGrid, materials: &[Elasticity]) -> FeResult<()> {
    if let Some(m) = materials.iter().position(|m| !m.is_positive_definite()) {
        return Err(FeError::SolidInput {
            detail: format!("material {m} is not positive definite"),
            hint: "check the elastic constants (E > 0, -1 < nu < 0.5; C11 > |C12|, C44 > 0)",
        });
    }
    let bad = (0..grid.element_count()).find(|&e| {
        grid.material(e)
            .is_some_and(|m| usize::from(m) >= materials.len())
    });
    if let Some(e) = bad {
        return Err(FeError::SolidInput {
            detail: format!(
                "element {:?} has material {}, only {} given",
                grid.element_ijk(e),
                grid.material(e).unwrap_or(0),
                materials.len()
            ),
            hint: "give one Elasticity per material index used in the grid",
        });
    }
    Ok(())
}

impl ElementMatrices {
    /// Computes every active element's stiffness: box elements of equal size and material share
    /// one matrix; mapped elements get their own. Errors if an element names a missing material
    /// or a material is not positive definite.
    pub fn new(
        grid: &HexGrid,
        pos_um: &[[f64; 3]],
        materials: &[Elasticity],
        shear: TransverseShear,
    ) -> FeResult<Self> {
        check_materials(grid, materials)?;
        // (representative element, material) of every distinct matrix.
        let mut jobs: Vec<(usize, u16)> = Vec::new();
        let mut cache: HashMap<([u64; 3], u16), u32> = HashMap::new();
        let mut kind = vec![VOID; grid.element_count()];
        for (e, k) in kind.iter_mut().enumerate() {
            let Some(m) = grid.material(e) else { continue };
            *k = if is_box(grid, pos_um, e) {
                let key = (grid.element_size_um(e).map(f64::to_bits), m);
                *cache.entry(key).or_insert_with(|| {
                    jobs.push((e, m));
                    (jobs.len() - 1) as u32
                })
            } else {
                jobs.push((e, m));
                (jobs.len() - 1) as u32
            };
        }
        let matrices = jobs
            .par_iter()
            .map(|&(e, m)| {
                Arc::new(hex27::stiffness(
                    &element_nodes_m(grid, pos_um, e),
                    &materials[usize::from(m)],
                    shear,
                ))
            })
            .collect();
        Ok(ElementMatrices { kind, matrices })
    }

    /// Number of distinct matrices computed.
    pub fn distinct(&self) -> usize {
        self.matrices.len()
    }

    /// The part of K x (global dofs, 3 per lattice node) from the given elements. `pos_um` are
    /// the node positions.
    ///
    /// K_e annihilates rigid motions, so each element's rigid part (mean translation plus the
    /// rotation W = (grad u - grad u^T)/2 at its centre) is subtracted first: the product then
    /// carries round-off of the deformation, not of the much larger displacement of a bent
    /// structure (the reactions of a slender cantilever balance to 1e-12 instead of 1e-9).
    pub fn apply_on(
        &self,
        grid: &HexGrid,
        pos_um: &[[f64; 3]],
        x: &[f64],
        elements: impl IntoIterator<Item = usize>,
    ) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for e in elements {
            if self.kind[e] == VOID {
                continue;
            }
            let k = &self.matrices[self.kind[e] as usize];
            let nodes = grid.element_nodes(e);
            let xn = element_nodes_m(grid, pos_um, e);
            let mut mean = [0.0; 3];
            let mut centre = [0.0; 3];
            for (&n, p) in nodes.iter().zip(&xn) {
                for d in 0..3 {
                    mean[d] += x[3 * n + d] / NODES as f64;
                    centre[d] += p[d] / NODES as f64;
                }
            }
            let g = hex27::geometry(&xn, [0.0; 3]);
            let mut grad = [[0.0; 3]; 3];
            for (n, dn) in nodes.iter().zip(&g.dn_dx) {
                for i in 0..3 {
                    for j in 0..3 {
                        grad[i][j] += x[3 * n + i] * dn[j];
                    }
                }
            }
            let w: [[f64; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (grad[i][j] - grad[j][i])));
            let xe: [f64; DOFS] = std::array::from_fn(|i| {
                let (a, d) = (i / 3, i % 3);
                let rot: f64 = (0..3).map(|j| w[d][j] * (xn[a][j] - centre[j])).sum();
                x[3 * nodes[a] + d] - mean[d] - rot
            });
            for i in 0..DOFS {
                let row = &k[i * DOFS..(i + 1) * DOFS];
                y[3 * nodes[i / 3] + i % 3] += row.iter().zip(&xe).map(|(a, b)| a * b).sum::<f64>();
            }
        }
        y
    }
}

/// Lower-triangle CSC pattern of the free-free stiffness: column = free dof, rows = the free dofs
/// of every node sharing an active element with it.
#[derive(Debug, Clone)]
pub struct SolidPattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// Nodes with at least one free dof, in order; their columns are consecutive.
    free_nodes: Vec<usize>,
    /// Elements each master reaches through its hanging nodes.
    through_hanging: HashMap<usize, Vec<usize>>,
}

/// Sorted nodes with dofs sharing an active element with `n` (itself included); a hanging node
/// stands for its masters, and `extra` lists the elements a master reaches through the nodes
/// hanging on it.
fn neighbours(
    grid: &HexGrid,
    dofs: &SolidDofs,
    extra: &HashMap<usize, Vec<usize>>,
    n: usize,
    out: &mut Vec<usize>,
) {
    out.clear();
    let through = extra.get(&n).map_or(&[][..], Vec::as_slice);
    for e in grid.node_elements(n).chain(through.iter().copied()) {
        if grid.material(e).is_some() {
            for m in grid.element_nodes(e) {
                match dofs.hanging.masters(m) {
                    Some(ms) => out.extend(ms.iter().map(|&(a, _)| a)),
                    None => out.push(m),
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
}

/// Active elements holding a node that hangs on `master`, by master (empty without hanging
/// nodes).
fn elements_through_hanging(grid: &HexGrid, dofs: &SolidDofs) -> HashMap<usize, Vec<usize>> {
    let mut out: HashMap<usize, Vec<usize>> = HashMap::new();
    for (h, masters) in &dofs.hanging.nodes {
        for e in grid.node_elements(*h) {
            if grid.material(e).is_none() {
                continue;
            }
            for &(m, _) in masters {
                out.entry(m).or_default().push(e);
            }
        }
    }
    for v in out.values_mut() {
        v.sort_unstable();
        v.dedup();
    }
    out
}

/// The element's local nodes that act on node `n`, with their weights: the node itself (1) and
/// the nodes hanging on it.
fn local_weights(dofs: &SolidDofs, nodes: &[usize; NODES], n: usize) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for (l, &m) in nodes.iter().enumerate() {
        if m == n {
            out.push((l, 1.0));
        } else if let Some(ms) = dofs.hanging.masters(m) {
            out.extend(ms.iter().filter(|&&(a, _)| a == n).map(|&(_, w)| (l, w)));
        }
    }
    out
}

/// An element matrix (81 x 81, row-major) reduced to the free dofs it acts on through its nodes
/// and their masters, T^T K T: the free indices (ascending) and the reduced matrix (row-major).
pub(crate) fn reduced_element(
    dofs: &SolidDofs,
    nodes: &[usize; NODES],
    k: &[f64],
) -> (Vec<usize>, Vec<f64>) {
    let nf = dofs.n_free();
    // (local dof, free index, weight) of every term of T.
    let mut terms = Vec::with_capacity(DOFS);
    for (l, &n) in nodes.iter().enumerate() {
        let one = [(n, 1.0)];
        let ms = dofs.hanging.masters(n).unwrap_or(&one);
        for &(m, w) in ms {
            for d in 0..3 {
                let r = dofs.free_index[3 * m + d];
                if r < nf {
                    terms.push((3 * l + d, r, w));
                }
            }
        }
    }
    let mut free: Vec<usize> = terms.iter().map(|t| t.1).collect();
    free.sort_unstable();
    free.dedup();
    let nr = free.len();
    // K T (81 x nr), then T^T (K T).
    let mut kt = vec![0.0; DOFS * nr];
    for &(q, c, w) in &terms {
        let col = free.binary_search(&c).unwrap_or(0);
        for p in 0..DOFS {
            kt[p * nr + col] += k[p * DOFS + q] * w;
        }
    }
    let mut out = vec![0.0; nr * nr];
    for &(p, r, w) in &terms {
        let row = free.binary_search(&r).unwrap_or(0);
        for col in 0..nr {
            out[row * nr + col] += w * kt[p * nr + col];
        }
    }
    (free, out)
}

fn first_free(dofs: &SolidDofs, n: usize) -> Option<usize> {
    let nf = dofs.free_dofs.len();
    (0..3).map(|d| dofs.free_index[3 * n + d]).find(|&f| f < nf)
}

impl SolidPattern {
    /// Build once per grid and constraint set. Errors (before allocating) if the lower triangle
    /// would exceed `usize` or the memory bound.
    pub fn new(grid: &HexGrid, dofs: &SolidDofs) -> FeResult<Self> {
        let nf = dofs.free_dofs.len();
        let free_nodes: Vec<usize> = (0..grid.node_count())
            .filter(|&n| first_free(dofs, n).is_some())
            .collect();
        let through_hanging = elements_through_hanging(grid, dofs);
        // Rows per node's columns, in parallel; concatenated in column order.
        let per_node: Vec<(Vec<usize>, [usize; 3])> = free_nodes
            .par_iter()
            .map_init(Vec::new, |nb, &n| {
                neighbours(grid, dofs, &through_hanging, n, nb);
                let mut rows = Vec::new();
                let mut len = [0; 3];
                for (d, l) in len.iter_mut().enumerate() {
                    let c = dofs.free_index[3 * n + d];
                    if c >= nf {
                        continue;
                    }
                    let before = rows.len();
                    for &m in nb.iter() {
                        for dd in 0..3 {
                            let r = dofs.free_index[3 * m + dd];
                            if r < nf && r >= c {
                                rows.push(r);
                            }
                        }
                    }
                    *l = rows.len() - before;
                }
                (rows, len)
            })
            .collect();
        let nnz: usize = per_node.iter().map(|(r, _)| r.len()).sum();
        let mut col_ptr = Vec::with_capacity(nf + 1);
        let mut row_idx = Vec::new();
        row_idx
            .try_reserve_exact(nnz)
            .map_err(|_| FeError::TooLarge {
                detail: format!("{nnz} stiffness entries"),
                limit: nnz,
                hint: "out of memory for the stiffness matrix: use a coarser grid",
            })?;
        col_ptr.push(0);
        for (n, (rows, len)) in free_nodes.iter().zip(per_node) {
            let mut at = 0;
            for (d, &l) in len.iter().enumerate() {
                if dofs.free_index[3 * n + d] < nf {
                    row_idx.extend_from_slice(&rows[at..at + l]);
                    at += l;
                    col_ptr.push(row_idx.len());
                }
            }
        }
        Ok(SolidPattern {
            symbolic: SymbolicSparseColMat::new_checked(nf, nf, col_ptr, None, row_idx),
            free_nodes,
            through_hanging,
        })
    }

    /// Entries of the lower triangle.
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// Assembled lower-triangle values (CSC order), column by column in parallel: each node's
    /// columns gather K_e(a, b) from the (at most 8) elements around it, so no two threads write
    /// the same entry.
    pub fn values(&self, grid: &HexGrid, dofs: &SolidDofs, k: &ElementMatrices) -> Vec<f64> {
        let nf = dofs.free_dofs.len();
        let col_ptr = self.symbolic.col_ptr();
        let row_idx = self.symbolic.row_idx();
        let mut vals = vec![0.0; row_idx.len()];
        // Split the values into each free node's column block.
        let mut chunks: Vec<(usize, usize, &mut [f64])> = Vec::with_capacity(self.free_nodes.len());
        let mut rest: &mut [f64] = &mut vals;
        let mut done = 0;
        for &n in &self.free_nodes {
            let c0 = first_free(dofs, n).unwrap_or(0);
            let ncols = (0..3).filter(|&d| dofs.free_index[3 * n + d] < nf).count();
            let end = col_ptr[c0 + ncols];
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(end - done);
            chunks.push((n, c0, head));
            rest = tail;
            done = end;
        }
        if !dofs.hanging.is_empty() {
            chunks.par_iter_mut().for_each(|(n, c0, block)| {
                self.gather_hanging(grid, dofs, k, *n, col_ptr[*c0], block);
            });
            return vals;
        }
        chunks.par_iter_mut().for_each(|(n, c0, block)| {
            let base = col_ptr[*c0];
            for e in grid.node_elements(*n) {
                if k.kind[e] == crate::fe::solid::assemble::VOID {
                    continue;
                }
                let ke = &k.matrices[k.kind[e] as usize];
                let nodes = grid.element_nodes(e);
                let lb = nodes.iter().position(|&m| m == *n).unwrap_or(0);
                for j in 0..3 {
                    let c = dofs.free_index[3 * *n + j];
                    if c >= nf {
                        continue;
                    }
                    let (s, t) = (col_ptr[c], col_ptr[c + 1]);
                    let rows = &row_idx[s..t];
                    for (la, &a) in nodes.iter().enumerate() {
                        for i in 0..3 {
                            let r = dofs.free_index[3 * a + i];
                            if r >= nf || r < c {
                                continue;
                            }
                            if let Ok(p) = rows.binary_search(&r) {
                                block[s - base + p] += ke[(3 * la + i) * DOFS + 3 * lb + j];
                            }
                        }
                    }
                }
            }
        });
        vals
    }

    /// One free node's columns with hanging nodes about: every element acting on the node,
    /// directly or through a node hanging on it, adds w_a w_b K_e(a, b) for each pair of its
    /// local nodes acting on a row node and on this one.
    fn gather_hanging(
        &self,
        grid: &HexGrid,
        dofs: &SolidDofs,
        k: &ElementMatrices,
        n: usize,
        base: usize,
        block: &mut [f64],
    ) {
        let nf = dofs.n_free();
        let col_ptr = self.symbolic.col_ptr();
        let row_idx = self.symbolic.row_idx();
        let through = self.through_hanging.get(&n).map_or(&[][..], Vec::as_slice);
        let mut elements: Vec<usize> = grid
            .node_elements(n)
            .chain(through.iter().copied())
            .collect();
        elements.sort_unstable();
        elements.dedup();
        for e in elements {
            if k.kind[e] == VOID {
                continue;
            }
            let ke = &k.matrices[k.kind[e] as usize];
            let nodes = grid.element_nodes(e);
            for (lb, wb) in local_weights(dofs, &nodes, n) {
                for j in 0..3 {
                    let c = dofs.free_index[3 * n + j];
                    if c >= nf {
                        continue;
                    }
                    let (s, t) = (col_ptr[c], col_ptr[c + 1]);
                    let rows = &row_idx[s..t];
                    for (la, &m) in nodes.iter().enumerate() {
                        let one = [(m, 1.0)];
                        for &(a, wa) in dofs.hanging.masters(m).unwrap_or(&one) {
                            for i in 0..3 {
                                let r = dofs.free_index[3 * a + i];
                                if r >= nf || r < c {
                                    continue;
                                }
                                if let Ok(p) = rows.binary_search(&r) {
                                    block[s - base + p] +=
                                        wa * wb * ke[(3 * la + i) * DOFS + 3 * lb + j];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}
