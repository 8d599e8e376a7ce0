//! Dof numbering of the solid (3 per node of an active element), constraints with their values
//! and reaction groups, the size bound and the rigid-body check per connected part.

use crate::fe::dofs::rank;
use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::grid::{HexGrid, MAX_DOFS};
use crate::fe::solid::hanging::Hanging;
use crate::fe::solid::problem::{Constraint, Prescribed};

/// Marker of a constrained dof in [`SolidDofs::free_index`].
pub const CONSTRAINED: usize = usize::MAX;
/// Marker of a dof of a node no active element touches.
pub const INACTIVE: usize = usize::MAX - 1;
/// Marker of a dof of a hanging node (it follows its masters: [`Hanging`]).
pub const HANGING: usize = usize::MAX - 2;

/// Dof numbering: global dof `3 node + d` for every lattice node; free dofs numbered in global
/// order (so a node's free dofs are consecutive).
#[derive(Debug, Clone, PartialEq)]
pub struct SolidDofs {
    /// Free index of every global dof, [`CONSTRAINED`], [`INACTIVE`] or [`HANGING`].
    pub free_index: Vec<usize>,
    /// Global dof of every free index.
    pub free_dofs: Vec<usize>,
    /// (global dof, prescribed value in m, group) of every constrained dof.
    pub constrained: Vec<(usize, f64, usize)>,
    /// Reaction group names in order of first appearance.
    pub groups: Vec<String>,
    /// Whether an active element touches each node.
    pub active: Vec<bool>,
    /// Nodes on a merged brick's faces that follow its trace; they have no dofs of their own
    /// and no constraint selects them (their masters carry it).
    pub hanging: Hanging,
}

/// Whether an active element touches each lattice node; errors if none does or if the model would
/// exceed [`MAX_DOFS`] (call before anything sized by the dofs is built).
pub(crate) fn active_nodes(grid: &HexGrid) -> FeResult<Vec<bool>> {
    let mut active = vec![false; grid.node_count()];
    for e in 0..grid.element_count() {
        if grid.material(e).is_some() {
            for n in grid.element_nodes(e) {
                active[n] = true;
            }
        }
    }
    let n_active = active.iter().filter(|&&a| a).count();
    if n_active == 0 {
        return Err(FeError::SolidInput {
            detail: "every element is void".into(),
            hint: "give some elements a material",
        });
    }
    if 3 * n_active > MAX_DOFS {
        return Err(FeError::TooLarge {
            detail: format!("{} dofs", 3 * n_active),
            limit: MAX_DOFS,
            hint: "use a coarser grid, fewer active elements or a symmetric half/quarter model",
        });
    }
    Ok(active)
}

/// Position tolerance of node selection: 1e-9 of the grid's extent.
pub(crate) fn position_tol_um(grid: &HexGrid) -> f64 {
    1e-9 * grid.extent_um()
}

impl SolidDofs {
    /// Numbers the dofs; errors if the model exceeds [`MAX_DOFS`] (before the tables are
    /// built), if there is no active element, or if a constraint selects no active node.
    pub fn new(grid: &HexGrid, pos_um: &[[f64; 3]], constraints: &[Constraint]) -> FeResult<Self> {
        let active = active_nodes(grid)?;
        let hanging = Hanging::find(grid, pos_um, &active)?;
        let mut hangs = vec![false; active.len()];
        for (h, _) in &hanging.nodes {
            hangs[*h] = true;
        }
        let n_active = active.iter().filter(|&&a| a).count();
        let tol = position_tol_um(grid);
        let mut owner: Vec<Option<(f64, usize)>> = vec![None; 3 * grid.node_count()];
        let mut groups: Vec<String> = Vec::new();
        for c in constraints {
            let g = groups
                .iter()
                .position(|x| *x == c.group)
                .unwrap_or_else(|| {
                    groups.push(c.group.clone());
                    groups.len() - 1
                });
            let mut any = false;
            for (n, p) in pos_um.iter().enumerate() {
                if !active[n] || hangs[n] || !c.nodes.contains(*p, tol) {
                    continue;
                }
                any = true;
                let x_m = p.map(|v| v * 1e-6);
                for d in (0..3).filter(|&d| c.fixed[d]) {
                    let v = match c.value {
                        Prescribed::Zero => 0.0,
                        Prescribed::Linear { u0_m, gradient } => {
                            u0_m[d] + (0..3).map(|j| gradient[d][j] * x_m[j]).sum::<f64>()
                        }
                    };
                    owner[3 * n + d].get_or_insert((v, g));
                }
            }
            if !any || !c.fixed.iter().any(|&f| f) {
                return Err(FeError::SolidInput {
                    detail: format!("constraint '{}' fixes no dof of an active node", c.group),
                    hint: "check the plane or box against the grid (positions after the node \
                           map, um) and that at least one component is fixed",
                });
            }
        }
        let mut free_index = vec![INACTIVE; 3 * grid.node_count()];
        let mut free_dofs = Vec::with_capacity(3 * n_active);
        let mut constrained = Vec::new();
        for (d, o) in owner.iter().enumerate() {
            if !active[d / 3] {
                continue;
            }
            if hangs[d / 3] {
                free_index[d] = HANGING;
                continue;
            }
            match o {
                None => {
                    free_index[d] = free_dofs.len();
                    free_dofs.push(d);
                }
                Some((v, g)) => {
                    free_index[d] = CONSTRAINED;
                    constrained.push((d, *v, *g));
                }
            }
        }
        if free_dofs.is_empty() {
            return Err(FeError::SolidInput {
                detail: "every dof is constrained".into(),
                hint: "nothing to solve: constrain fewer nodes",
            });
        }
        Ok(SolidDofs {
            free_index,
            free_dofs,
            constrained,
            groups,
            active,
            hanging,
        })
    }

    /// Number of free dofs.
    pub fn n_free(&self) -> usize {
        self.free_dofs.len()
    }

    /// Errors if a connected part of the active elements (elements sharing a node are connected)
    /// can move as a rigid body: the 6 rigid modes (3 translations, 3 rotations) restricted to its
    /// constrained dofs must have rank 6. Mechanisms inside a part (two blocks hinged on one node
    /// line) are not detected here; the factorisation reports them as not positive definite.
    pub fn check_rigid_modes(&self, grid: &HexGrid, pos_um: &[[f64; 3]]) -> FeResult<()> {
        let n = grid.node_count();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for e in 0..grid.element_count() {
            if grid.material(e).is_none() {
                continue;
            }
            let nodes = grid.element_nodes(e);
            let r0 = find(&mut parent, nodes[0]);
            for &m in &nodes[1..] {
                let r = find(&mut parent, m);
                if r != r0 {
                    parent[r] = r0;
                }
            }
        }
        for (h, masters) in &self.hanging.nodes {
            for &(m, _) in masters {
                let (a, b) = (find(&mut parent, *h), find(&mut parent, m));
                if a != b {
                    parent[a] = b;
                }
            }
        }
        let scale = grid.extent_um().max(f64::MIN_POSITIVE);
        let mut rows: std::collections::BTreeMap<usize, Vec<[f64; 6]>> = Default::default();
        for n in (0..n).filter(|&n| self.active[n] && self.hanging.masters(n).is_none()) {
            rows.entry(find(&mut parent, n)).or_default();
        }
        for &(d, _, _) in &self.constrained {
            let node = d / 3;
            let [x, y, z] = pos_um[node].map(|v| v / scale);
            let row = match d % 3 {
                0 => [1.0, 0.0, 0.0, 0.0, z, -y],
                1 => [0.0, 1.0, 0.0, -z, 0.0, x],
                _ => [0.0, 0.0, 1.0, y, -x, 0.0],
            };
            rows.entry(find(&mut parent, node)).or_default().push(row);
        }
        for (root, r) in rows {
            let cols: Vec<Vec<f64>> = (0..6)
                .map(|k| r.iter().map(|row| row[k]).collect())
                .collect();
            let free = 6 - rank(cols);
            if free > 0 {
                return Err(FeError::SolidInput {
                    detail: format!(
                        "the connected part containing the node at {:?} um can move as a rigid \
                         body ({free} of 6 rigid modes unconstrained)",
                        pos_um[root]
                    ),
                    hint: "constrain every separate part: clamp a face or add symmetry planes \
                           and a point support",
                });
            }
        }
        Ok(())
    }
}
