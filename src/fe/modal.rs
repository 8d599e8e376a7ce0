//! Natural frequencies of the plate: the lowest eigenpairs of K phi = omega^2 M phi by subspace
//! iteration (Bathe, Finite Element Procedures, 2nd ed. 2014, sec. 11.6) on the stiffness already
//! factorised for the static solves ([`Factorised`]) and the consistent mass ([`super::mass`]).
//!
//! Each iteration solves K Xbar = M X for q trial vectors (one multi-column solve with the sparse
//! Cholesky factor), projects K and M onto them (K_r = Xbar^T M X: no product with K is needed),
//! solves the small problem K_r Q = M_r Q Lambda and takes X = Xbar Q. The Ritz vectors are
//! M-orthonormal by construction; the iteration stops when the lowest p eigenvalues change by
//! less than the tolerance. q = p + 8 (Bathe suggests min(2 p, p + 8); the larger subspace costs
//! little here and keeps the rate (lambda_p / lambda_(q+1))^k fast when, as on a long plate, many
//! frequencies crowd above the first).

// Index loops mirror the matrix formulas (Cholesky, triangular solves).
#![allow(clippy::needless_range_loop)]

use faer::{Mat, Side};
use rayon::prelude::*;
use serde::Serialize;

use crate::fe::error::{FeError, FeResult};
use crate::fe::mass::{element_mass, MassModel};
use crate::fe::problem::PlateProblem;
use crate::fe::solve::Factorised;

/// Most modes one analysis may ask for (each costs a trial vector of every free dof).
pub const MAX_MODES: usize = 50;

/// How many modes and how tightly.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModalOptions {
    /// Modes wanted, 1..=[`MAX_MODES`].
    pub modes: usize,
    /// Stop when every wanted eigenvalue omega^2 changes by less than this, relative, between
    /// iterations; in (0, 1).
    pub tol_rel: f64,
    /// Iterations before giving up with [`FeError::Eigen`].
    pub max_iterations: usize,
}

impl Default for ModalOptions {
    /// Four modes; eigenvalues to 1e-10 (frequencies to ~5e-11, well above round-off in the
    /// Rayleigh quotients), 200 iterations.
    fn default() -> Self {
        ModalOptions {
            modes: 4,
            tol_rel: 1e-10,
            max_iterations: 200,
        }
    }
}

/// One natural mode.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// f = omega / (2 pi), Hz.
    pub freq_hz: f64,
    /// omega^2, rad^2/s^2.
    pub eigenvalue: f64,
    /// ||K phi - omega^2 M phi|| / ||K phi|| over the free dofs: how well the pair solves the
    /// discrete problem (not the discretisation error).
    pub residual: f64,
    /// The shape on every global dof (4 per node, constrained dofs zero), normalised so that
    /// phi^T M phi = 1.
    #[serde(skip)]
    pub shape: Vec<f64>,
}

/// The lowest modes, ascending in frequency, and what finding them cost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Modes {
    pub modes: Vec<Mode>,
    pub iterations: usize,
    /// Trial vectors q.
    pub subspace: usize,
    pub free_dofs: usize,
}

/// beta L of the first mode of a clamped-clamped beam: the root of cos x cosh x = 1 near 4.73
/// (Euler-Bernoulli; Blevins, Formulas for Natural Frequency and Mode Shape, Table 8-1: 4.73004),
/// by bisection, so the reference frequency (beta L)^2 / L^2 sqrt(EI / (rho A)) the plate is
/// checked against is computed, not copied.
pub fn clamped_clamped_beta_l() -> f64 {
    let g = |x: f64| x.cos() * x.cosh() - 1.0;
    let (mut lo, mut hi) = (4.0f64, 5.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Factorises the problem's stiffness and finds its lowest modes with the mass `mass`.
#[track_caller]
pub fn natural_frequencies(
    problem: &PlateProblem,
    mass: MassModel,
    opts: ModalOptions,
) -> FeResult<Modes> {
    Factorised::new(problem)?.modes(mass, opts)
}

impl Factorised {
    /// The lowest `opts.modes` natural modes of this plate with the areal mass of `mass` (the
    /// supports as constrained for the static solve, prescribed values taken as zero). Panics on
    /// options out of range (misuse); a problem with fewer free dofs than modes, or an iteration
    /// that does not converge, is an error.
    #[track_caller]
    pub fn modes(&self, mass: MassModel, opts: ModalOptions) -> FeResult<Modes> {
        assert!(
            (1..=MAX_MODES).contains(&opts.modes),
            "modes must be in 1..={MAX_MODES}"
        );
        assert!(
            opts.tol_rel > 0.0 && opts.tol_rel < 1.0 && opts.max_iterations >= 1,
            "tol_rel in (0, 1) and at least one iteration"
        );
        let ctx = self.context();
        let dofs = self.dof_map();
        let mesh = &ctx.mesh;
        let n = dofs.n_free();
        let p = opts.modes;
        if n < p {
            return Err(FeError::Eigen {
                detail: format!("{p} modes asked of a plate with {n} free dofs"),
                hint: "use a finer mesh or ask for fewer modes",
            });
        }
        let q = (p + 8).min(n);
        let mel = element_mass(mesh, &ctx.thickness_um, mass)?;
        let kel = self.element_stiffness();
        let global = |x: &[f64]| {
            let mut g = vec![0.0; dofs.n_dofs];
            for (i, &d) in dofs.free_dofs.iter().enumerate() {
                g[d] = x[i];
            }
            g
        };
        let gather = |g: Vec<f64>| -> Vec<f64> { dofs.free_dofs.iter().map(|&d| g[d]).collect() };
        let m_times = |x: &Vec<f64>| gather(mel.apply(mesh, &global(x)));
        let (x0, y0, x1, y1) = mesh.bounds_um();
        let size_m = (x1 - x0).max(y1 - y0) * 1e-6;
        let mut x = start_vectors(&dofs.free_dofs, q, size_m);
        let mut mx: Vec<Vec<f64>> = x.par_iter().map(m_times).collect();
        let mut previous: Option<Vec<f64>> = None;
        for iteration in 1..=opts.max_iterations {
            let mut rhs = Mat::from_fn(n, q, |i, c| mx[c][i]);
            self.solve_free_in_place(rhs.as_mut());
            let xb: Vec<Vec<f64>> = (0..q)
                .map(|c| (0..n).map(|i| rhs[(i, c)]).collect())
                .collect();
            let mxb: Vec<Vec<f64>> = xb.par_iter().map(m_times).collect();
            let kr = gram(&xb, &mx);
            let mr = gram(&xb, &mxb);
            let (lambda, qm) = ritz(&kr, &mr)?;
            x = combine(&xb, &qm);
            mx = combine(&mxb, &qm);
            let converged = previous.as_ref().is_some_and(|prev| {
                (0..p).all(|i| (lambda[i] - prev[i]).abs() <= opts.tol_rel * lambda[i].abs())
            });
            if converged {
                let modes = (0..p)
                    .map(|i| {
                        let kx = gather(kel.apply(mesh, &global(&x[i])));
                        let r: f64 = kx
                            .iter()
                            .zip(&mx[i])
                            .map(|(k, m)| (k - lambda[i] * m).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        let norm = kx.iter().map(|v| v * v).sum::<f64>().sqrt();
                        Mode {
                            freq_hz: lambda[i].sqrt() / (2.0 * std::f64::consts::PI),
                            eigenvalue: lambda[i],
                            residual: r / norm,
                            shape: global(&x[i]),
                        }
                    })
                    .collect();
                return Ok(Modes {
                    modes,
                    iterations: iteration,
                    subspace: q,
                    free_dofs: n,
                });
            }
            previous = Some(lambda);
        }
        Err(FeError::Eigen {
            detail: format!(
                "the lowest {p} eigenvalues still change by more than {:.0e} after {} iterations",
                opts.tol_rel, opts.max_iterations
            ),
            hint: "raise the tolerance or the iteration limit; nearly equal frequencies converge \
                   slowly",
        })
    }
}

/// Trial vectors: deterministic pseudo-random values (splitmix64) on every free dof, the slopes
/// scaled by 1 / `size_m` and the twists by 1 / `size_m`^2 so each dof kind carries a comparable
/// displacement, plus a uniform translation of the w dofs in the first (it excites the
/// fundamental mode of any supported plate).
fn start_vectors(free_dofs: &[usize], q: usize, size_m: f64) -> Vec<Vec<f64>> {
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..q)
        .map(|c| {
            free_dofs
                .iter()
                .map(|&d| {
                    let r = next();
                    match d % 4 {
                        0 if c == 0 => 1.0 + 0.1 * r,
                        0 => r,
                        3 => r / (size_m * size_m),
                        _ => r / size_m,
                    }
                })
                .collect()
        })
        .collect()
}

/// The symmetric q x q matrix a_i . b_j, symmetrised (row-major).
fn gram(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let q = a.len();
    let mut g = vec![vec![0.0; q]; q];
    for i in 0..q {
        for j in 0..q {
            g[i][j] = a[i].iter().zip(&b[j]).map(|(u, v)| u * v).sum();
        }
    }
    for i in 0..q {
        for j in 0..i {
            let s = 0.5 * (g[i][j] + g[j][i]);
            g[i][j] = s;
            g[j][i] = s;
        }
    }
    g
}

/// Columns sum_k v_k Q_kj.
fn combine(v: &[Vec<f64>], q: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = v[0].len();
    (0..q.len())
        .map(|j| {
            let mut out = vec![0.0; n];
            for (k, vk) in v.iter().enumerate() {
                let c = q[k][j];
                out.iter_mut().zip(vk).for_each(|(o, x)| *o += c * x);
            }
            out
        })
        .collect()
}

/// The reduced problem K_r Q = M_r Q Lambda ([`definite_eigen`]), every eigenvalue positive.
fn ritz(kr: &[Vec<f64>], mr: &[Vec<f64>]) -> FeResult<(Vec<f64>, Vec<Vec<f64>>)> {
    let (lambda, qm) = definite_eigen(kr, mr).map_err(|e| match e {
        DefiniteEigenError::NotDefinite => FeError::Eigen {
            detail: "the trial vectors became linearly dependent".into(),
            hint: "ask for fewer modes than the plate has free dofs",
        },
        DefiniteEigenError::Solver(detail) => FeError::Eigen {
            detail,
            hint: "check the plate's material, thickness and density for extreme values",
        },
    })?;
    if lambda.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(FeError::Eigen {
            detail: "a Ritz eigenvalue is not positive".into(),
            hint: "the plate must be supported: a free plate has zero-frequency rigid modes",
        });
    }
    Ok((lambda, qm))
}

/// Why [`definite_eigen`] failed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum DefiniteEigenError {
    /// B is not positive definite.
    NotDefinite,
    /// The dense symmetric eigen solver failed (its message).
    Solver(String),
}

/// The symmetric-definite eigenproblem A Q = B Q Lambda (B positive definite): B = L L^T
/// (Cholesky), C = L^-1 A L^-T is symmetric with eigenvectors U, Q = L^-T U (so Q^T B Q = I
/// and Q^T A Q = Lambda; Golub & Van Loan, sec. 8.7.2). Eigenvalues ascending, of any sign;
/// `Q[k][j]` is row k of column j.
pub(crate) fn definite_eigen(
    a: &[Vec<f64>],
    b: &[Vec<f64>],
) -> Result<(Vec<f64>, Vec<Vec<f64>>), DefiniteEigenError> {
    let q = a.len();
    let mut l = vec![vec![0.0; q]; q];
    for j in 0..q {
        let d = b[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if !(d > 0.0 && d.is_finite()) {
            return Err(DefiniteEigenError::NotDefinite);
        }
        l[j][j] = d.sqrt();
        for i in j + 1..q {
            l[i][j] = (b[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    let forward = |v: &[f64]| {
        let mut y = vec![0.0; q];
        for i in 0..q {
            y[i] = (v[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
        }
        y
    };
    // Z = L^-1 A column by column; A symmetric, so column c is row c.
    let z: Vec<Vec<f64>> = (0..q).map(|c| forward(&a[c])).collect(); // z[c] = column c
                                                                     // C = L^-1 Z^T: column c of C is L^-1 (row c of Z).
    let c_cols: Vec<Vec<f64>> = (0..q)
        .map(|c| forward(&(0..q).map(|k| z[k][c]).collect::<Vec<_>>()))
        .collect();
    let c = Mat::from_fn(q, q, |i, j| 0.5 * (c_cols[j][i] + c_cols[i][j]));
    let eig = c.self_adjoint_eigen(Side::Lower).map_err(|e| {
        DefiniteEigenError::Solver(format!("the reduced eigenproblem failed: {e:?}"))
    })?;
    let (u, s) = (eig.U(), eig.S().column_vector());
    let lambda: Vec<f64> = (0..q).map(|i| s[i]).collect();
    // Q = L^-T U by back substitution per column.
    let mut qm = vec![vec![0.0; q]; q];
    for j in 0..q {
        for i in (0..q).rev() {
            let s: f64 = (i + 1..q).map(|k| l[k][i] * qm[k][j]).sum();
            qm[i][j] = (u[(i, j)] - s) / l[i][i];
        }
    }
    Ok((lambda, qm))
}
