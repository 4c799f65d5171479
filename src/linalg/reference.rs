//! The reference implementation: faer's own sparse LU and Cholesky factorizations with their
//! generic solves ([`FaerLu`], [`FaerLlt`]), which the tuned ones ([`super::SparseLu`],
//! [`super::SparseLlt`]) are checked and timed against (the unit tests of `linalg`,
//! `tests/factor.rs`, `benches/step.rs`). The solver does not use them.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par, Side};

use super::solver::{factorization_by_counts, Counts};
use super::{LinalgError, Pattern};

fn symbolic_error(e: faer::sparse::FaerError) -> LinalgError {
    LinalgError::Symbolic(format!("{e:?}"))
}

/// faer's own sparse LU (its COLAMD ordering, its supernodal or simplicial numeric LU and
/// its generic solve), with its solve scratch; the symbolic analysis behind an [`Arc`],
/// shared by [`FaerLu::with_values`].
pub struct FaerLu {
    n: usize,
    symbolic: Arc<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
    counts: Counts,
}

impl std::fmt::Debug for FaerLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaerLu").field("n", &self.n).finish()
    }
}

impl FaerLu {
    /// Analyses `pattern` and factors `values` on it.
    ///
    /// # Errors
    /// [`LinalgError`] when faer cannot analyse or factor the matrix.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let symbolic =
            factorize_symbolic_lu(pattern.as_ref(), Default::default()).map_err(symbolic_error)?;
        Self::on(Arc::new(symbolic), Counts::analysed(), pattern, values)
    }

    /// A factorization of `values` on the analysis `symbolic`.
    fn on(
        symbolic: Arc<SymbolicLu<usize>>,
        counts: Counts,
        pattern: &Pattern,
        values: &[f64],
    ) -> Result<Self, LinalgError> {
        let mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mut lu = Self {
            n: pattern.nrows(),
            symbolic,
            numeric: NumericLu::new(),
            mem,
            counts,
        };
        lu.refactor(pattern, values)?;
        Ok(lu)
    }

    /// Factors new `values` on the same pattern and analysis.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        let mut mem = MemBuffer::new(
            self.symbolic
                .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                SparseColMatRef::new(pattern.as_ref(), values),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        self.counts.factorizations += 1;
        Ok(())
    }

    /// A second factorization, of `values` on the same pattern, sharing this analysis.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::on(
            Arc::clone(&self.symbolic),
            Counts::default(),
            pattern,
            values,
        )
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// `rhs <- A^{-1} rhs`.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, self.n, 1),
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}

/// faer's own sparse Cholesky factorization `A = L L^T` of a symmetric positive definite
/// matrix (its AMD ordering, its choice of supernodal or simplicial factor, its generic
/// solve; only the upper triangle is read); the symbolic analysis behind an [`Arc`], shared
/// by [`FaerLlt::with_values`].
pub struct FaerLlt {
    n: usize,
    symbolic: Arc<SymbolicCholesky<usize>>,
    numeric: Vec<f64>,
    mem: MemBuffer,
    counts: Counts,
}

impl std::fmt::Debug for FaerLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaerLlt").field("n", &self.n).finish()
    }
}

impl FaerLlt {
    /// Analyses `pattern` and factors `values` on it.
    ///
    /// # Errors
    /// [`LinalgError`] when the analysis fails or the matrix is not positive definite.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            Default::default(),
            Default::default(),
        )
        .map_err(symbolic_error)?;
        Self::on(Arc::new(symbolic), Counts::analysed(), pattern, values)
    }

    /// A factorization of `values` on the analysis `symbolic`.
    fn on(
        symbolic: Arc<SymbolicCholesky<usize>>,
        counts: Counts,
        pattern: &Pattern,
        values: &[f64],
    ) -> Result<Self, LinalgError> {
        let mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mut llt = Self {
            n: pattern.nrows(),
            numeric: vec![0.0; symbolic.len_val()],
            symbolic,
            mem,
            counts,
        };
        llt.refactor(pattern, values)?;
        Ok(llt)
    }

    /// Factors new `values` on the same pattern and analysis.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        let mut mem = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.numeric,
                SparseColMatRef::new(pattern.as_ref(), values),
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        self.counts.factorizations += 1;
        Ok(())
    }

    /// A second factorization, of `values` on the same pattern, sharing this analysis.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::on(
            Arc::clone(&self.symbolic),
            Counts::default(),
            pattern,
            values,
        )
    }

    /// Stored entries of `L`.
    pub fn factor_nnz(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// `rhs <- A^{-1} rhs`.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        LltRef::new(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, self.n, 1),
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}

factorization_by_counts!(FaerLu, FaerLu::new);
factorization_by_counts!(FaerLlt, FaerLlt::new);
