//! The geometrically nonlinear solid ([`crate::fe::solid::tl`]): Newton with the consistent
//! tangent on the linear model's dofs, pattern and symbolic analysis (one per grid and constraint
//! set), with load stepping in the style of the von Karman plate ([`crate::fe::VonKarman`]). Where
//! the factor is large every correction after the first is conjugate gradients on the current
//! tangent preconditioned by the last numeric factorisation (inexact Newton: one factorisation
//! per solve on the sensor); on small meshes each iteration factorises (full Newton).
//!
//! Loads are dead loads: point forces and pressures computed on the undeformed geometry exactly as
//! the linear core does, scaled by the load factor. Prescribed displacements are scaled with the
//! same factor. Reactions are f_int - f at the constrained dofs (the linear core's K u - f).

use std::sync::Arc;

use faer::sparse::{SparseColMat, SparseColMatRef};
use faer::Mat;
use rayon::prelude::*;

use crate::fe::cholesky::{CholeskyFactor, SymbolicFactor};
use crate::fe::error::{FeError, FeResult};
use crate::fe::solid::assemble::{
    check_materials, element_nodes_m, reduced_element, ElementMatrices, SolidPattern, VOID,
};
use crate::fe::solid::dofs::{active_nodes, SolidDofs};
use crate::fe::solid::grid::{check_elements, node_positions_um, HexGrid};
use crate::fe::solid::hex27::{self, DOFS, NODES};
use crate::fe::solid::loads::load_vector;
use crate::fe::solid::ordering::free_dof_order;
use crate::fe::solid::problem::{SolidLoad, SolidProblem};
use crate::fe::solid::solution::{SolidContext, SolidReaction, SolidSolution};
use crate::fe::solid::tl;
use crate::fe::vonkarman::NewtonStats;

/// Energy-norm ratio under which a correction that stops shrinking is round-off (as in the von
/// Karman plate) \[choice\]: the displacement correction is then ~1e-4 of the first.
const ROUND_OFF_RATIO: f64 = 1e-8;

/// A correction under this fraction of the largest displacement is round-off and ends the
/// iterations \[choice\] (~1e4 times double precision): covers a predictor so good that the
/// first correction is already round-off (a prescribed rigid rotation: no force to compare a
/// residual with).
const ROUND_OFF_DISPLACEMENT: f64 = 1e-12;

/// Relative residual (2-norm) to which a lagged-tangent correction is solved \[choice\]: each
/// Newton iteration then reduces the residual at least this much, so from a coarser level's
/// field the 1e-10 tolerance takes about as many iterations as exact corrections do.
const KRYLOV_TOL: f64 = 1e-5;

/// A correction under this fraction of the step's first (in energy, so ~1e-3 in displacement)
/// leaves the tangent practically as it was \[choice\]: the next correction is solved on the
/// same tangent (no new assembly; on the sensor's 280k-dof level a tangent takes 3-4 s, a
/// residual 0.8 s). Its error is then of the order of the two corrections' product, far under
/// the tolerances.
const POLISH_RATIO: f64 = 1e-6;

/// Largest relative residual a correction is solved to \[choice\]: Eisenstat & Walker's
/// safeguard (their eta_max is 0.9; a tenth keeps a lagged-tangent correction a Newton step).
const FORCING_MAX: f64 = 0.1;

/// Where a Newton solve starts, which sets how exactly its first correction is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Start {
    /// A load step, from rest or from the last step's field: the first correction carries the
    /// step's nonlinearity, which leaves a tenth of its energy or more for the next (the
    /// bundled centre load from rest), so it is solved only to [`FORCING_MAX`], Eisenstat and
    /// Walker's safeguard (their own first forcing term is 0.5). Level 0 of that load took 28
    /// conjugate-gradient steps instead of 36, in the same five iterations, to the same field
    /// within 1e-10.
    Step,
    /// A guessed field, a coarser mesh's: the first correction is the change of mesh, linear to
    /// 3e-4 (a finer level of the same load), so it is solved to [`KRYLOV_TOL`].
    Guess,
}

impl Start {
    fn tol(self) -> f64 {
        match self {
            Start::Step => FORCING_MAX,
            Start::Guess => KRYLOV_TOL,
        }
    }
}

/// The relative residual to which a correction is solved, from the residual's reduction by the
/// last one (2-norms): Eisenstat & Walker's choice 2, eta = 0.9 (|r_k| / |r_k-1|)^2 (SIAM J.
/// Sci. Comput. 17 (1996) 16, sec. 2, gamma 0.9 and alpha 2), between [`KRYLOV_TOL`] and
/// [`FORCING_MAX`]. Far from the solution, where the last step reduced the residual little, the
/// linear solve need not be accurate (its error stays under the nonlinearity's); near it the
/// forcing term shrinks with the residual and Newton's fast convergence is kept.
fn forcing(reduction: f64) -> f64 {
    if reduction.is_finite() {
        (0.9 * reduction * reduction).clamp(KRYLOV_TOL, FORCING_MAX)
    } else {
        KRYLOV_TOL
    }
}

/// Conjugate-gradient iterations a correction may take, at most.
const KRYLOV_MAX: usize = 40;

/// Factor entries per free dof and per conjugate-gradient iteration that one numeric
/// factorisation costs \[choice, measured\]: a factorisation takes ~(entries / n)^2 flops per
/// dof at dense-kernel speed, a CG step ~4 entries / n at memory speed. On the sensor's half die
/// (166k dofs, 902 entries per dof) one factorisation took 5.2 s and one CG step 0.2 s (26 steps,
/// 902 / 35: 50 leaves a margin); on a 14.5k-dof plate (298 per dof) CG lost to refactorising
/// (`examples/solid_tl_bench.rs`).
const ENTRIES_PER_DOF_PER_STEP: usize = 50;

/// Fewest CG iterations worth trying: a correction to [`KRYLOV_TOL`] takes about 7 on the
/// sensor \[choice\].
const KRYLOV_MIN: usize = 8;

/// How far under the energy tolerance the next correction's estimate must lie to end the
/// iterations \[choice\]: the lagged factor's estimate r . K_0^-1 r differs from the current
/// tangent's r . K_T^-1 r by at most the spread of K_0^-1 K_T's eigenvalues (measured on the
/// sensor's level 0: 8.18e-21 against the next iteration's 8.46e-21 of the first energy).
const NEXT_ENERGY_MARGIN: f64 = 0.1;

/// Whether the correction that would follow residual `r` is already under the energy tolerance
/// (`energy_tol` of the step's first correction energy `e0`), estimated with the factor at hand
/// (one pair of triangular solves, where computing it takes a tangent, a correction and a
/// residual: on the sensor's 348k-dof level 1.4 s against 18 s). The test on the correction
/// just made ([`TlOptions::energy_tol`]) looks one iteration back: after a Newton step from a
/// small residual the field's error is the next correction, not the last.
fn next_correction_small(
    lagged: Option<&CholeskyFactor>,
    r: &[f64],
    e0: f64,
    energy_tol: f64,
) -> bool {
    let Some(pre) = lagged else {
        return false;
    };
    let z = solve_with(pre, r);
    let energy = z.iter().zip(r).map(|(a, b)| a * b).sum::<f64>().abs();
    energy.is_finite() && energy <= NEXT_ENERGY_MARGIN * energy_tol * e0
}

/// x = A^-1 b with a Cholesky factor of A.
fn solve_with(llt: &CholeskyFactor, b: &[f64]) -> Vec<f64> {
    let mut rhs = Mat::<f64>::zeros(b.len(), 1);
    for (i, v) in b.iter().enumerate() {
        rhs[(i, 0)] = *v;
    }
    llt.solve_in_place(rhs.as_mut());
    (0..b.len()).map(|i| rhs[(i, 0)]).collect()
}

/// Smallest load step (fraction of the load) before the solve gives up \[choice\].
const MIN_STEP: f64 = 1e-4;

/// Elements per parallel chunk of the assembly \[choice\]: bounds the element tangents held at
/// once (52 kB each; two chunks, one added while the next is computed) while keeping both cores
/// busy.
const CHUNK: usize = 256;

/// One element's nodes, internal force and (if asked) tangent, 81 x 81 row-major.
type ElementForce = ([usize; NODES], [f64; DOFS], Option<Vec<f64>>);

/// Newton and load-stepping controls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TlOptions {
    /// Converged when the energy norm of the correction (du . r) falls below this fraction of
    /// the step's first one, or the next correction's, estimated with the factor at hand, below
    /// a tenth of it (a squared norm: 1e-12 is ~1e-6 in displacement; the field is then at most
    /// about that far from the solution, and after a correction that met it, with Newton's
    /// quadratic convergence, ~1e-12) ...
    pub energy_tol: f64,
    /// ... and the largest free residual below this fraction of the step's force scale (the
    /// larger of the load and the first residual).
    pub residual_tol: f64,
    /// Newton iterations per load step before the step is halved.
    pub max_iterations: usize,
    /// Load steps tried (accepted or halved) before giving up.
    pub max_load_steps: usize,
    /// First load step as a fraction of the load (doubled after fast steps, halved on failure).
    pub first_step: f64,
    /// Conjugate-gradient iterations a Newton correction may take on the current tangent,
    /// preconditioned by an earlier iteration's factor, before the tangent is refactorised:
    /// `Some(0)` is full Newton (a factorisation every iteration: quadratic convergence); None
    /// sets it from the factor's size, where a factorisation costs more than that many CG
    /// steps (large 3-D meshes: one factorisation per solve), else full Newton.
    pub krylov_iterations: Option<usize>,
    /// The most work one solve may take, in numeric factorisations of the tangent (a
    /// conjugate-gradient step counts as its share, as it does in choosing CG): a load the
    /// solid cannot carry ends in a bounded time, not after every step and iteration allowed
    /// (64 x 20 factorisations: hours on the sensor's mesh). Never less than
    /// `min_budget_flops` of factorisation, so small meshes keep the full step budget.
    pub max_factorisations: f64,
    /// The floor of that budget, in floating-point operations of factorisation
    /// ([`factorisation_flops`]).
    pub min_budget_flops: f64,
}

/// Work one solve may take by default, in factorisations \[choice\]: the sensor's levels take 1-2
/// (one factorisation, then preconditioned CG), a load stepped down to small steps a dozen.
pub const MAX_FACTORISATIONS: f64 = 24.0;

/// The budget's floor in flops \[choice\]: about 35 s of factorisation at the 2.9e10 flop/s
/// measured on 2 cores (below), so meshes under ~150k dofs are bounded by the step and
/// iteration counts alone, as before.
pub const MIN_BUDGET_FLOPS: f64 = 1e12;

/// Floating-point operations of one numeric factorisation with `factor_len` entries over `n`
/// columns, (entries / n)^2 per column \[estimate\]: on the sensor's half die (333k dofs, 299M
/// entries) 2.7e11, which took 9.2 s (README, "Where a solid level's time goes").
pub fn factorisation_flops(factor_len: usize, n: usize) -> f64 {
    let (l, n) = (factor_len as f64, n.max(1) as f64);
    l * l / n
}

/// The work a solve has taken (its counts, and in factorisations) and may take.
struct Work {
    stats: NewtonStats,
    used: f64,
    limit: f64,
    /// One conjugate-gradient step's share of a factorisation.
    cg_step: f64,
    /// An error that ends the solve rather than the step: a factor refused for memory (a
    /// smaller step needs the same factor).
    fatal: Option<FeError>,
    /// A single-precision preconditioner failed (not positive definite in single precision,
    /// or CG did not converge on it): factorise in double for the rest of the solve.
    double_only: bool,
}

impl Work {
    /// One numeric factorisation done.
    fn factorised(&mut self) {
        self.stats.factorisations += 1;
        self.used += 1.0;
    }

    /// Whether the work has passed the budget.
    fn spent(&self) -> bool {
        self.used > self.limit
    }

    /// A factorisation's error as the step's failure (`context` first); a factor refused for
    /// memory is kept to end the solve.
    fn factor_failed(&mut self, e: FeError, context: String) -> StepFailure {
        let why = format!("{context}: {e}");
        if matches!(e, FeError::OutOfMemory { .. }) {
            self.fatal.get_or_insert(e);
        }
        why
    }

    /// The error that ends the solve: a factor refused for memory, or the budget spent (with how
    /// far the load got); Ok while neither.
    fn check(&mut self, lambda: f64) -> FeResult<()> {
        if let Some(e) = self.fatal.take() {
            return Err(e);
        }
        if !self.spent() {
            return Ok(());
        }
        Err(FeError::Newton {
            detail: format!(
                "stopped at {:.1} % of the load when its work passed the budget of {:.0} \
                 factorisations of the tangent ({:.1} spent)",
                100.0 * lambda,
                self.limit,
                self.used
            ),
            hint: "the solid may buckle or snap at this load, or Newton stalls: lower the load \
                   or refine the grid where it bends most",
        })
    }
}

impl Default for TlOptions {
    fn default() -> Self {
        TlOptions {
            energy_tol: 1e-12,
            residual_tol: 1e-10,
            max_iterations: 20,
            max_load_steps: 64,
            first_step: 1.0,
            krylov_iterations: None,
            max_factorisations: MAX_FACTORISATIONS,
            min_budget_flops: MIN_BUDGET_FLOPS,
        }
    }
}

/// A grid, materials and constraints analysed once for Newton solves of any number of loads.
#[derive(Debug, Clone)]
pub struct TlSolid {
    ctx: Arc<SolidContext>,
    pattern: SolidPattern,
    symbolic: SymbolicFactor,
    active: Vec<usize>,
    opts: TlOptions,
}

/// The converged nonlinear field of one load case.
#[derive(Debug, Clone)]
pub struct TlSolution {
    /// Displacements, reactions and the applied load; its linear stresses are not exposed.
    field: SolidSolution,
    stats: NewtonStats,
    history: Vec<NewtonIterate>,
}

/// Why a Newton step failed (becomes the detail of [`FeError::Newton`]).
type StepFailure = String;

/// A converged Newton step: its iterations, and the internal force of the converged field (all
/// dofs, N), which the last convergence check computed (the reactions' f_int).
struct Converged {
    history: Vec<NewtonIterate>,
    force: Vec<f64>,
}

/// What [`TlSolid::internal`] computes.
struct Internal {
    /// Internal force over all dofs, N.
    force: Vec<f64>,
    /// Tangent values on the pattern, if asked.
    tangent: Option<Vec<f64>>,
    /// The largest sum of element force magnitudes at a dof, N (the force's round-off scale).
    magnitude: f64,
    /// K_T v over all dofs for the vector v given, if any.
    product: Option<Vec<f64>>,
}

/// One Newton iteration of the last load step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonIterate {
    /// Largest free residual before the correction, N.
    pub residual_n: f64,
    /// Energy norm of the correction, |du . r|, J (0 for the final, converged residual).
    pub energy_j: f64,
}

impl TlSolid {
    /// Checks the input as the linear model does (lines, map, materials, constraints, rigid
    /// modes, size) and analyses the pattern in the nested-dissection order. Errors on invalid
    /// options (tolerances not in (0, 1), zero iterations or steps, a first step not in (0, 1]).
    pub fn new(problem: &SolidProblem, opts: TlOptions) -> FeResult<Self> {
        let ok = |v: f64| v > 0.0 && v < 1.0;
        if !ok(opts.energy_tol)
            || !ok(opts.residual_tol)
            || opts.max_iterations == 0
            || opts.max_load_steps == 0
            || !(opts.first_step > 0.0 && opts.first_step <= 1.0)
            || opts.max_factorisations.is_nan()
            || opts.max_factorisations < 1.0
            || !(opts.min_budget_flops >= 0.0 && opts.min_budget_flops.is_finite())
        {
            return Err(FeError::SolidInput {
                detail: format!("invalid Newton options {opts:?}"),
                hint:
                    "tolerances in (0, 1), at least one iteration and step, first step in (0, 1], \
                       a budget of at least one factorisation and a finite floor",
            });
        }
        let grid = &problem.grid;
        active_nodes(grid)?;
        let pos_um = node_positions_um(grid)?;
        check_elements(grid, &pos_um)?;
        check_materials(grid, &problem.materials)?;
        let dofs = SolidDofs::new(grid, &pos_um, &problem.constraints)?;
        dofs.check_rigid_modes(grid, &pos_um)?;
        let pattern = SolidPattern::new(grid, &dofs)?;
        let symbolic =
            SymbolicFactor::new(pattern.symbolic.as_ref(), &free_dof_order(&dofs, grid))?;
        let active = (0..grid.element_count())
            .filter(|&e| grid.material(e).is_some())
            .collect();
        Ok(TlSolid {
            ctx: Arc::new(SolidContext {
                grid: grid.clone(),
                pos_um,
                materials: problem.materials.clone(),
                dofs,
                // The linear element matrices are not needed: stresses come from tl.
                kel: ElementMatrices {
                    kind: vec![VOID; grid.element_count()],
                    matrices: Vec::new(),
                },
                shear: problem.shear,
            }),
            pattern,
            symbolic,
            active,
            opts,
        })
    }

    /// Number of free dofs.
    pub fn n_free_dofs(&self) -> usize {
        self.ctx.dofs.n_free()
    }

    /// Entries of the tangent's Cholesky factor (f64s), a measure of the memory a Newton
    /// iteration takes.
    pub fn factor_len(&self) -> usize {
        self.symbolic.factor_len()
    }

    /// Internal force over all dofs (N, 3 per lattice node), the tangent's values on the pattern
    /// if asked, the largest sum of element force magnitudes at a dof (the scale of the force's
    /// round-off), and the product of the full tangent (free and constrained dofs) with `apply`;
    /// Err names an inverted element.
    fn internal(
        &self,
        u: &[f64],
        with_tangent: bool,
        apply: Option<&[f64]>,
    ) -> Result<Internal, StepFailure> {
        let with_tangent = with_tangent || apply.is_some();
        let c = &self.ctx;
        let grid = &c.grid;
        let hanging = &c.dofs.hanging;
        // Hanging nodes follow their masters: the element fields see the constrained motion.
        let filled = |v: &[f64]| {
            let mut w = v.to_vec();
            hanging.fill(&mut w);
            w
        };
        let (u_own, apply_own) = if hanging.is_empty() {
            (None, None)
        } else {
            (Some(filled(u)), apply.map(filled))
        };
        let u = u_own.as_deref().unwrap_or(u);
        let apply = apply_own.as_deref().or(apply);
        let mut r = vec![0.0; u.len()];
        let mut magnitude = vec![0.0; u.len()];
        let mut vals = with_tangent.then(|| vec![0.0; self.pattern.nnz()]);
        let mut product = apply.map(|_| vec![0.0; u.len()]);
        // Each chunk's element forces and tangents in parallel, added in element order (so the
        // sums do not depend on the threads) while the next chunk is computed.
        let compute = |chunk: &[usize]| -> Result<Vec<_>, StepFailure> {
            chunk
                .par_iter()
                .map(|&e| {
                    let nodes = grid.element_nodes(e);
                    let ue: [f64; DOFS] = std::array::from_fn(|i| u[3 * nodes[i / 3] + i % 3]);
                    let m = &c.materials[usize::from(grid.material(e).unwrap_or(0))];
                    let mut k = with_tangent.then(|| vec![0.0; DOFS * DOFS]);
                    let x = element_nodes_m(grid, &c.pos_um, e);
                    tl::internal_force(&x, m, &ue, c.shear, k.as_deref_mut())
                        .map(|f| (nodes, f, k))
                        .map_err(|inv| {
                            format!(
                                "element {:?} inverted (det F = {:.3e})",
                                grid.element_ijk(e),
                                inv.det_f
                            )
                        })
                })
                .collect::<Result<_, _>>()
        };
        let mut add = |done: Vec<ElementForce>| {
            for (nodes, f, k) in done {
                for (i, v) in f.iter().enumerate() {
                    let d = 3 * nodes[i / 3] + i % 3;
                    r[d] += v;
                    magnitude[d] += v.abs();
                }
                if let (Some(y), Some(v), Some(k)) = (product.as_mut(), apply, k.as_ref()) {
                    let ve: [f64; DOFS] = std::array::from_fn(|i| v[3 * nodes[i / 3] + i % 3]);
                    for p in 0..DOFS {
                        let row = &k[p * DOFS..(p + 1) * DOFS];
                        y[3 * nodes[p / 3] + p % 3] +=
                            row.iter().zip(&ve).map(|(a, b)| a * b).sum::<f64>();
                    }
                }
                if let (Some(vals), Some(k)) = (vals.as_mut(), k) {
                    self.scatter(vals, &nodes, &k);
                }
            }
        };
        let mut pending = None;
        for chunk in self.active.chunks(CHUNK) {
            let last = pending.take();
            let (_, next) = rayon::join(|| last.map(&mut add), || compute(chunk));
            pending = Some(next?);
        }
        if let Some(done) = pending {
            add(done);
        }
        hanging.reduce(&mut r);
        hanging.reduce_magnitude(&mut magnitude);
        if let Some(y) = product.as_mut() {
            hanging.reduce(y);
        }
        Ok(Internal {
            force: r,
            tangent: vals,
            magnitude: magnitude.iter().fold(0.0, |a: f64, b| a.max(*b)),
            product,
        })
    }

    /// Adds an element matrix into the lower-triangle values: the element's free dofs sorted by
    /// row, each column's rows merged with them in one pass (a binary search per entry made the
    /// scatter 1.5 s of a 2 s tangent on the sensor's 333k-dof level, 1.0 s now, and it runs
    /// while the next chunk's element tangents are computed).
    fn scatter(&self, vals: &mut [f64], nodes: &[usize; NODES], k: &[f64]) {
        let dofs = &self.ctx.dofs;
        let nf = dofs.n_free();
        let col_ptr = self.pattern.symbolic.col_ptr();
        let row_idx = self.pattern.symbolic.row_idx();
        if nodes.iter().any(|&n| dofs.hanging.masters(n).is_some()) {
            // Reduced to the free dofs the element acts on through the hanging nodes' masters.
            let (free, kr) = reduced_element(dofs, nodes, k);
            let nr = free.len();
            for (i, &c) in free.iter().enumerate() {
                let (s, t) = (col_ptr[c], col_ptr[c + 1]);
                let rows = &row_idx[s..t];
                let mut at = 0;
                for (j, &r) in free.iter().enumerate().skip(i) {
                    while at < rows.len() && rows[at] < r {
                        at += 1;
                    }
                    if rows.get(at) == Some(&r) {
                        vals[s + at] += kr[j * nr + i];
                    }
                }
            }
            return;
        }
        // (free index, local dof) of the element's free dofs, by free index.
        let mut free = [(0usize, 0usize); DOFS];
        let mut n = 0;
        for p in 0..DOFS {
            let r = dofs.free_index[3 * nodes[p / 3] + p % 3];
            if r < nf {
                free[n] = (r, p);
                n += 1;
            }
        }
        let free = &mut free[..n];
        free.sort_unstable();
        for (i, &(c, q)) in free.iter().enumerate() {
            let (s, t) = (col_ptr[c], col_ptr[c + 1]);
            let rows = &row_idx[s..t];
            // K_e is symmetric (bit for bit): row q read for column q, contiguous.
            let kq = &k[q * DOFS..(q + 1) * DOFS];
            let mut at = 0;
            // Rows r >= c: this column's lower triangle.
            for &(r, p) in &free[i..] {
                while at < rows.len() && rows[at] < r {
                    at += 1;
                }
                if rows.get(at) == Some(&r) {
                    vals[s + at] += kq[p];
                }
            }
        }
    }

    /// Solves one load case by Newton at the full load from a guessed field (`guess` gives the
    /// displacement, m, at an undeformed position, um; e.g. a coarser mesh's solution), falling
    /// back to [`Self::solve`] from the undeformed state if that fails or the model prescribes
    /// displacements. A good guess saves the load steps and most iterations of a refinement
    /// sequence; the answer is the same converged field either way. The stats count both tries.
    pub fn solve_from(
        &self,
        loads: &[SolidLoad],
        guess: impl Fn([f64; 3]) -> Option<[f64; 3]> + Sync,
    ) -> FeResult<TlSolution> {
        let c = &self.ctx;
        if c.dofs.constrained.iter().any(|&(_, v, _)| v != 0.0) {
            return self.solve(loads);
        }
        let f = load_vector(&c.grid, &c.pos_um, &c.dofs, loads, 0)?;
        let mut u = vec![0.0; f.len()];
        // One guess per node (its free dofs are consecutive), the nodes in parallel.
        let mut nodes: Vec<usize> = c.dofs.free_dofs.iter().map(|&d| d / 3).collect();
        nodes.dedup();
        let guesses: Vec<Option<[f64; 3]>> = nodes
            .par_iter()
            .map(|&n| guess(c.pos_um[n]).filter(|g| g.iter().all(|v| v.is_finite())))
            .collect();
        for (&n, g) in nodes.iter().zip(&guesses) {
            if let Some(g) = g {
                for d in 0..3 {
                    if c.dofs.free_index[3 * n + d] < c.dofs.n_free() {
                        u[3 * n + d] = g[d];
                    }
                }
            }
        }
        let mut work = self.work();
        match self.newton(&mut u, &f, 1.0, Start::Guess, &mut None, &mut work) {
            Ok(done) => {
                work.stats.load_steps = 1;
                self.solution(u, &f, work.stats, done)
            }
            Err(_) => {
                work.check(0.0)?;
                let tried = std::mem::take(&mut work.stats);
                let mut fresh = self.stepped(loads, work)?;
                fresh.stats.iterations += tried.iterations;
                fresh.stats.factorisations += tried.factorisations;
                fresh.stats.single_precision += tried.single_precision;
                Ok(fresh)
            }
        }
    }

    /// Solves one load case from the undeformed state, stepping the load (and the prescribed
    /// displacements) up from zero: the step halves when Newton fails (divergence, an inverted
    /// element, a tangent that is not positive definite, too many iterations) and doubles after
    /// a step that converged in at most 4 iterations. Errors ([`FeError::Newton`]) when the step
    /// falls under 1e-4 of the load, after `max_load_steps` tries or once its work passes
    /// [`TlOptions::max_factorisations`].
    pub fn solve(&self, loads: &[SolidLoad]) -> FeResult<TlSolution> {
        self.stepped(loads, self.work())
    }

    /// A solve's work budget ([`TlOptions::max_factorisations`]).
    fn work(&self) -> Work {
        let (len, n) = (self.symbolic.factor_len(), self.n_free_dofs());
        let flops = factorisation_flops(len, n);
        let floor = if flops > 0.0 {
            self.opts.min_budget_flops / flops
        } else {
            f64::INFINITY
        };
        Work {
            stats: NewtonStats::default(),
            used: 0.0,
            limit: self.opts.max_factorisations.max(floor),
            cg_step: (ENTRIES_PER_DOF_PER_STEP * n.max(1)) as f64 / len.max(1) as f64,
            fatal: None,
            double_only: false,
        }
    }

    /// [`Self::solve`] with the work already spent on it.
    fn stepped(&self, loads: &[SolidLoad], mut work: Work) -> FeResult<TlSolution> {
        let c = &self.ctx;
        let f = load_vector(&c.grid, &c.pos_um, &c.dofs, loads, 0)?;
        let mut u = vec![0.0; f.len()];
        let (mut lambda, mut step) = (0.0f64, self.opts.first_step);
        let mut previous: Option<(f64, Vec<f64>)> = None;
        // The last factorised tangent, carried across load steps as the preconditioner.
        let mut lagged: Option<CholeskyFactor> = None;
        let mut tries = 0;
        let mut why = String::new();
        let prescribed = c.dofs.constrained.iter().any(|&(_, v, _)| v != 0.0);
        // Ends with the step that reaches the full load, or an error.
        loop {
            work.check(lambda)?;
            tries += 1;
            if tries > self.opts.max_load_steps {
                return Err(FeError::Newton {
                    detail: format!(
                        "no convergence within {} load steps (reached {:.1} % of the load; last \
                         failure: {why})",
                        self.opts.max_load_steps,
                        100.0 * lambda
                    ),
                    hint: "the solid may buckle or snap at this load: lower the load, allow more \
                           steps or use a finer grid",
                });
            }
            let target = (lambda + step).min(1.0);
            // Predictor: with prescribed displacements the tangent (Euler) step from the last
            // state, which carries their increment into the interior (a prescribed rigid
            // rotation lands on the rigid field); else extrapolation along the last step.
            let predicted = if prescribed {
                self.tangent_predictor(&u, &f, lambda, target, &mut lagged, &mut work)
            } else {
                let mut trial = u.clone();
                if let Some((l0, u0)) = &previous {
                    let s = (target - lambda) / (lambda - l0);
                    for ((t, a), b) in trial.iter_mut().zip(&u).zip(u0) {
                        *t = a + s * (a - b);
                    }
                }
                Ok(trial)
            };
            let step_result = predicted.and_then(|mut trial| {
                self.newton(&mut trial, &f, target, Start::Step, &mut lagged, &mut work)
                    .map(|h| (trial, h))
            });
            match step_result {
                Ok((trial, res)) => {
                    work.stats.load_steps += 1;
                    if target >= 1.0 {
                        return self.solution(trial, &f, work.stats, res);
                    }
                    // At most 4 iterations, then the final residual.
                    let fast = res.history.len() <= 5;
                    previous = Some((lambda, std::mem::replace(&mut u, trial)));
                    lambda = target;
                    if fast {
                        step *= 2.0;
                    }
                }
                Err(w) => {
                    // A budget spent mid-step is that error, not a step to halve.
                    work.check(lambda)?;
                    why = w;
                    step *= 0.5;
                    if step < MIN_STEP {
                        return Err(FeError::Newton {
                            detail: format!(
                                "Newton failed at {:.1} % of the load even with steps of {:.0e} \
                                 ({why})",
                                100.0 * lambda,
                                MIN_STEP
                            ),
                            hint: "the solid may buckle or snap, or an element inverts: lower \
                                   the load or refine the grid where it bends most",
                        });
                    }
                }
            }
        }
    }

    /// The Euler predictor from the converged state `u` at `lambda` to `target`: the constrained
    /// dofs take their new values and the free ones the linearised response,
    /// K_ff du_f = target f_f - f_int,f(u) - (K_T dc)_f with dc the constrained increments (one
    /// factorisation, counted as an iteration).
    fn tangent_predictor(
        &self,
        u: &[f64],
        f: &[f64],
        lambda: f64,
        target: f64,
        lagged: &mut Option<CholeskyFactor>,
        work: &mut Work,
    ) -> Result<Vec<f64>, StepFailure> {
        let dofs = &self.ctx.dofs;
        let mut dc = vec![0.0; u.len()];
        for &(d, v, _) in &dofs.constrained {
            dc[d] = target * v - u[d];
        }
        let at = self.internal(u, true, Some(&dc))?;
        let product = at.product.unwrap_or_default();
        *lagged = None;
        let llt = self
            .symbolic
            .factor(
                SparseColMat::<usize, f64>::new(
                    self.pattern.symbolic.clone(),
                    at.tangent.unwrap_or_default(),
                )
                .as_ref(),
            )
            .map_err(|e| {
                work.factor_failed(
                    e,
                    format!("tangent not positive definite at {lambda:.3} of the load"),
                )
            })?;
        work.factorised();
        work.stats.iterations += 1;
        let rhs: Vec<f64> = dofs
            .free_dofs
            .iter()
            .map(|&d| target * f[d] - at.force[d] - product[d])
            .collect();
        let du = solve_with(&llt, &rhs);
        let mut trial: Vec<f64> = u.iter().zip(&dc).map(|(a, b)| a + b).collect();
        for (i, &d) in dofs.free_dofs.iter().enumerate() {
            trial[d] += du[i];
        }
        if trial.iter().any(|v| !v.is_finite()) {
            return Err("non-finite predictor".into());
        }
        *lagged = Some(llt);
        Ok(trial)
    }

    /// Newton iterations at load factor `lambda` from `u` (constrained dofs already set); the
    /// history of the step and the converged field's internal force on convergence.
    ///
    /// Converged when the largest free residual is under `residual_tol` of the force scale (the
    /// load, the step's first residual and the largest sum of element force magnitudes at a dof,
    /// which sets the residual's round-off) and the correction's energy du . r is under
    /// `energy_tol` of the step's first, or the next one's is under a tenth of that
    /// ([`next_correction_small`]), or it has stopped shrinking under 1e-8 of it; or when the
    /// correction is under 1e-12 of the largest displacement (round-off). The first correction
    /// is solved as exactly as where it starts from asks ([`Start`]), the later ones to
    /// [`forcing`].
    fn newton(
        &self,
        u: &mut [f64],
        f: &[f64],
        lambda: f64,
        from: Start,
        lagged: &mut Option<CholeskyFactor>,
        work: &mut Work,
    ) -> Result<Converged, StepFailure> {
        let dofs = &self.ctx.dofs;
        let residual = |r_int: &[f64]| -> Vec<f64> {
            dofs.free_dofs
                .iter()
                .map(|&d| lambda * f[d] - r_int[d])
                .collect()
        };
        let inf = |r: &[f64]| r.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let mut history = Vec::new();
        let start = self.internal(u, true, None)?;
        let mut r = residual(&start.force);
        let magnitude = start.magnitude;
        let mut vals = start.tangent;
        let load: Vec<f64> = dofs.free_dofs.iter().map(|&d| lambda * f[d]).collect();
        let mut scale = inf(&load).max(inf(&r)).max(magnitude);
        let mut first_energy: Option<f64> = None;
        let mut last_energy = f64::INFINITY;
        // The tangent the last correction was solved with, whether the next correction is
        // solved on it again (the field has moved too little to change it), and the relative
        // residual a last correction needs (only the residual test left).
        let mut last_tangent: Option<Vec<f64>> = None;
        let mut keep_tangent = false;
        let mut last_forcing: Option<f64> = None;
        // The residual (2-norm) the last correction was solved for.
        let mut last_r2: Option<f64> = None;
        for it in 1..=self.opts.max_iterations {
            if work.spent() {
                return Err("the work budget is spent".into());
            }
            let r_inf = inf(&r);
            if !r_inf.is_finite() {
                return Err("non-finite residual".into());
            }
            let kept = last_tangent
                .take()
                .filter(|_| std::mem::take(&mut keep_tangent));
            let values = match (kept, vals.take()) {
                (Some(v), _) | (None, Some(v)) => v,
                (None, None) => self.internal(u, true, None)?.tangent.unwrap_or_default(),
            };
            let r2 = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            let tol = last_forcing
                .take()
                .unwrap_or_else(|| last_r2.map_or(from.tol(), |prev| forcing(r2 / prev)));
            last_r2 = Some(r2);
            let correction = self.correction(&values, &r, lagged, it, work, tol)?;
            last_tangent = Some(values);
            work.stats.iterations += 1;
            let mut energy = 0.0;
            for (i, &d) in dofs.free_dofs.iter().enumerate() {
                let du = correction[i];
                if !du.is_finite() {
                    return Err(format!("non-finite correction at iteration {it}"));
                }
                energy += du * r[i];
                u[d] += du;
            }
            let energy = energy.abs();
            history.push(NewtonIterate {
                residual_n: r_inf,
                energy_j: energy,
            });
            let e0 = *first_energy.get_or_insert(energy);
            let ratio = if e0 > 0.0 { energy / e0 } else { 0.0 };
            if energy > 1e6 * e0 {
                return Err(format!(
                    "diverging at iteration {it} (energy ratio {ratio:.1e})"
                ));
            }
            // Round-off: the correction is at the field's last digits, or it stopped shrinking
            // once already small.
            let du_inf = correction.iter().map(|v| v.abs()).fold(0.0, f64::max);
            let u_inf = u.iter().map(|v| v.abs()).fold(0.0, f64::max);
            let stalled = energy > 1e-2 * last_energy && ratio <= ROUND_OFF_RATIO;
            last_energy = energy;
            // The residual of the corrected field (the tangent only if another step follows).
            let now = self.internal(u, false, None)?;
            r = residual(&now.force);
            scale = scale.max(now.magnitude);
            let r_inf = inf(&r);
            let target = self.opts.residual_tol * scale;
            let small = r_inf <= target;
            // Looked at only once the residual is small or the corrections are (one pair of
            // triangular solves).
            let energy_done = (small || ratio <= POLISH_RATIO)
                && (ratio <= self.opts.energy_tol
                    || stalled
                    || next_correction_small(lagged.as_ref(), &r, e0, self.opts.energy_tol));
            if du_inf <= ROUND_OFF_DISPLACEMENT * u_inf || (small && energy_done) {
                history.push(NewtonIterate {
                    residual_n: r_inf,
                    energy_j: 0.0,
                });
                return Ok(Converged {
                    history,
                    force: now.force,
                });
            }
            // A correction this small leaves the tangent as it was: the next one is solved on
            // it again, by conjugate gradients, to the forcing term ([`forcing`]), or, where
            // only the residual is left, to the reduction that brings it under its tolerance (a
            // tenth of it: Eisenstat & Walker's safeguard against oversolving).
            if ratio <= POLISH_RATIO && self.krylov_budget(r.len()) > 0 && lagged.is_some() {
                keep_tangent = true;
                last_forcing =
                    energy_done.then(|| (0.1 * target / r_inf).clamp(KRYLOV_TOL, FORCING_MAX));
            }
        }
        Err(format!(
            "no convergence in {} iterations (residual {:.2e} N of {scale:.2e} N)",
            self.opts.max_iterations,
            inf(&r)
        ))
    }

    /// The Newton correction du of K_T du = r (free dofs). With the factor of an earlier
    /// tangent at hand (`lagged`: this step's or an earlier one's), conjugate gradients on the
    /// current tangent preconditioned by it: an inexact Newton step (Dembo, Eisenstat &
    /// Steihaug, SIAM J. Numer. Anal. 19 (1982) 400), whose outer iteration converges to the
    /// same residual tolerance; CG stops at `tol` of the residual (2-norm). A fresh
    /// factorisation (replacing `lagged`) when there is none, when full Newton is cheaper or
    /// asked for ([`TlOptions::krylov_iterations`]), or when CG does not reach `tol` within its
    /// budget (the old tangent is too far from the new one). Where CG is the rule, that factor
    /// is in single precision and CG on it solves this correction too (mixed-precision
    /// preconditioning: the outer CG in double precision reaches any tolerance, the factor only
    /// sets its rate); in double, solved directly, where CG is not the rule or single failed.
    fn correction(
        &self,
        values: &[f64],
        r: &[f64],
        lagged: &mut Option<CholeskyFactor>,
        it: usize,
        work: &mut Work,
        tol: f64,
    ) -> Result<Vec<f64>, StepFailure> {
        let budget = self.krylov_budget(r.len());
        // CG on `pre`, its steps counted as work.
        let cg = |pre: &CholeskyFactor, max_it: usize, work: &mut Work| {
            let (du, steps) = self.preconditioned_cg(values, pre, r, max_it, tol);
            work.used += steps as f64 * work.cg_step;
            du
        };
        if budget > 0 {
            if let Some(du) = lagged
                .as_ref()
                .and_then(|pre| cg(pre, budget.min(KRYLOV_MAX), work))
            {
                return Ok(du);
            }
        }
        // Free the old factor before the new one is built (each can take gigabytes).
        *lagged = None;
        let mat = SparseColMatRef::new(self.pattern.symbolic.as_ref(), values);
        // Where corrections are solved by CG anyway, the factor only preconditions: single
        // precision, which takes half the memory and less time (README, "Single-precision
        // preconditioner"); double from the first time that fails.
        if budget > 0 && !work.double_only {
            match self.symbolic.factor_single(mat) {
                Ok(pre) => {
                    work.factorised();
                    work.stats.single_precision += 1;
                    if let Some(du) = cg(&pre, KRYLOV_MAX, work) {
                        *lagged = Some(pre);
                        return Ok(du);
                    }
                    work.double_only = true;
                }
                Err(e @ FeError::OutOfMemory { .. }) => {
                    return Err(
                        work.factor_failed(e, format!("tangent not factorised at iteration {it}"))
                    )
                }
                Err(_) => work.double_only = true,
            }
        }
        let llt = self.symbolic.factor(mat).map_err(|e| {
            work.factor_failed(
                e,
                format!("tangent not positive definite at iteration {it}"),
            )
        })?;
        work.factorised();
        let du = solve_with(&llt, r);
        *lagged = Some(llt);
        Ok(du)
    }

    /// Conjugate-gradient iterations a correction may take before refactorising: the
    /// [`TlOptions::krylov_iterations`] asked for, or as many as one factorisation costs (0, full
    /// Newton, where that is under [`KRYLOV_MIN`]).
    fn krylov_budget(&self, n: usize) -> usize {
        self.opts.krylov_iterations.unwrap_or_else(|| {
            let steps = self.symbolic.factor_len() / (ENTRIES_PER_DOF_PER_STEP * n.max(1));
            if steps >= KRYLOV_MIN {
                steps
            } else {
                0
            }
        })
    }

    /// Preconditioned conjugate gradients (Saad, Iterative Methods for Sparse Linear Systems,
    /// 2nd ed., Alg. 9.1) on the tangent `values` (lower triangle of the pattern) with the
    /// factor `pre` of an earlier tangent, to the residual's 2-norm reduced by `tol`; None when
    /// it does not converge in `max_it` iterations or the tangent is not positive definite
    /// along a search direction; with the steps taken (the solve's work).
    fn preconditioned_cg(
        &self,
        values: &[f64],
        pre: &CholeskyFactor,
        r: &[f64],
        max_it: usize,
        tol: f64,
    ) -> (Option<Vec<f64>>, usize) {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let r0 = dot(r, r).sqrt();
        let mut x = vec![0.0; r.len()];
        if r0 == 0.0 {
            return (Some(x), 0);
        }
        let mut res = r.to_vec();
        let mut z = solve_with(pre, &res);
        let mut p = z.clone();
        let mut rz = dot(&res, &z);
        for k in 0..max_it {
            // A quarter of the budget gone without a quarter of the reduction (in orders of
            // magnitude): the old factor is too stale, refactorising is cheaper.
            if k == max_it / 4 && k > 0 && dot(&res, &res).sqrt() > tol.powf(0.25) * r0 {
                return (None, k);
            }
            let q = self.tangent_times(values, &p);
            let pq = dot(&p, &q);
            if !(pq > 0.0 && rz.is_finite()) {
                return (None, k + 1);
            }
            let alpha = rz / pq;
            for i in 0..x.len() {
                x[i] += alpha * p[i];
                res[i] -= alpha * q[i];
            }
            if dot(&res, &res).sqrt() <= tol * r0 {
                return (x.iter().all(|v| v.is_finite()).then_some(x), k + 1);
            }
            z = solve_with(pre, &res);
            let rz_new = dot(&res, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..p.len() {
                p[i] = z[i] + beta * p[i];
            }
        }
        (None, max_it)
    }

    /// K v for the symmetric tangent stored as its lower triangle on the pattern.
    fn tangent_times(&self, values: &[f64], v: &[f64]) -> Vec<f64> {
        let (cp, ri) = (
            self.pattern.symbolic.col_ptr(),
            self.pattern.symbolic.row_idx(),
        );
        let mut out = vec![0.0; v.len()];
        for j in 0..v.len() {
            let mut acc = 0.0;
            for k in cp[j]..cp[j + 1] {
                let (i, a) = (ri[k], values[k]);
                out[i] += a * v[j];
                if i != j {
                    acc += a * v[i];
                }
            }
            out[j] += acc;
        }
        out
    }

    /// The converged field `u` with its reactions, from the internal force the last convergence
    /// check computed on it (one pass over the elements fewer per solve).
    fn solution(
        &self,
        u: Vec<f64>,
        f: &[f64],
        stats: NewtonStats,
        done: Converged,
    ) -> FeResult<TlSolution> {
        if u.iter().any(|v| !v.is_finite()) {
            return Err(FeError::NonFinite {
                hint: "check material constants and load values for NaN/inf",
            });
        }
        let Converged {
            history,
            force: r_int,
        } = done;
        let mut u = u;
        self.ctx.dofs.hanging.fill(&mut u);
        let reactions = self
            .ctx
            .dofs
            .constrained
            .iter()
            .map(|&(d, _, _)| r_int[d] - f[d])
            .collect();
        let mut applied = [0.0; 3];
        for (d, v) in f.iter().enumerate() {
            applied[d % 3] += v;
        }
        Ok(TlSolution {
            field: SolidSolution::new(self.ctx.clone(), u, reactions, applied),
            stats,
            history,
        })
    }
}

impl TlSolution {
    /// What the solve cost: accepted load steps, Newton iterations, factorisations.
    pub fn stats(&self) -> NewtonStats {
        self.stats
    }

    /// The last load step's iterations, and the converged residual last: the convergence
    /// history.
    pub fn last_step_history(&self) -> &[NewtonIterate] {
        &self.history
    }

    /// The grid solved.
    pub fn grid(&self) -> &HexGrid {
        self.field.grid()
    }

    /// The displacement field as a linear solution (its stresses are the linear C eps, not this
    /// model's: for locating points and reading displacements).
    pub(crate) fn linear_field(&self) -> &SolidSolution {
        &self.field
    }

    /// Undeformed node positions (after the node map), um.
    pub fn node_positions_um(&self) -> &[[f64; 3]] {
        self.field.node_positions_um()
    }

    /// Displacements of every lattice node (3 per node, m).
    pub fn displacements_m(&self) -> &[f64] {
        self.field.displacements_m()
    }

    /// Displacement of lattice node `n`, m.
    pub fn node_displacement_m(&self, n: usize) -> [f64; 3] {
        self.field.node_displacement_m(n)
    }

    /// Displacement (m) of the material point at undeformed position `p_um`; None outside the
    /// active elements.
    pub fn displacement_m(&self, p_um: [f64; 3]) -> Option<[f64; 3]> {
        self.field.displacement_m(p_um)
    }

    /// Displacement (m) at local point `xi` of element (i, j, k); None if void.
    #[track_caller]
    pub fn displacement_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        self.field.displacement_at(element, xi)
    }

    /// Sum of the applied (dead) forces, N.
    pub fn applied_force_n(&self) -> [f64; 3] {
        self.field.applied_force_n()
    }

    /// Reactions per constraint group (f_int - f, N).
    pub fn reactions(&self) -> &[SolidReaction] {
        self.field.reactions()
    }

    /// Reaction of one group, if it exists.
    pub fn reaction_n(&self, group: &str) -> Option<[f64; 3]> {
        self.field.reaction_n(group)
    }

    /// Undeformed position (um) and reaction (N) of every node of a group.
    pub fn nodal_reactions(&self, group: &str) -> Vec<([f64; 3], [f64; 3])> {
        self.field.nodal_reactions(group)
    }

    /// Element nodes (m), material and displacements, or None if void. Panics outside the grid.
    #[track_caller]
    fn element(&self, element: [usize; 3]) -> Option<([[f64; 3]; NODES], usize, [f64; DOFS])> {
        let grid = self.grid();
        let e = grid.element(element);
        let m = grid.material(e)?;
        let nodes = grid.element_nodes(e);
        let u = self.displacements_m();
        Some((
            element_nodes_m(grid, self.node_positions_um(), e),
            usize::from(m),
            std::array::from_fn(|i| u[3 * nodes[i / 3] + i % 3]),
        ))
    }

    /// Green-Lagrange strain (Voigt, engineering shears) at local point `xi` of element
    /// (i, j, k); None if void. Panics outside the grid (misuse).
    #[track_caller]
    pub fn green_lagrange_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        let (x, _, u) = self.element(element)?;
        Some(tl::strain_at(&x, &u, xi, self.field.shear()))
    }

    /// Second Piola-Kirchhoff stress S = C E (Voigt, Pa, undeformed axes) at local point `xi` of
    /// element (i, j, k); None if void. Panics outside the grid (misuse).
    #[track_caller]
    pub fn second_piola_kirchhoff_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        let (x, m, u) = self.element(element)?;
        Some(tl::second_piola_kirchhoff_pa(
            &x,
            self.field.material(m),
            &u,
            xi,
            self.field.shear(),
        ))
    }

    /// First Piola-Kirchhoff (nominal) stress P = F S (Pa, `P[i][J]` force along i per undeformed
    /// area of normal J) at local point `xi` of element (i, j, k); None if void.
    #[track_caller]
    pub fn first_piola_kirchhoff_at(
        &self,
        element: [usize; 3],
        xi: [f64; 3],
    ) -> Option<[[f64; 3]; 3]> {
        let (x, m, u) = self.element(element)?;
        Some(tl::first_piola_kirchhoff_pa(
            &x,
            self.field.material(m),
            &u,
            xi,
            self.field.shear(),
        ))
    }

    /// Cauchy (true) stress F S F^T / det F (Voigt, Pa, fixed axes) at local point `xi` of
    /// element (i, j, k); None if void. Panics outside the grid (misuse).
    #[track_caller]
    pub fn cauchy_stress_at(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 6]> {
        let (x, m, u) = self.element(element)?;
        Some(tl::cauchy_pa(
            &x,
            self.field.material(m),
            &u,
            xi,
            self.field.shear(),
        ))
    }

    /// Deformed position of the material point at local `xi` of element (i, j, k), um.
    #[track_caller]
    pub fn deformed_position_um(&self, element: [usize; 3], xi: [f64; 3]) -> Option<[f64; 3]> {
        let (x, _, _) = self.element(element)?;
        let u = self.displacement_at(element, xi)?;
        let p = hex27::position(&x, xi);
        Some(std::array::from_fn(|d| (p[d] + u[d]) * 1e6))
    }
}

impl SolidProblem {
    /// Solves every load case with the geometrically nonlinear model (each from the undeformed
    /// state, on one symbolic analysis).
    pub fn solve_nonlinear(&self, opts: TlOptions) -> FeResult<Vec<TlSolution>> {
        let model = TlSolid::new(self, opts)?;
        self.load_cases.iter().map(|l| model.solve(l)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::solid::problem::{Axis3, Constraint, NodeSet};
    use crate::fe::solid::{uniform_lines, Elasticity};

    /// The assembled tangent times a vector equals the central difference of the assembled
    /// internal force along it (the element check of `tl` says nothing about the scatter).
    #[test]
    fn assembled_tangent_is_the_force_derivative() {
        tangent_check(false);
    }

    /// The same with a merged brick whose faces carry hanging nodes: the reduced tangent is the
    /// derivative of the reduced force.
    #[test]
    fn assembled_tangent_with_hanging_nodes_is_the_force_derivative() {
        tangent_check(true);
    }

    fn tangent_check(merge: bool) {
        let mut grid = HexGrid::new(
            &uniform_lines(0.0, 1000.0, 5),
            &[0.0, 100.0],
            &[0.0, 50.0, 100.0],
        )
        .unwrap();
        if merge {
            grid.merge([2, 0, 0], [4, 1, 2]).unwrap();
        }
        let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(169e9, 0.3)]);
        p.constraints.push(Constraint::clamp(
            "root",
            NodeSet::Plane {
                axis: Axis3::X,
                at_um: 0.0,
            },
        ));
        let m = TlSolid::new(&p, TlOptions::default()).unwrap();
        let dofs = &m.ctx.dofs;
        // The merged brick's x faces carry the fine cells' mid-height nodes.
        assert_eq!(dofs.hanging.nodes.len(), if merge { 2 * 3 * 2 } else { 0 });
        // A bent, twisted state (free dofs only).
        let mut u = vec![0.0; 3 * m.ctx.pos_um.len()];
        for (n, x) in m.ctx.pos_um.iter().enumerate() {
            let s = x[0] / 1000.0;
            u[3 * n] = -100e-6 * s * s + 1e-6 * (n as f64 * 0.3).sin();
            u[3 * n + 1] = 50e-6 * s * (x[2] - 50.0) / 50.0;
            u[3 * n + 2] = -300e-6 * s * s + 1e-6 * (n as f64 * 0.7).cos();
        }
        for &(d, _, _) in &dofs.constrained {
            u[d] = 0.0;
        }
        let vals = m.internal(&u, true, None).unwrap().tangent.unwrap();
        let nf = dofs.n_free();
        let v: Vec<f64> = (0..nf)
            .map(|i| ((i * 13 % 7) as f64 - 3.0) * 1e-9)
            .collect();
        let (cp, ri) = (m.pattern.symbolic.col_ptr(), m.pattern.symbolic.row_idx());
        let mut kv = vec![0.0; nf];
        for c in 0..nf {
            for k in cp[c]..cp[c + 1] {
                kv[ri[k]] += vals[k] * v[c];
                if ri[k] != c {
                    kv[c] += vals[k] * v[ri[k]];
                }
            }
        }
        let h = 1e-3;
        let shifted = |s: f64| {
            let mut w = u.clone();
            for (i, &d) in dofs.free_dofs.iter().enumerate() {
                w[d] += s * v[i];
            }
            m.internal(&w, false, None).unwrap().force
        };
        let (a, b) = (shifted(h), shifted(-h));
        let scale = kv.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let worst = dofs
            .free_dofs
            .iter()
            .enumerate()
            .map(|(i, &d)| ((a[d] - b[d]) / (2.0 * h) - kv[i]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-7 * scale, "{worst:e} of {scale:e}");
    }
}
