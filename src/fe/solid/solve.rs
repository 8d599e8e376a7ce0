//! The factorised solid model: dofs, pattern, symbolic analysis (nested dissection or AMD) and
//! the Cholesky factor, kept for any number of load cases and for new material constants.

use std::sync::Arc;
use std::time::{Duration, Instant};

use faer::sparse::SparseColMat;
use faer::Mat;
use rayon::prelude::*;

use crate::fe::cholesky::{CholeskyFactor, SymbolicFactor};
use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::assemble::{ElementMatrices, SolidPattern};
use crate::fe::solid::dofs::{active_nodes, SolidDofs};
use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::grid::{check_elements, node_positions_um};
use crate::fe::solid::loads::load_vector;
use crate::fe::solid::ordering::free_dof_order;
use crate::fe::solid::problem::{SolidLoad, SolidProblem};
use crate::fe::solid::solution::{SolidContext, SolidSolution};

/// Fill-reducing order of the factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ordering {
    /// Nested dissection of the node lattice ([`crate::fe::solid::ordering`]).
    NestedDissection,
    /// faer's approximate minimum degree on the assembled pattern.
    Amd,
}

/// Wall-clock cost of building the model (for benches and reports, never for tests).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuildTimings {
    /// Node positions, element checks, dofs, element matrices and the pattern.
    pub setup: Duration,
    /// Assembly of the values.
    pub assembly: Duration,
    /// Ordering and symbolic analysis.
    pub symbolic: Duration,
    /// Numeric factorisation.
    pub numeric: Duration,
}

/// A solid model factorised once: solve any number of load cases ([`SolidModel::solve`]) and
/// refactorise for new materials on the same pattern ([`SolidModel::refactor_materials`]).
#[derive(Debug, Clone)]
pub struct SolidModel {
    ctx: Arc<SolidContext>,
    pattern: SolidPattern,
    symbolic: SymbolicFactor,
    llt: CholeskyFactor,
    /// Active elements touching a constrained dof: K u there gives the reactions and the
    /// prescribed values' load.
    support_elements: Vec<usize>,
    /// Each solve takes one step of iterative refinement ([`SolidModel::refine`]).
    refine: bool,
    timings: BuildTimings,
}

impl SolidModel {
    /// Builds and factorises with the nested-dissection order.
    pub fn new(problem: &SolidProblem) -> FeResult<Self> {
        Self::with_ordering(problem, Ordering::NestedDissection)
    }

    /// Builds and factorises with the given order. Every invalid input (lines, map, materials,
    /// constraints, size) is a returned error.
    pub fn with_ordering(problem: &SolidProblem, ordering: Ordering) -> FeResult<Self> {
        let t0 = Instant::now();
        let grid = &problem.grid;
        // The size bound before the positions and element checks, which scale with it.
        active_nodes(grid)?;
        let pos_um = node_positions_um(grid)?;
        check_elements(grid, &pos_um)?;
        let dofs = SolidDofs::new(grid, &pos_um, &problem.constraints)?;
        dofs.check_rigid_modes(grid, &pos_um)?;
        let kel = ElementMatrices::new(grid, &pos_um, &problem.materials, problem.shear)?;
        let pattern = SolidPattern::new(grid, &dofs)?;
        let t1 = Instant::now();
        let vals = pattern.values(grid, &dofs, &kel);
        let t2 = Instant::now();
        let symbolic = match ordering {
            Ordering::NestedDissection => {
                SymbolicFactor::new(pattern.symbolic.as_ref(), &free_dof_order(&dofs, grid))?
            }
            Ordering::Amd => SymbolicFactor::amd(pattern.symbolic.as_ref())?,
        };
        let t3 = Instant::now();
        let llt = factor(&symbolic, &pattern, vals)?;
        let t4 = Instant::now();
        let support_elements = support_elements(grid, &dofs);
        Ok(SolidModel {
            ctx: Arc::new(SolidContext {
                grid: grid.clone(),
                pos_um,
                materials: problem.materials.clone(),
                dofs,
                kel,
                shear: problem.shear,
            }),
            pattern,
            symbolic,
            llt,
            support_elements,
            refine: true,
            timings: BuildTimings {
                setup: t1 - t0,
                assembly: t2 - t1,
                symbolic: t3 - t2,
                numeric: t4 - t3,
            },
        })
    }

    /// New material constants on the same grid and constraints: element matrices and values
    /// again, the symbolic analysis reused.
    pub fn refactor_materials(&mut self, materials: &[Elasticity]) -> FeResult<()> {
        let c = &self.ctx;
        let kel = ElementMatrices::new(&c.grid, &c.pos_um, materials, c.shear)?;
        let vals = self.pattern.values(&c.grid, &c.dofs, &kel);
        self.llt = factor(&self.symbolic, &self.pattern, vals)?;
        self.ctx = Arc::new(SolidContext {
            grid: c.grid.clone(),
            pos_um: c.pos_um.clone(),
            materials: materials.to_vec(),
            dofs: c.dofs.clone(),
            kel,
            shear: c.shear,
        });
        Ok(())
    }

    /// The model without the step of iterative refinement after each solve: for a submodel read
    /// only for its stresses (`fe::solid::vertex`), where the direct solve's residual (about
    /// 1e-9 of the driven values) is far under any reading and the step would double each
    /// solve's triangular solves. Reactions then balance only to that residual.
    pub fn without_refinement(mut self) -> Self {
        self.refine = false;
        self
    }

    /// Number of free dofs.
    pub fn n_free_dofs(&self) -> usize {
        self.ctx.dofs.n_free()
    }

    /// Entries of the assembled lower triangle.
    pub fn matrix_nnz(&self) -> usize {
        self.pattern.nnz()
    }

    /// Entries of the Cholesky factor (f64s of memory).
    pub fn factor_len(&self) -> usize {
        self.symbolic.factor_len()
    }

    /// Distinct element matrices computed (shared ones count once).
    pub fn distinct_element_matrices(&self) -> usize {
        self.ctx.kel.distinct()
    }

    /// Wall-clock cost of [`SolidModel::with_ordering`].
    pub fn timings(&self) -> BuildTimings {
        self.timings
    }

    /// Solves all load cases with one multi-column triangular solve. Prescribed values apply to
    /// every case. Reactions are K u - f at the constrained dofs.
    pub fn solve(&self, load_cases: &[Vec<SolidLoad>]) -> FeResult<Vec<SolidSolution>> {
        let c = &self.ctx;
        let dofs = &c.dofs;
        let forces: Vec<Vec<f64>> = load_cases
            .par_iter()
            .enumerate()
            .map(|(k, l)| load_vector(&c.grid, &c.pos_um, dofs, l, k))
            .collect::<FeResult<_>>()?;
        let mut u_fixed = vec![0.0; 3 * c.pos_um.len()];
        for &(d, v, _) in &dofs.constrained {
            u_fixed[d] = v;
        }
        self.solve_with(forces, u_fixed)
    }

    /// Solves without loads, the constrained dofs given new values: `value(p_um)` is the
    /// displacement (m) of a constrained node at (mapped) position `p_um`, of which the
    /// components the constraints fix are taken. The factor is reused: a submodel driven by
    /// another field, any number of times (`fe::solid::vertex`).
    pub fn solve_prescribed(
        &self,
        value: impl Fn([f64; 3]) -> FeResult<[f64; 3]>,
    ) -> FeResult<SolidSolution> {
        let c = &self.ctx;
        let mut u_fixed = vec![0.0; 3 * c.pos_um.len()];
        let mut last: Option<(usize, [f64; 3])> = None;
        for &(d, _, _) in &c.dofs.constrained {
            let node = d / 3;
            let u = match last {
                Some((n, u)) if n == node => u,
                _ => value(c.pos_um[node])?,
            };
            last = Some((node, u));
            u_fixed[d] = u[d % 3];
        }
        let forces = vec![vec![0.0; u_fixed.len()]];
        let mut out = self.solve_with(forces, u_fixed)?;
        Ok(out.pop().expect("one case"))
    }

    fn solve_with(
        &self,
        forces: Vec<Vec<f64>>,
        mut u_fixed: Vec<f64>,
    ) -> FeResult<Vec<SolidSolution>> {
        let c = &self.ctx;
        let dofs = &c.dofs;
        dofs.hanging.fill(&mut u_fixed);
        let mut k_fixed = c.kel.apply_on(
            &c.grid,
            &c.pos_um,
            &u_fixed,
            self.support_elements.iter().copied(),
        );
        dofs.hanging.reduce(&mut k_fixed);
        let n_free = dofs.n_free();
        let mut rhs = Mat::<f64>::zeros(n_free, forces.len());
        for (k, f) in forces.iter().enumerate() {
            for (i, &d) in dofs.free_dofs.iter().enumerate() {
                rhs[(i, k)] = f[d] - k_fixed[d];
            }
        }
        let rhs0 = self.refine.then(|| rhs.clone());
        self.llt.solve_in_place(rhs.as_mut());
        if let Some(rhs0) = rhs0 {
            self.refine(&rhs0, &mut rhs, &u_fixed);
        }
        (0..forces.len())
            .into_par_iter()
            .map(|k| {
                let mut u = u_fixed.clone();
                for (i, &d) in dofs.free_dofs.iter().enumerate() {
                    u[d] = rhs[(i, k)];
                }
                dofs.hanging.fill(&mut u);
                if u.iter().any(|v| !v.is_finite()) {
                    return Err(FeError::NonFinite {
                        hint: "check material constants and load values for NaN/inf",
                    });
                }
                let mut ku = c.kel.apply_on(
                    &c.grid,
                    &c.pos_um,
                    &u,
                    self.support_elements.iter().copied(),
                );
                dofs.hanging.reduce(&mut ku);
                let reactions = dofs
                    .constrained
                    .iter()
                    .map(|&(d, _, _)| ku[d] - forces[k][d])
                    .collect();
                let mut applied = [0.0; 3];
                for (d, f) in forces[k].iter().enumerate() {
                    applied[d % 3] += f;
                }
                Ok(SolidSolution::new(self.ctx.clone(), u, reactions, applied))
            })
            .collect()
    }
}

impl SolidModel {
    /// One step of iterative refinement, x += K^-1 (b - K x) (Higham, Accuracy and Stability of
    /// Numerical Algorithms, sec. 12.1): the free equations' residual, and with it the
    /// reactions' imbalance, drops from ~1e-9 to round-off of the load.
    fn refine(&self, b: &Mat<f64>, x: &mut Mat<f64>, u_fixed: &[f64]) {
        let c = &self.ctx;
        let dofs = &c.dofs;
        let active: Vec<usize> = (0..c.grid.element_count())
            .filter(|&e| c.grid.material(e).is_some())
            .collect();
        let mut r = Mat::<f64>::zeros(x.nrows(), x.ncols());
        let cols: Vec<Vec<f64>> = (0..x.ncols())
            .into_par_iter()
            .map(|k| {
                let mut u = vec![0.0; u_fixed.len()];
                for (i, &d) in dofs.free_dofs.iter().enumerate() {
                    u[d] = x[(i, k)];
                }
                dofs.hanging.fill(&mut u);
                let mut ku = c
                    .kel
                    .apply_on(&c.grid, &c.pos_um, &u, active.iter().copied());
                dofs.hanging.reduce(&mut ku);
                dofs.free_dofs
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| b[(i, k)] - ku[d])
                    .collect()
            })
            .collect();
        for (k, col) in cols.iter().enumerate() {
            for (i, v) in col.iter().enumerate() {
                r[(i, k)] = *v;
            }
        }
        self.llt.solve_in_place(r.as_mut());
        for k in 0..x.ncols() {
            for i in 0..x.nrows() {
                x[(i, k)] += r[(i, k)];
            }
        }
    }
}

fn factor(
    symbolic: &SymbolicFactor,
    pattern: &SolidPattern,
    vals: Vec<f64>,
) -> FeResult<CholeskyFactor> {
    symbolic.factor(SparseColMat::<usize, f64>::new(pattern.symbolic.clone(), vals).as_ref())
}

/// Elements K u_fixed needs: those round a constrained node (every active one when nodes hang,
/// since a hanging node's element acts on its masters).
fn support_elements(grid: &crate::fe::solid::grid::HexGrid, dofs: &SolidDofs) -> Vec<usize> {
    if !dofs.hanging.is_empty() {
        return (0..grid.element_count())
            .filter(|&e| grid.material(e).is_some())
            .collect();
    }
    let mut out: Vec<usize> = dofs
        .constrained
        .iter()
        .flat_map(|&(d, _, _)| grid.node_elements(d / 3))
        .filter(|&e| grid.material(e).is_some())
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

impl SolidProblem {
    /// Builds, factorises and solves every load case.
    pub fn solve(&self) -> FeResult<Vec<SolidSolution>> {
        SolidModel::new(self)?.solve(&self.load_cases)
    }
}
