//! Sparse Cholesky through faer's low-level API, so the elimination order can come from the mesh
//! ([`crate::fe::ordering`]) instead of AMD; the symbolic analysis is shared (`Arc`) and reused for
//! every numeric factorisation on the same pattern.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{get_global_parallelism, Conj, MatMut, Par, Side};

use crate::fe::error::{FeError, FeResult};
use crate::fe::memory::Held;

/// Symbolic analysis of a lower-triangle pattern under a given elimination order.
#[derive(Debug, Clone)]
pub struct SymbolicFactor(Arc<SymbolicCholesky<usize>>);

/// Factors with more entries than this (f64s, 160 MB) are factorised on every core whatever the
/// global setting: threads lost on the plate meshes (up to ~5e6 entries, benches/README.md) but win
/// on the solid's dense separators. \[choice\]
pub const THREADED_FACTOR_ENTRIES: usize = 20_000_000;

/// The factor's entries: double precision, or single where the factor only preconditions.
#[derive(Debug, Clone)]
enum Values {
    F64(Vec<f64>),
    F32(Vec<f32>),
}

/// Numeric factor L L^T of a matrix with the analysed pattern.
#[derive(Debug, Clone)]
pub struct CholeskyFactor {
    symbolic: SymbolicFactor,
    values: Values,
    /// The factor's entry in [`crate::fe::memory::LEDGER`] while it lives (large factors).
    _held: Option<Held<'static>>,
}

/// Always supernodal: faer's flop-ratio heuristic picks the scalar simplicial kernel for the plate
/// matrices (4x4 node blocks, ~125 entries per column of L), which ran 10x slower here.
fn params() -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    }
}

impl SymbolicFactor {
    /// Analyse `pattern` (lower triangle) eliminated in the order `fwd` (`fwd[new] = old`).
    /// Panics if `fwd` is not a permutation of the pattern's rows (misuse).
    #[track_caller]
    pub fn new(pattern: SymbolicSparseColMatRef<'_, usize>, fwd: &[usize]) -> FeResult<Self> {
        let n = pattern.nrows();
        let mut inv = vec![usize::MAX; n];
        for (new, &old) in fwd.iter().enumerate() {
            inv[old] = new;
        }
        let perm = PermRef::new_checked(fwd, &inv, n);
        factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            SymmetricOrdering::Custom(perm),
            params(),
        )
        .map(|s| SymbolicFactor(Arc::new(s)))
        .map_err(|e| FeError::Sparse {
            detail: format!("{e:?}"),
            hint: "out of memory or index overflow: use a coarser mesh",
        })
        .and_then(|s| s.ensure_fits().map(|()| s))
    }

    /// Analyse `pattern` (lower triangle) in faer's approximate-minimum-degree order (to compare
    /// with a geometric order).
    pub fn amd(pattern: SymbolicSparseColMatRef<'_, usize>) -> FeResult<Self> {
        factorize_symbolic_cholesky(pattern, Side::Lower, SymmetricOrdering::Amd, params())
            .map(|s| SymbolicFactor(Arc::new(s)))
            .map_err(|e| FeError::Sparse {
                detail: format!("{e:?}"),
                hint: "out of memory or index overflow: use a coarser mesh",
            })
            .and_then(|s| s.ensure_fits().map(|()| s))
    }

    /// The global parallelism, except for factors above [`THREADED_FACTOR_ENTRIES`], which use
    /// every core: the solid rung's 1e8-entry factors ran 1.55x faster on 2 cores (6.3 to 4.1 s).
    fn parallelism(&self) -> Par {
        if self.0.len_val() > THREADED_FACTOR_ENTRIES {
            Par::rayon(0)
        } else {
            get_global_parallelism()
        }
    }

    /// faer's scratch for one numeric factorisation in `T`'s precision.
    fn scratch<T: faer::traits::ComplexField>(&self) -> StackReq {
        self.0
            .factorize_numeric_llt_scratch::<T>(self.parallelism(), Default::default())
    }

    /// Bytes a numeric factorisation allocates: the factor's values and faer's scratch.
    pub fn numeric_bytes(&self) -> u64 {
        self.bytes_with(self.scratch::<f64>())
    }

    fn bytes_with(&self, scratch: StackReq) -> u64 {
        self.values_bytes()
            .saturating_add(scratch.size_bytes() as u64)
    }

    /// Bytes of the factor's values (what stays allocated after the factorisation).
    fn values_bytes(&self) -> u64 {
        (self.0.len_val() as u64).saturating_mul(8)
    }

    /// Refuses a factor that cannot fit in memory beside the factorisations of the run
    /// ([`crate::fe::memory`]); asked after every symbolic analysis, and again, entering the
    /// ledger, before each numeric one, since an overcommitted factor ends in the OOM killer,
    /// not in an error.
    pub fn ensure_fits(&self) -> FeResult<()> {
        crate::fe::memory::ensure_fits(&self.describe(), self.numeric_bytes())
    }

    fn describe(&self) -> String {
        format!("a Cholesky factor of {} entries", self.0.len_val())
    }

    /// Entries of L (the memory the numeric factor takes, in f64s).
    pub fn factor_len(&self) -> usize {
        self.0.len_val()
    }

    /// Numeric factorisation of `mat` (same pattern, lower triangle). A matrix that is not positive
    /// definite is a returned error naming the likely cause, never NaN.
    pub fn factor(&self, mat: SparseColMatRef<'_, usize, f64>) -> FeResult<CholeskyFactor> {
        let scratch = self.scratch::<f64>();
        let reservation = crate::fe::memory::reserve(
            &self.describe(),
            self.bytes_with(scratch),
            self.values_bytes(),
        )?;
        let values = self.numeric(mat, scratch, "")?;
        Ok(CholeskyFactor {
            symbolic: self.clone(),
            values: Values::F64(values),
            _held: reservation.map(|r| r.finished()),
        })
    }

    /// Numeric factorisation of `mat` in single precision, for a factor that only
    /// preconditions: half the memory of [`Self::factor`] (on the sensor's 291 M-entry level
    /// 8.2 s against 11-14 s), its solves accurate to single precision (6e-8) times the
    /// matrix's condition, not to round-off.
    pub fn factor_single(&self, mat: SparseColMatRef<'_, usize, f64>) -> FeResult<CholeskyFactor> {
        let scratch = self.scratch::<f32>();
        let kept = (self.0.len_val() as u64).saturating_mul(4);
        let reservation = crate::fe::memory::reserve(
            &self.describe(),
            kept.saturating_add(scratch.size_bytes() as u64)
                .saturating_add((mat.compute_nnz() as u64).saturating_mul(4)),
            kept,
        )?;
        let single: Vec<f32> = mat.val().iter().map(|&v| v as f32).collect();
        let values = self.numeric(
            SparseColMatRef::new(mat.symbolic(), &single),
            scratch,
            " (single precision)",
        )?;
        Ok(CholeskyFactor {
            symbolic: self.clone(),
            values: Values::F32(values),
            _held: reservation.map(|r| r.finished()),
        })
    }

    /// faer's numeric factorisation in `T`'s precision; `what` ends the error's detail.
    fn numeric<T: faer::traits::ComplexField>(
        &self,
        mat: SparseColMatRef<'_, usize, T>,
        scratch: StackReq,
        what: &str,
    ) -> FeResult<Vec<T>> {
        let mut values = vec![T::zero_impl(); self.0.len_val()];
        let mut mem = MemBuffer::try_new(scratch).map_err(|_| FeError::Sparse {
            detail: "scratch allocation failed".into(),
            hint: "out of memory: use a coarser mesh",
        })?;
        self.0
            .factorize_numeric_llt(
                &mut values,
                mat,
                Side::Lower,
                LltRegularization::default(),
                self.parallelism(),
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| FeError::NotPositiveDefinite {
                detail: format!("{e:?}{what}"),
                hint: "the plate is not fully constrained or has zero stiffness somewhere: check \
                       that supports exist and thicknesses are positive",
            })?;
        Ok(values)
    }
}

impl CholeskyFactor {
    /// Solves A X = B in place for every column of `rhs`.
    pub fn solve_in_place(&self, mut rhs: MatMut<'_, f64>) {
        match &self.values {
            Values::F64(values) => self.solve_as(values, rhs),
            Values::F32(values) => {
                let mut single =
                    faer::Mat::<f32>::from_fn(rhs.nrows(), rhs.ncols(), |i, j| rhs[(i, j)] as f32);
                self.solve_as(values, single.as_mut());
                for j in 0..rhs.ncols() {
                    for i in 0..rhs.nrows() {
                        rhs[(i, j)] = f64::from(single[(i, j)]);
                    }
                }
            }
        }
    }

    /// faer's supernodal solve in `T`'s precision. One right-hand side is solved on one thread:
    /// its triangular sweeps are bound by the factor's memory traffic, and threads only add
    /// their synchronisation (a conjugate-gradient step on the solid's 311M-entry
    /// single-precision factor took 0.32 s threaded, 0.28 s on one thread, on 2 cores).
    fn solve_as<T: faer::traits::ComplexField>(&self, values: &[T], rhs: MatMut<'_, T>) {
        let par = if rhs.ncols() == 1 {
            Par::Seq
        } else {
            self.symbolic.parallelism()
        };
        let s = &self.symbolic.0;
        let mut mem = MemBuffer::new(s.solve_in_place_scratch::<T>(rhs.ncols(), par));
        LltRef::new(s, values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            par,
            MemStack::new(&mut mem),
        );
    }

    /// Whether solves with this factor are exact to double-precision round-off (not a
    /// single-precision preconditioner).
    pub fn is_exact(&self) -> bool {
        matches!(self.values, Values::F64(_))
    }
}

#[cfg(test)]
mod tests {
    use faer::sparse::{SparseColMat, Triplet};
    use faer::Mat;

    use super::*;
    use crate::fe::error::FeError;

    /// The lower triangle of a shifted 5-point Laplacian on an n x n grid (SPD).
    fn laplacian(n: usize) -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let k = j * n + i;
                t.push(Triplet::new(k, k, 4.01));
                if i + 1 < n {
                    t.push(Triplet::new(k + 1, k, -1.0));
                }
                if j + 1 < n {
                    t.push(Triplet::new(k + n, k, -1.0));
                }
            }
        }
        SparseColMat::try_new_from_triplets(n * n, n * n, &t).unwrap()
    }

    /// max |A x - b| / max |b| for the symmetric A stored as its lower triangle.
    fn residual(a: &SparseColMat<usize, f64>, x: &Mat<f64>, b: &[f64]) -> f64 {
        let mut ax = vec![0.0; b.len()];
        let (cp, ri, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
        for j in 0..b.len() {
            for k in cp[j]..cp[j + 1] {
                let i = ri[k];
                ax[i] += v[k] * x[(j, 0)];
                if i != j {
                    ax[j] += v[k] * x[(i, 0)];
                }
            }
        }
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        ax.iter()
            .zip(b)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
            / scale
    }

    #[test]
    fn a_single_precision_factor_solves_to_single_precision() {
        let a = laplacian(30);
        let n = a.nrows();
        let order: Vec<usize> = (0..n).rev().collect();
        let s = SymbolicFactor::new(a.symbolic(), &order).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let solve = |f: &CholeskyFactor| {
            let mut x = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
            f.solve_in_place(x.as_mut());
            residual(&a, &x, &b)
        };
        let double = s.factor(a.as_ref()).unwrap();
        let single = s.factor_single(a.as_ref()).unwrap();
        assert!(double.is_exact() && !single.is_exact());
        let (rd, rs) = (solve(&double), solve(&single));
        assert!(rd < 1e-13, "{rd:e}");
        // Single precision (2^-24 = 6e-8) times the condition number's growth, not round-off.
        assert!(rs > 1e-9 && rs < 1e-5, "{rs:e}");
    }

    #[test]
    fn a_matrix_definite_only_in_double_precision_is_refused_in_single() {
        // 1 - a^2 = 2e-9 in double; a rounds to 1 in single, so the second pivot is 0.
        let a = 1.0 - 1e-9;
        let t = [
            Triplet::new(0, 0, 1.0),
            Triplet::new(1, 0, a),
            Triplet::new(1, 1, 1.0),
        ];
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(2, 2, &t).unwrap();
        let s = SymbolicFactor::new(m.symbolic(), &[0, 1]).unwrap();
        assert!(s.factor(m.as_ref()).is_ok());
        let e = s.factor_single(m.as_ref()).unwrap_err();
        assert!(
            matches!(&e, FeError::NotPositiveDefinite { detail, .. } if detail.contains("single")),
            "{e}"
        );
    }
}
