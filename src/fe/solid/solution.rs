//! One load case's solid solution: displacements anywhere, stresses at element-local points,
//! reactions at the constrained dofs (its read-outs: [`crate::fe::solid::SolidField`]).

use std::sync::Arc;

use crate::fe::solid::assemble::{element_nodes_m, ElementMatrices};
use crate::fe::solid::dofs::SolidDofs;
use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::grid::HexGrid;
use crate::fe::solid::hex27::{self, DOFS};
use crate::fe::solid::shear_tying::TransverseShear;

/// What a solution needs of the model (shared by all load cases).
#[derive(Debug)]
pub(crate) struct SolidContext {
    pub grid: HexGrid,
    pub pos_um: Vec<[f64; 3]>,
    pub materials: Vec<Elasticity>,
    pub dofs: SolidDofs,
    pub kel: ElementMatrices,
    pub shear: TransverseShear,
}

/// Sum of the reactions of one constraint group, N.
#[derive(Debug, Clone, PartialEq)]
pub struct SolidReaction {
    pub group: String,
    /// Force the constraint exerts on the body, K u - f summed over the group's dofs (the
    /// reactions of all groups sum to minus the applied load).
    pub force_n: [f64; 3],
}

/// The largest principal stress found and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalPeak {
    pub stress_pa: f64,
    /// Element (i, j, k) and local point.
    pub element: [usize; 3],
    pub xi: [f64; 3],
    /// Position of the point (after the node map), um.
    pub position_um: [f64; 3],
}

/// Displacements and reactions of one load case.
#[derive(Debug, Clone)]
pub struct SolidSolution {
    ctx: Arc<SolidContext>,
    u_m: Vec<f64>,
    /// K u - f of every constrained dof, in the order of `ctx.dofs.constrained`.
    constrained_reaction_n: Vec<f64>,
    reactions: Vec<SolidReaction>,
    applied_force_n: [f64; 3],
}

impl SolidSolution {
    pub(crate) fn new(
        ctx: Arc<SolidContext>,
        u_m: Vec<f64>,
        constrained_reaction_n: Vec<f64>,
        applied_force_n: [f64; 3],
    ) -> Self {
        let dofs = &ctx.dofs;
        let mut by_group = vec![[0.0; 3]; dofs.groups.len()];
        for (&(d, _, g), r) in dofs.constrained.iter().zip(&constrained_reaction_n) {
            by_group[g][d % 3] += r;
        }
        let reactions = dofs
            .groups
            .iter()
            .zip(by_group)
            .map(|(g, f)| SolidReaction {
                group: g.clone(),
                force_n: f,
            })
            .collect();
        SolidSolution {
            ctx,
            u_m,
            constrained_reaction_n,
            reactions,
            applied_force_n,
        }
    }

    /// Material `m` of the model.
    pub(crate) fn material(&self, m: usize) -> &Elasticity {
        &self.ctx.materials[m]
    }

    /// How the bricks took their transverse shears.
    pub(crate) fn shear(&self) -> TransverseShear {
        self.ctx.shear
    }

    /// The grid solved.
    pub fn grid(&self) -> &HexGrid {
        &self.ctx.grid
    }

    /// Node positions after the map, um (lattice order).
    pub fn node_positions_um(&self) -> &[[f64; 3]] {
        &self.ctx.pos_um
    }

    /// Displacements of every lattice node (3 per node, m; zero on void nodes).
    pub fn displacements_m(&self) -> &[f64] {
        &self.u_m
    }

    /// Displacement of lattice node `n`, m.
    pub fn node_displacement_m(&self, n: usize) -> [f64; 3] {
        [self.u_m[3 * n], self.u_m[3 * n + 1], self.u_m[3 * n + 2]]
    }

    /// Sum of the applied forces, N.
    pub fn applied_force_n(&self) -> [f64; 3] {
        self.applied_force_n
    }

    /// Reactions summed per constraint group.
    pub fn reactions(&self) -> &[SolidReaction] {
        &self.reactions
    }

    /// Reaction of one group (K u - f, N), if the group exists.
    pub fn reaction_n(&self, group: &str) -> Option<[f64; 3]> {
        self.reactions
            .iter()
            .find(|r| r.group == group)
            .map(|r| r.force_n)
    }

    /// Node position (um) and reaction vector (N, components not constrained are zero) of every
    /// node of a group.
    pub fn nodal_reactions(&self, group: &str) -> Vec<([f64; 3], [f64; 3])> {
        let dofs = &self.ctx.dofs;
        let Some(g) = dofs.groups.iter().position(|x| x == group) else {
            return Vec::new();
        };
        let mut out: Vec<(usize, [f64; 3])> = Vec::new();
        for (&(d, _, gg), r) in dofs.constrained.iter().zip(&self.constrained_reaction_n) {
            if gg != g {
                continue;
            }
            let n = d / 3;
            match out.last_mut() {
                Some((m, f)) if *m == n => f[d % 3] += r,
                _ => {
                    let mut f = [0.0; 3];
                    f[d % 3] = *r;
                    out.push((n, f));
                }
            }
        }
        out.into_iter()
            .map(|(n, f)| (self.ctx.pos_um[n], f))
            .collect()
    }

    fn element_u(&self, e: usize) -> [f64; DOFS] {
        let nodes = self.ctx.grid.element_nodes(e);
        std::array::from_fn(|i| self.u_m[3 * nodes[i / 3] + i % 3])
    }

    /// Displacement (m) at local point `xi` of element (i, j, k); None if the element is void.
    /// Panics outside the grid (misuse).
    #[track_caller]
    pub fn displacement_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        let e = self.ctx.grid.element(element);
        self.ctx.grid.material(e)?;
        let n = hex27::shape(xi);
        let u = self.element_u(e);
        Some(std::array::from_fn(|d| {
            (0..hex27::NODES).map(|k| n[k] * u[3 * k + d]).sum()
        }))
    }

    /// Stress (Voigt xx, yy, zz, yz, xz, xy, Pa) at local point `xi` of element (i, j, k); None if
    /// the element is void. Panics outside the grid (misuse).
    #[track_caller]
    pub fn stress_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        let grid = &self.ctx.grid;
        let e = grid.element(element);
        let m = grid.material(e)?;
        Some(hex27::stress_pa(
            &element_nodes_m(grid, &self.ctx.pos_um, e),
            &self.ctx.materials[usize::from(m)],
            &self.element_u(e),
            xi,
            self.ctx.shear,
        ))
    }

    /// Element and local point containing `p_um` (after the node map): the element found on
    /// the unmapped grid, its neighbours, those within a few cells in plane (a node
    /// map moves points across many fine cells), then every active element whose node box holds
    /// the point, each tried by Newton on x(xi) = p. Failing that, the nearest point of an
    /// active element within the grid's [`HexGrid::tolerance_um`] (a drawn face the builder
    /// moved onto a nearby line). None farther outside the active elements.
    pub fn locate(&self, p_um: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        let grid = &self.ctx.grid;
        let try_element = |e: usize| -> Option<[f64; 3]> {
            grid.material(e)?;
            let x = grid.element_nodes(e).map(|n| self.ctx.pos_um[n]);
            inverse_map(&x, p_um)
        };
        let mut tried = Vec::new();
        if let Some((ijk, _)) = grid.locate_unmapped(p_um) {
            let ne = grid.n_elements();
            // The unmapped element first (a merged brick stands for its cells), before the
            // ring's distances are computed: away from the sidewalls it holds the point.
            let home = grid.owner(grid.element(ijk));
            if let Some(xi) = try_element(home) {
                return Some((grid.element_ijk(home), xi));
            }
            tried.push(home);
            for reach in [1i64, LOCATE_REACH] {
                let mut ring = Vec::new();
                for dk in -1i64..=1 {
                    for dj in -reach..=reach {
                        for di in -reach..=reach {
                            let c = [ijk[0] as i64 + di, ijk[1] as i64 + dj, ijk[2] as i64 + dk];
                            if (0..3).all(|d| c[d] >= 0 && (c[d] as usize) < ne[d]) {
                                let e = grid.owner(grid.element(c.map(|v| v as usize)));
                                if !tried.contains(&e) && !ring.contains(&e) {
                                    ring.push(e);
                                }
                            }
                        }
                    }
                }
                // By the distance from the point to the element's node centroid (mapped): near
                // a sidewall the point lies in a neighbour, and the nearest is the likeliest (on
                // the sensor 5.4 Newton inversions a point, 15 in index order).
                let distance = |e: usize| {
                    let x = grid.element_nodes(e).map(|n| self.ctx.pos_um[n]);
                    (0..3)
                        .map(|d| {
                            let c = x.iter().map(|q| q[d]).sum::<f64>() / x.len() as f64;
                            (c - p_um[d]).powi(2)
                        })
                        .sum::<f64>()
                };
                let mut keyed: Vec<(f64, usize)> = ring.iter().map(|&e| (distance(e), e)).collect();
                keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let ring: Vec<usize> = keyed.into_iter().map(|k| k.1).collect();
                for &e in &ring {
                    if let Some(xi) = try_element(e) {
                        return Some((grid.element_ijk(e), xi));
                    }
                }
                tried.extend(ring);
            }
        }
        // Active elements whose node box, grown by `margin`, holds the point.
        let near = |margin: f64| {
            (0..grid.element_count())
                .filter(|&e| grid.material(e).is_some())
                .filter(move |&e| {
                    let x = grid.element_nodes(e).map(|n| self.ctx.pos_um[n]);
                    (0..3).all(|d| {
                        let lo = x.iter().map(|p| p[d]).fold(f64::INFINITY, f64::min);
                        let hi = x.iter().map(|p| p[d]).fold(f64::NEG_INFINITY, f64::max);
                        p_um[d] >= lo - margin && p_um[d] <= hi + margin
                    })
                })
        };
        tried.sort_unstable();
        let inside = near(1e-9 * grid.extent_um())
            .filter(|e| tried.binary_search(e).is_err())
            .find_map(|e| try_element(e).map(|xi| (grid.element_ijk(e), xi)));
        let tol = grid.tolerance_um();
        if inside.is_some() || tol <= 0.0 {
            return inside;
        }
        // The nearest point within the tolerance (the smallest distance, then the lowest
        // element: deterministic).
        near(tol)
            .filter_map(|e| {
                let x = grid.element_nodes(e).map(|n| self.ctx.pos_um[n]);
                let xi = nearest_local_point(&x, p_um);
                let at = hex27::position(&x, xi);
                let d = (0..3)
                    .map(|k| (at[k] - p_um[k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                (d <= tol).then_some((d, e, xi))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, e, xi)| (grid.element_ijk(e), xi))
    }

    /// Displacement (m) at a point (um, after the node map); None outside the active elements.
    pub fn displacement_m(&self, p_um: [f64; 3]) -> Option<[f64; 3]> {
        let (e, xi) = self.locate(p_um)?;
        self.displacement_at(e, xi)
    }
}

/// Cells in plane round the unmapped guess that [`SolidSolution::locate`] tries before scanning
/// every element \[choice\]: a tooth's sidewall map moves a point by its run-out (141 um on the
/// bundled design), several of the finest graded cells.
const LOCATE_REACH: i64 = 6;

/// Local coordinates of `p` in the element with nodes `x` (same unit), by Newton from the
/// centre; None if it does not converge inside [-1, 1]^3 (with a 1e-9 margin).
fn inverse_map(x: &[[f64; 3]; hex27::NODES], p: [f64; 3]) -> Option<[f64; 3]> {
    let (xi, converged) = newton_local_point(x, p);
    (converged && xi.iter().all(|v| v.abs() <= 1.0 + 1e-9)).then(|| xi.map(|v| v.clamp(-1.0, 1.0)))
}

/// A point of the element with nodes `x` near `p` (outside it): Newton's local coordinates of
/// `p`, clamped to [-1, 1]^3. On a curved face not exactly the closest point, so its distance
/// from `p` is at least the closest point's; the caller measures that distance.
fn nearest_local_point(x: &[[f64; 3]; hex27::NODES], p: [f64; 3]) -> [f64; 3] {
    newton_local_point(x, p).0.map(|v| v.clamp(-1.0, 1.0))
}

/// Newton on x(xi) = p from the element's centre, the iterate kept within [-3, 3]^3 (a point
/// far outside is not chased): the last iterate and whether it converged (to 1e-12 of the
/// element's size).
fn newton_local_point(x: &[[f64; 3]; hex27::NODES], p: [f64; 3]) -> ([f64; 3], bool) {
    let scale = (0..3)
        .map(|d| {
            let lo = x.iter().map(|q| q[d]).fold(f64::INFINITY, f64::min);
            let hi = x.iter().map(|q| q[d]).fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        })
        .fold(0.0, f64::max);
    let mut xi = [0.0; 3];
    for _ in 0..30 {
        let at = hex27::position(x, xi);
        let r: [f64; 3] = std::array::from_fn(|d| p[d] - at[d]);
        if r.iter().map(|v| v.abs()).fold(0.0, f64::max) <= 1e-12 * scale {
            return (xi, true);
        }
        let Some(step) = hex27::solve_transposed(&hex27::jacobian(x, xi), r) else {
            return (xi, false);
        };
        for d in 0..3 {
            xi[d] = (xi[d] + step[d]).clamp(-3.0, 3.0);
        }
    }
    (xi, false)
}
