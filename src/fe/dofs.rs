//! Dof numbering (4 per node), constraints from line supports and prescribed values, reaction
//! groups, and the rigid-body-mode check.

use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::{Axis, PlateProblem, SupportKind};

/// Marker of a free dof in [`DofMap::free_index`].
pub const CONSTRAINED: usize = usize::MAX;

/// Numbering of the 4 dofs per node, the constrained dofs with their values and reaction groups.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    pub n_dofs: usize,
    /// Free-dof index of every global dof, or [`CONSTRAINED`].
    pub free_index: Vec<usize>,
    /// Global index of every free dof.
    pub free_dofs: Vec<usize>,
    /// (global dof, prescribed value, group index) of every constrained dof.
    pub constrained: Vec<(usize, f64, usize)>,
    /// Reaction group names in order of first appearance.
    pub groups: Vec<String>,
    /// Free dofs held by edge springs (w and the normal slope of each spring node): they remove
    /// rigid-body modes as constraints would.
    pub elastic: Vec<usize>,
}

/// Global dofs of an element in BFS local order.
pub fn element_dofs(mesh: &RectMesh, e: usize) -> [usize; 16] {
    let nodes = mesh.element_nodes(e);
    std::array::from_fn(|i| 4 * nodes[i / 4] + i % 4)
}

pub(crate) fn find_line(axis: &[f64], at: f64) -> Option<usize> {
    let tol = 1e-9 * (axis.last().unwrap() - axis[0]).abs().max(1.0);
    let k = axis.partition_point(|&v| v < at - tol);
    (k < axis.len() && (axis[k] - at).abs() <= tol).then_some(k)
}

/// A support's or spring's mesh line: line `k` across `along`, the nodes' coordinates along it
/// (`span`), and the part of it that `[from, to]` covers (to a relative 1e-9).
pub(crate) struct MeshLine<'a> {
    along: Axis,
    k: usize,
    pub span: &'a [f64],
    lo: f64,
    hi: f64,
}

impl<'a> MeshLine<'a> {
    /// The line at `at_um` across `along`, or the error that names `group` and `hint`.
    pub fn find(
        mesh: &'a RectMesh,
        along: Axis,
        at_um: f64,
        (from_um, to_um): (f64, f64),
        group: &str,
        hint: &'static str,
    ) -> FeResult<Self> {
        let (line_axis, span) = match along {
            Axis::X => (&mesh.y_um, &mesh.x_um),
            Axis::Y => (&mesh.x_um, &mesh.y_um),
        };
        let k = find_line(line_axis, at_um).ok_or_else(|| FeError::SupportNotOnMeshLine {
            group: group.to_string(),
            at_um,
            hint,
        })?;
        let tol = 1e-9 * (span.last().unwrap() - span[0]);
        Ok(MeshLine {
            along,
            k,
            span,
            lo: from_um.min(to_um) - tol,
            hi: from_um.max(to_um) + tol,
        })
    }

    /// Whether the coordinate `c` along the line lies in the covered part.
    pub fn covers(&self, c: f64) -> bool {
        c >= self.lo && c <= self.hi
    }

    /// The mesh node `m` along the line.
    pub fn node(&self, mesh: &RectMesh, m: usize) -> usize {
        match self.along {
            Axis::X => mesh.node(m, self.k),
            Axis::Y => mesh.node(self.k, m),
        }
    }
}

impl DofMap {
    /// Build the dof map; a dof constrained by several supports belongs to the first one listed.
    pub fn new(problem: &PlateProblem) -> FeResult<Self> {
        let mesh = &problem.mesh;
        let n_dofs = 4 * mesh.n_nodes();
        let mut owner: Vec<Option<(f64, usize)>> = vec![None; n_dofs];
        let mut groups: Vec<String> = Vec::new();
        let group_id = |name: &str, groups: &mut Vec<String>| {
            groups.iter().position(|g| g == name).unwrap_or_else(|| {
                groups.push(name.to_string());
                groups.len() - 1
            })
        };
        for s in &problem.supports {
            let line = MeshLine::find(
                mesh,
                s.along,
                s.at_um,
                (s.from_um, s.to_um),
                &s.group,
                "add the support position to the required mesh lines",
            )?;
            let g = group_id(&s.group, &mut groups);
            let mut any = false;
            for (m, &c) in line.span.iter().enumerate() {
                if !line.covers(c) {
                    continue;
                }
                any = true;
                let node = line.node(mesh, m);
                // Tangential slope dof is fixed with w; clamped also fixes the normal slope and the
                // twist.
                let tangential = match s.along {
                    Axis::X => 1,
                    Axis::Y => 2,
                };
                let normal = 3 - tangential;
                let dofs: &[usize] = match s.kind {
                    SupportKind::SimplySupported => &[0, tangential],
                    SupportKind::Clamped => &[0, 1, 2, 3],
                    SupportKind::Symmetry => &[normal, 3],
                };
                for &d in dofs {
                    owner[4 * node + d].get_or_insert((0.0, g));
                }
            }
            if !any {
                return Err(FeError::EmptySupport {
                    group: s.group.clone(),
                    hint: "check from_um/to_um against the plate size",
                });
            }
        }
        for p in &problem.prescribed {
            let (i, j) = match (find_line(&mesh.x_um, p.x_um), find_line(&mesh.y_um, p.y_um)) {
                (Some(i), Some(j)) => (i, j),
                _ => {
                    return Err(FeError::PrescribedNotAtNode {
                        group: p.group.clone(),
                        x_um: p.x_um,
                        y_um: p.y_um,
                        hint: "prescribe values at mesh nodes (add the coordinates to the \
                               required lines)",
                    })
                }
            };
            let g = group_id(&p.group, &mut groups);
            owner[4 * mesh.node(i, j) + p.dof.offset()] = Some((p.value, g));
        }
        let mut elastic = Vec::new();
        for s in &problem.edge_springs {
            let normal = match s.along {
                Axis::X => 2,
                Axis::Y => 1,
            };
            for seg in crate::fe::edge_spring::segments(mesh, s)? {
                for n in seg.nodes {
                    elastic.extend([4 * n, 4 * n + normal]);
                }
            }
            group_id(&s.group, &mut groups);
        }
        elastic.sort_unstable();
        elastic.dedup();
        let mut free_index = vec![CONSTRAINED; n_dofs];
        let mut free_dofs = Vec::new();
        let mut constrained = Vec::new();
        for (d, o) in owner.iter().enumerate() {
            match o {
                None => {
                    free_index[d] = free_dofs.len();
                    free_dofs.push(d);
                }
                Some((v, g)) => constrained.push((d, *v, *g)),
            }
        }
        Ok(DofMap {
            n_dofs,
            free_index,
            free_dofs,
            constrained,
            groups,
            elastic,
        })
    }

    /// Number of free dofs.
    pub fn n_free(&self) -> usize {
        self.free_dofs.len()
    }

    /// An error naming the rigid-body modes the constraints leave free, if any.
    pub fn check_rigid_modes(&self, mesh: &RectMesh) -> FeResult<()> {
        match self.free_rigid_modes(mesh) {
            0 => Ok(()),
            free_modes => Err(FeError::Underconstrained {
                free_modes,
                hint: "the plate is not fully constrained: check that supports exist and are not \
                       all collinear",
            }),
        }
    }

    /// Number of rigid-body modes (w = 1, w = x, w = y) not removed by the constraints (rank test
    /// of the constrained rows of the rigid-mode matrix by modified Gram-Schmidt).
    pub fn free_rigid_modes(&self, mesh: &RectMesh) -> usize {
        let (x0, y0, x1, y1) = mesh.bounds_um();
        let (xc, yc, l) = (0.5 * (x0 + x1), 0.5 * (y0 + y1), (x1 - x0).max(y1 - y0));
        let nxl = mesh.x_um.len();
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 3];
        let held = self.constrained.iter().map(|c| c.0);
        for d in held.chain(self.elastic.iter().copied()) {
            let node = d / 4;
            let (x, y) = (
                (mesh.x_um[node % nxl] - xc) / l,
                (mesh.y_um[node / nxl] - yc) / l,
            );
            let row = match d % 4 {
                0 => [1.0, x, y],
                1 => [0.0, 1.0, 0.0],
                2 => [0.0, 0.0, 1.0],
                _ => [0.0, 0.0, 0.0],
            };
            for k in 0..3 {
                cols[k].push(row[k]);
            }
        }
        3 - rank(cols)
    }
}

/// Rank of the columns (rigid modes restricted to the constrained dofs) by modified Gram-Schmidt:
/// the modes a constraint set removes.
pub(crate) fn rank(cols: Vec<Vec<f64>>) -> usize {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for mut c in cols {
        for q in &basis {
            let dot: f64 = c.iter().zip(q).map(|(a, b)| a * b).sum();
            c.iter_mut().zip(q).for_each(|(a, b)| *a -= dot * b);
        }
        let norm = c.iter().map(|a| a * a).sum::<f64>().sqrt();
        if norm > 1e-9 {
            basis.push(c.into_iter().map(|a| a / norm).collect());
        }
    }
    basis.len()
}
