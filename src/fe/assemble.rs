//! Element stiffness matrices and assembly of the free-free stiffness into a CSC pattern.

use crate::fe::bfs;
use crate::fe::dofs::{element_dofs, DofMap, CONSTRAINED};
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::PlateProblem;
use faer::sparse::SymbolicSparseColMat;
use std::collections::HashMap;

/// Element stiffness matrices shared by elements of equal size and thickness.
#[derive(Debug, Clone)]
pub struct ElementStiffness {
    /// Index into `matrices` of every element.
    pub kind: Vec<u32>,
    pub matrices: Vec<Box<[[f64; 16]; 16]>>,
}

impl ElementStiffness {
    /// Compute (with sharing) the BFS stiffness of every element for the problem's thickness and
    /// material.
    pub fn new(problem: &PlateProblem, thickness_um: &[f64]) -> FeResult<Self> {
        let mesh = &problem.mesh;
        if !problem.material.is_positive_definite() {
            return Err(FeError::InvalidStiffness {
                element: 0,
                hint: "material Q must be positive definite (Q11 Q22 > Q12^2, Q66 > 0)",
            });
        }
        let mut cache: HashMap<[u64; 3], u32> = HashMap::new();
        let mut matrices = Vec::new();
        let mut kind = Vec::with_capacity(mesh.n_elements());
        for (e, &t) in thickness_um.iter().enumerate() {
            if !(t > 0.0 && t.is_finite()) {
                return Err(FeError::InvalidStiffness {
                    element: e,
                    hint: "every thickness (base and regions) must be positive",
                });
            }
            let (x0, y0, x1, y1) = mesh.element_bounds_um(e);
            let (a, b) = ((x1 - x0) * 1e-6, (y1 - y0) * 1e-6);
            let key = [a.to_bits(), b.to_bits(), t.to_bits()];
            let id = *cache.entry(key).or_insert_with(|| {
                let d = problem.bending_stiffness(t * 1e-6);
                matrices.push(Box::new(bfs::stiffness(a, b, &d)));
                (matrices.len() - 1) as u32
            });
            kind.push(id);
        }
        Ok(ElementStiffness { kind, matrices })
    }

    /// y = K x over all global dofs (element by element).
    pub fn apply(&self, mesh: &RectMesh, x: &[f64]) -> Vec<f64> {
        self.apply_on(mesh, x, 0..mesh.n_elements())
    }

    /// The part of K x from the given elements: exact at every dof those elements cover alone
    /// (the constrained dofs, when `elements` are all elements touching them).
    pub fn apply_on(
        &self,
        mesh: &RectMesh,
        x: &[f64],
        elements: impl IntoIterator<Item = usize>,
    ) -> Vec<f64> {
        self.product(mesh, x, elements, false)
    }

    /// [`Self::apply_on`] with each element's w taken less its mean corner deflection: the
    /// same product in exact arithmetic (K annihilates a rigid translation), without the
    /// round-off of |K| w_mean that on fine meshes adds up to a phantom vertical force (the
    /// large-deflection plate's internal force does the same, `fe::vonkarman`).
    pub fn apply_on_mean_free(
        &self,
        mesh: &RectMesh,
        x: &[f64],
        elements: impl IntoIterator<Item = usize>,
    ) -> Vec<f64> {
        self.product(mesh, x, elements, true)
    }

    fn product(
        &self,
        mesh: &RectMesh,
        x: &[f64],
        elements: impl IntoIterator<Item = usize>,
        mean_free: bool,
    ) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for e in elements {
            let k = &self.matrices[self.kind[e] as usize];
            let dofs = element_dofs(mesh, e);
            let mut xe: [f64; 16] = std::array::from_fn(|j| x[dofs[j]]);
            if mean_free {
                let wbar = 0.25 * (xe[0] + xe[4] + xe[8] + xe[12]);
                for c in 0..4 {
                    xe[4 * c] -= wbar;
                }
            }
            for i in 0..16 {
                let s: f64 = (0..16).map(|j| k[i][j] * xe[j]).sum();
                y[dofs[i]] += s;
            }
        }
        y
    }
}

/// Sparsity pattern (CSC, lower triangle) of the free-free stiffness, built directly from the 3x3
/// node stencil of the rectilinear mesh (no sorting of element triplets), for `m` dofs per node
/// (4 for the bending plate, 6 for the von Karman plate).
#[derive(Debug, Clone)]
pub struct Pattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// Dofs per node.
    m: usize,
    /// Position in the values of entry (row, col) for every free column, by the row's stencil
    /// neighbour k (0..9) and node dof d (0..m): `slot[9 m col + m k + d]`, or [`NO_SLOT`] above
    /// the diagonal or on a constrained row. Assembly is then indexing, not searching.
    slot: Vec<u32>,
}

const NO_SLOT: u32 = u32::MAX;

/// Stencil neighbour index (dy + 1) 3 + (dx + 1) of element corner `r` seen from corner `c`.
pub(crate) const NEIGHBOUR: [[usize; 4]; 4] = {
    let mut t = [[0; 4]; 4];
    let mut r = 0;
    while r < 4 {
        let mut c = 0;
        while c < 4 {
            let (rx, ry) = bfs::CORNERS[r];
            let (cx, cy) = bfs::CORNERS[c];
            t[r][c] = (ry + 1 - cy) * 3 + (rx + 1 - cx);
            c += 1;
        }
        r += 1;
    }
    t
};

impl Pattern {
    /// Build once per mesh and constraint set (4 dofs per node).
    pub fn new(mesh: &RectMesh, dofs: &DofMap) -> FeResult<Self> {
        Self::with_node_dofs(mesh, &dofs.free_index, &dofs.free_dofs, 4)
    }

    /// The pattern for `m` dofs per node: `free_index[m node + d]` is the free index of a global
    /// dof or [`CONSTRAINED`], `free_dofs` the global dof of every free index. Panics if the
    /// lengths do not match the mesh (misuse).
    #[track_caller]
    pub fn with_node_dofs(
        mesh: &RectMesh,
        free_index: &[usize],
        free_dofs: &[usize],
        m: usize,
    ) -> FeResult<Self> {
        let (nxl, nyl) = (mesh.x_um.len(), mesh.y_um.len());
        assert_eq!(free_index.len(), m * nxl * nyl, "m dofs per node");
        let n = free_dofs.len();
        // Positions are u32: at most 9 m entries per column.
        if n >= (u32::MAX as usize) / (9 * m) {
            return Err(FeError::Sparse {
                detail: format!("{n} free dofs"),
                hint: "too many dofs for one plate: use a coarser mesh",
            });
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(n * 5 * m);
        let mut slot = vec![NO_SLOT; 9 * m * n];
        col_ptr.push(0);
        for (c, &g) in free_dofs.iter().enumerate() {
            let node = g / m;
            let (i, j) = (node % nxl, node / nxl);
            // All nodes of the 3x3 stencil share an element with this node; rows come out sorted
            // when free indices grow with the global dof.
            for jj in j.saturating_sub(1)..=(j + 1).min(nyl - 1) {
                for ii in i.saturating_sub(1)..=(i + 1).min(nxl - 1) {
                    let nn = jj * nxl + ii;
                    let k = (jj + 1 - j) * 3 + (ii + 1 - i);
                    for d in 0..m {
                        let f = free_index[m * nn + d];
                        if f != CONSTRAINED && f >= c {
                            slot[9 * m * c + m * k + d] = row_idx.len() as u32;
                            row_idx.push(f);
                        }
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Pattern {
            symbolic: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
            m,
            slot,
        })
    }

    /// Adds an element matrix to the values: local dof `i` sits at element corner `corner[i]`,
    /// node dof `node_dof[i]`, free index `free[i]` (or [`CONSTRAINED`]); `ke` is row-major,
    /// `n` x `n`.
    pub fn add_element(
        &self,
        vals: &mut [f64],
        free: &[usize],
        corner: &[usize],
        node_dof: &[usize],
        ke: &[f64],
    ) {
        let n = free.len();
        let m = self.m;
        for j in 0..n {
            let c = free[j];
            if c == CONSTRAINED {
                continue;
            }
            let base = 9 * m * c;
            for i in 0..n {
                let s = self.slot[base + m * NEIGHBOUR[corner[i]][corner[j]] + node_dof[i]];
                if s != NO_SLOT {
                    vals[s as usize] += ke[i * n + j];
                }
            }
        }
    }

    /// Adds a block over the global dofs `dofs` (`m` per node, their nodes neighbours in the
    /// stencil; `ke` row-major, n x n) to the values; constrained rows and columns are skipped.
    #[track_caller]
    pub fn add_dof_block(
        &self,
        vals: &mut [f64],
        mesh: &RectMesh,
        free_index: &[usize],
        dofs: &[usize],
        ke: &[f64],
    ) {
        let (m, nxl, n) = (self.m, mesh.x_um.len(), dofs.len());
        assert_eq!(ke.len(), n * n, "one row per dof");
        for (j, &dj) in dofs.iter().enumerate() {
            let c = free_index[dj];
            if c == CONSTRAINED {
                continue;
            }
            let (ic, jc) = ((dj / m) % nxl, (dj / m) / nxl);
            for (i, &di) in dofs.iter().enumerate() {
                let (ir, jr) = ((di / m) % nxl, (di / m) / nxl);
                assert!(
                    ir.abs_diff(ic) <= 1 && jr.abs_diff(jc) <= 1,
                    "stencil neighbours"
                );
                let k = (jr + 1 - jc) * 3 + (ir + 1 - ic);
                let s = self.slot[9 * m * c + m * k + di % m];
                if s != NO_SLOT {
                    vals[s as usize] += ke[i * n + j];
                }
            }
        }
    }

    /// Adds a block coupling the 4 bending dofs of each of `nodes` (neighbours in the stencil;
    /// `ke` row-major, 4 n x 4 n, node by node) to the values; constrained rows and columns are
    /// skipped.
    #[track_caller]
    pub fn add_node_block(
        &self,
        vals: &mut [f64],
        mesh: &RectMesh,
        free_index: &[usize],
        nodes: &[usize],
        ke: &[f64],
    ) {
        let m = self.m;
        let nxl = mesh.x_um.len();
        let n = 4 * nodes.len();
        assert_eq!(ke.len(), n * n, "4 dofs per node");
        for j in 0..n {
            let c = free_index[m * nodes[j / 4] + j % 4];
            if c == CONSTRAINED {
                continue;
            }
            let (ic, jc) = (nodes[j / 4] % nxl, nodes[j / 4] / nxl);
            for i in 0..n {
                let (ir, jr) = (nodes[i / 4] % nxl, nodes[i / 4] / nxl);
                assert!(
                    ir.abs_diff(ic) <= 1 && jr.abs_diff(jc) <= 1,
                    "stencil neighbours"
                );
                let k = (jr + 1 - jc) * 3 + (ir + 1 - ic);
                let s = self.slot[9 * m * c + m * k + i % 4];
                if s != NO_SLOT {
                    vals[s as usize] += ke[i * n + j];
                }
            }
        }
    }

    /// Assembled lower-triangle values (CSC order) from the element stiffness matrices.
    #[track_caller]
    pub fn values(&self, mesh: &RectMesh, dofs: &DofMap, k: &ElementStiffness) -> Vec<f64> {
        assert_eq!(self.m, 4, "the bending pattern");
        let mut vals = vec![0.0; self.symbolic.row_idx().len()];
        for e in 0..mesh.n_elements() {
            let ed = element_dofs(mesh, e).map(|d| dofs.free_index[d]);
            let ke = &k.matrices[k.kind[e] as usize];
            for j in 0..16 {
                let c = ed[j];
                if c == CONSTRAINED {
                    continue;
                }
                let base = 36 * c;
                for i in 0..16 {
                    let s = self.slot[base + 4 * NEIGHBOUR[i / 4][j / 4] + i % 4];
                    if s != NO_SLOT {
                        vals[s as usize] += ke[i][j];
                    }
                }
            }
        }
        vals
    }
}
