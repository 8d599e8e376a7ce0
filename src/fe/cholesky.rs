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

/// Numeric factor L L^T of a matrix with the analysed pattern.
#[derive(Debug, Clone)]
pub struct CholeskyFactor {
    symbolic: SymbolicFactor,
    values: Vec<f64>,
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

    /// faer's scratch for one numeric factorisation.
    fn scratch(&self) -> StackReq {
        self.0
            .factorize_numeric_llt_scratch::<f64>(self.parallelism(), Default::default())
    }

    /// Bytes a numeric factorisation allocates: the factor's values and faer's scratch.
    pub fn numeric_bytes(&self) -> u64 {
        self.bytes_with(self.scratch())
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
        let par = self.parallelism();
        let scratch = self.scratch();
        let reservation = crate::fe::memory::reserve(
            &self.describe(),
            self.bytes_with(scratch),
            self.values_bytes(),
        )?;
        let mut values = vec![0.0; self.0.len_val()];
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
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| FeError::NotPositiveDefinite {
                detail: format!("{e:?}"),
                hint: "the plate is not fully constrained or has zero stiffness somewhere: check \
                       that supports exist and thicknesses are positive",
            })?;
        drop(mem);
        Ok(CholeskyFactor {
            symbolic: self.clone(),
            values,
            _held: reservation.map(|r| r.finished()),
        })
    }
}

impl CholeskyFactor {
    /// Solves A X = B in place for every column of `rhs`.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        let par = self.symbolic.parallelism();
        let s = &self.symbolic.0;
        let mut mem = MemBuffer::new(s.solve_in_place_scratch::<f64>(rhs.ncols(), par));
        LltRef::new(s, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            par,
            MemStack::new(&mut mem),
        );
    }
}
