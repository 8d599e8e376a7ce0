//! Sparse Cholesky factorisation (faer) with a reusable symbolic analysis and multi-column solves.

use crate::fe::assemble::{ElementStiffness, Pattern};
use crate::fe::cholesky::{CholeskyFactor, SymbolicFactor};
use crate::fe::dofs::DofMap;
use crate::fe::edge_spring::{self, SpringSegment};
use crate::fe::error::{FeError, FeResult};
use crate::fe::loads::load_vector;
use crate::fe::ordering::free_dof_order;
use crate::fe::problem::{EdgeSpring, Load, PlateProblem};
use crate::fe::solution::NodalReaction;
use crate::fe::solution::{GroupReaction, PlateSolution, SolutionContext};
use faer::sparse::SparseColMat;
use faer::{Mat, MatMut, MatRef};
use rayon::prelude::*;
use std::sync::Arc;

/// A factorised plate stiffness: the symbolic analysis is kept and reused by
/// [`Factorised::refactor`] when only values change (thickness, material); load cases are solved as
/// one multi-column solve.
#[derive(Debug, Clone)]
pub struct Factorised {
    dofs: DofMap,
    pattern: Pattern,
    kel: ElementStiffness,
    symbolic: SymbolicFactor,
    llt: CholeskyFactor,
    ctx: Arc<SolutionContext>,
    key: PlateProblem,
    /// Elements with a constrained dof: K u there gives the reactions (and K u_fixed the
    /// prescribed values' load) without a product over the whole plate.
    support_elements: Vec<usize>,
    /// Edge springs with their segments on this mesh.
    springs: Vec<Springs>,
}

pub(crate) type Springs = (EdgeSpring, Vec<SpringSegment>);

pub(crate) fn springs_of(problem: &PlateProblem) -> FeResult<Vec<Springs>> {
    problem
        .edge_springs
        .iter()
        .map(|s| {
            if let Some(g) = s.along_wall {
                edge_spring::check_semi_definite(&g, &s.group)?;
            }
            Ok((s.clone(), edge_spring::segments(&problem.mesh, s)?))
        })
        .collect()
}

fn values_with_springs(
    pattern: &Pattern,
    mesh: &crate::fe::mesh::RectMesh,
    dofs: &DofMap,
    kel: &ElementStiffness,
    springs: &[Springs],
) -> Vec<f64> {
    let mut vals = pattern.values(mesh, dofs, kel);
    edge_spring::add_to_values(pattern, &mut vals, mesh, &dofs.free_index, springs);
    vals
}

fn support_elements(mesh: &crate::fe::mesh::RectMesh, dofs: &DofMap) -> Vec<usize> {
    (0..mesh.n_elements())
        .filter(|&e| {
            crate::fe::dofs::element_dofs(mesh, e)
                .iter()
                .any(|&d| dofs.free_index[d] == crate::fe::dofs::CONSTRAINED)
        })
        .collect()
}

fn numeric(
    symbolic: &SymbolicFactor,
    pattern: &Pattern,
    vals: Vec<f64>,
) -> FeResult<CholeskyFactor> {
    symbolic.factor(SparseColMat::<usize, f64>::new(pattern.symbolic.clone(), vals).as_ref())
}

fn pattern_key(p: &PlateProblem) -> PlateProblem {
    PlateProblem {
        thickness_regions: Vec::new(),
        load_cases: Vec::new(),
        base_thickness_um: 0.0,
        ..p.clone()
    }
}

impl Factorised {
    /// Number the dofs, check that rigid-body motion is prevented, build the pattern, analyse and
    /// factorise. Panics on an empty or unsorted mesh (misuse); returns errors for physically
    /// invalid input.
    #[track_caller]
    pub fn new(problem: &PlateProblem) -> FeResult<Self> {
        let mesh = &problem.mesh;
        mesh.validate();
        let dofs = DofMap::new(problem)?;
        dofs.check_rigid_modes(mesh)?;
        if dofs.n_free() == 0 {
            return Err(FeError::Sparse {
                detail: "no free dofs".into(),
                hint: "everything is constrained: use a finer mesh or fewer supports",
            });
        }
        let pattern = Pattern::new(mesh, &dofs)?;
        let order = free_dof_order(&dofs, mesh.x_um.len(), mesh.y_um.len());
        let symbolic = SymbolicFactor::new(pattern.symbolic.as_ref(), &order)?;
        let thickness = problem.element_thickness_um();
        let kel = ElementStiffness::new(problem, &thickness)?;
        let springs = springs_of(problem)?;
        let vals = values_with_springs(&pattern, mesh, &dofs, &kel, &springs);
        let llt = numeric(&symbolic, &pattern, vals)?;
        let ctx = Arc::new(SolutionContext {
            mesh: mesh.clone(),
            thickness_um: thickness,
            rise_um: Vec::new(),
            material: problem.material,
            groups: dofs.groups.clone(),
        });
        let support_elements = support_elements(mesh, &dofs);
        Ok(Factorised {
            dofs,
            pattern,
            kel,
            symbolic,
            llt,
            ctx,
            key: pattern_key(problem),
            support_elements,
            springs,
        })
    }

    /// New values (thickness map, material) on the same mesh, supports and prescribed dofs:
    /// reuses the symbolic factorisation.
    pub fn refactor(&mut self, problem: &PlateProblem) -> FeResult<()> {
        let mut key = pattern_key(problem);
        key.material = self.key.material;
        let mut old = self.key.clone();
        old.material = key.material;
        if key != old {
            return Err(FeError::PatternMismatch {
                hint: "build a new Factorised when the mesh, supports or prescribed dofs change",
            });
        }
        let thickness = problem.element_thickness_um();
        let kel = ElementStiffness::new(problem, &thickness)?;
        let llt = numeric(
            &self.symbolic,
            &self.pattern,
            values_with_springs(
                &self.pattern,
                &problem.mesh,
                &self.dofs,
                &kel,
                &self.springs,
            ),
        )?;
        self.kel = kel;
        self.llt = llt;
        self.key = pattern_key(problem);
        self.ctx = Arc::new(SolutionContext {
            mesh: problem.mesh.clone(),
            thickness_um: thickness,
            rise_um: Vec::new(),
            material: problem.material,
            groups: self.dofs.groups.clone(),
        });
        Ok(())
    }

    /// New mesh coordinates (same node counts), thickness and material with the same constrained
    /// dof indices: the sparsity pattern depends only on the mesh topology and the constraint
    /// set, so the symbolic analysis is reused and only the numeric factorisation is redone (a
    /// design sweep over plate sizes). Errors with [`FeError::PatternMismatch`] if the topology
    /// or constraints differ.
    pub fn refactor_topology(&mut self, problem: &PlateProblem) -> FeResult<()> {
        let mesh = &problem.mesh;
        mesh.validate();
        let same_counts = mesh.x_um.len() == self.ctx.mesh.x_um.len()
            && mesh.y_um.len() == self.ctx.mesh.y_um.len();
        let dofs = if same_counts {
            DofMap::new(problem)?
        } else {
            self.dofs.clone()
        };
        if !same_counts
            || dofs.free_dofs != self.dofs.free_dofs
            || dofs.groups != self.dofs.groups
            || !dofs
                .constrained
                .iter()
                .zip(&self.dofs.constrained)
                .all(|(a, b)| a.0 == b.0 && a.2 == b.2)
        {
            return Err(FeError::PatternMismatch {
                hint: "refactor_topology needs the same node counts and the same constrained \
                       dofs; build a new Factorised otherwise",
            });
        }
        let thickness = problem.element_thickness_um();
        let kel = ElementStiffness::new(problem, &thickness)?;
        let springs = springs_of(problem)?;
        let llt = numeric(
            &self.symbolic,
            &self.pattern,
            values_with_springs(&self.pattern, mesh, &dofs, &kel, &springs),
        )?;
        self.springs = springs;
        self.kel = kel;
        self.llt = llt;
        self.dofs = dofs;
        self.support_elements = support_elements(mesh, &self.dofs);
        self.key = pattern_key(problem);
        self.ctx = Arc::new(SolutionContext {
            mesh: mesh.clone(),
            thickness_um: thickness,
            rise_um: Vec::new(),
            material: problem.material,
            groups: self.dofs.groups.clone(),
        });
        Ok(())
    }

    /// The mesh, element thickness and material this factorisation was built for.
    pub(crate) fn context(&self) -> &SolutionContext {
        &self.ctx
    }

    /// The dof numbering and constraints.
    pub(crate) fn dof_map(&self) -> &DofMap {
        &self.dofs
    }

    /// The element stiffness matrices (K x products without the assembled matrix).
    pub(crate) fn element_stiffness(&self) -> &ElementStiffness {
        &self.kel
    }

    /// Overwrites every column of `rhs` (free dofs) with K^-1 of it: the factor, reused.
    pub(crate) fn solve_free_in_place(&self, rhs: faer::MatMut<'_, f64>) {
        self.llt.solve_in_place(rhs);
    }

    /// Number of free (unknown) dofs.
    pub fn n_free_dofs(&self) -> usize {
        self.dofs.n_free()
    }

    /// Every dof's value for load case `c`: the prescribed ones, then column `c` of the free
    /// solution `x`.
    fn full_field(&self, u_fixed: &[f64], x: MatRef<'_, f64>, c: usize) -> Vec<f64> {
        let mut u = u_fixed.to_vec();
        for (i, &d) in self.dofs.free_dofs.iter().enumerate() {
            u[d] = x[(i, c)];
        }
        u
    }

    /// One step of iterative refinement for a plate on edge springs, whose reactions are the
    /// springs' forces K_s u rather than a clamp's f - K u: the residual f - K u at the free
    /// dofs with each element's product taken on w less its mean corner deflection
    /// ([`ElementStiffness::apply_on_mean_free`]), solved with the same factor and added. The
    /// factorised K annihilates a rigid translation only to round-off, and on fine meshes the
    /// solved field carried a phantom vertical force the springs' reactions showed (6.3e-5 of
    /// the load on the bundled design's 8th level under the support sections).
    fn refine_with_springs(&self, forces: &[Vec<f64>], u_fixed: &[f64], mut x: MatMut<'_, f64>) {
        let mesh = &self.ctx.mesh;
        let free = &self.dofs.free_dofs;
        let mut res = Mat::<f64>::zeros(free.len(), forces.len());
        for (c, f) in forces.iter().enumerate() {
            let u = self.full_field(u_fixed, x.as_ref(), c);
            let mut ku = self.kel.apply_on_mean_free(mesh, &u, 0..mesh.n_elements());
            edge_spring::add_forces(&self.springs, &u, 4, &mut ku);
            for (i, &d) in free.iter().enumerate() {
                res[(i, c)] = f[d] - ku[d];
            }
        }
        self.llt.solve_in_place(res.as_mut());
        for c in 0..forces.len() {
            for i in 0..free.len() {
                x[(i, c)] += res[(i, c)];
            }
        }
    }

    /// Solve all load cases with one multi-column triangular solve. Prescribed dof values apply to
    /// every case.
    pub fn solve(&self, load_cases: &[Vec<Load>]) -> FeResult<Vec<PlateSolution>> {
        let mesh = &self.ctx.mesh;
        let n_free = self.dofs.n_free();
        let forces: Vec<Vec<f64>> = load_cases
            .par_iter()
            .enumerate()
            .map(|(c, l)| load_vector(mesh, l, c))
            .collect::<FeResult<_>>()?;
        let mut u_fixed = vec![0.0; self.dofs.n_dofs];
        for &(d, v, _) in &self.dofs.constrained {
            u_fixed[d] = v;
        }
        let k_fixed = self
            .kel
            .apply_on(mesh, &u_fixed, self.support_elements.iter().copied());
        let mut rhs = Mat::<f64>::zeros(n_free, load_cases.len());
        for (c, f) in forces.iter().enumerate() {
            for (i, &d) in self.dofs.free_dofs.iter().enumerate() {
                rhs[(i, c)] = f[d] - k_fixed[d];
            }
        }
        self.llt.solve_in_place(rhs.as_mut());
        if !self.springs.is_empty() {
            self.refine_with_springs(&forces, &u_fixed, rhs.as_mut());
        }
        (0..load_cases.len())
            .into_par_iter()
            .map(|c| {
                let u = self.full_field(&u_fixed, rhs.as_ref(), c);
                if u.iter().any(|v| !v.is_finite()) {
                    return Err(FeError::NonFinite {
                        hint: "check material constants, thickness and load values for NaN/inf",
                    });
                }
                let ku = self
                    .kel
                    .apply_on(mesh, &u, self.support_elements.iter().copied());
                // Force carried by each support in the load direction: f - K u at constrained w
                // dofs.
                let mut by_group = vec![0.0; self.dofs.groups.len()];
                let mut nodal = Vec::new();
                for &(d, _, g) in &self.dofs.constrained {
                    if d % 4 == 0 {
                        let r = forces[c][d] - ku[d];
                        by_group[g] += r;
                        let node = d / 4;
                        let (i, j) = (node % (mesh.nx() + 1), node / (mesh.nx() + 1));
                        nodal.push(NodalReaction {
                            group: self.dofs.groups[g].clone(),
                            x_um: mesh.x_um[i],
                            y_um: mesh.y_um[j],
                            force_n: r,
                        });
                    }
                }
                // An edge spring carries K_s u at its w dofs.
                for (i, node, f) in edge_spring::nodal_forces(&self.springs, &u, 4) {
                    let g = self
                        .dofs
                        .groups
                        .iter()
                        .position(|g| *g == self.springs[i].0.group)
                        .expect("DofMap names every spring group");
                    by_group[g] += f;
                    let (ii, jj) = (node % (mesh.nx() + 1), node / (mesh.nx() + 1));
                    nodal.push(NodalReaction {
                        group: self.dofs.groups[g].clone(),
                        x_um: mesh.x_um[ii],
                        y_um: mesh.y_um[jj],
                        force_n: f,
                    });
                }
                let applied_force_n = forces[c].iter().step_by(4).sum();
                let reactions = self
                    .dofs
                    .groups
                    .iter()
                    .zip(by_group)
                    .map(|(g, f)| GroupReaction {
                        group: g.clone(),
                        force_n: f,
                    })
                    .collect();
                Ok(
                    PlateSolution::new(self.ctx.clone(), u, reactions, applied_force_n)
                        .with_nodal(nodal),
                )
            })
            .collect()
    }
}

impl PlateProblem {
    /// Factorise and solve all load cases of the problem.
    #[track_caller]
    pub fn solve(&self) -> FeResult<Vec<PlateSolution>> {
        Factorised::new(self)?.solve(&self.load_cases)
    }
}
