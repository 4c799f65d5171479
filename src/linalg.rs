//! Sparse linear algebra on one sparsity pattern: matrix-vector products and a sparse LU
//! factorization (faer) whose symbolic analysis is done once and whose solve uses scratch
//! memory allocated once, so that the time loop does not allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::Side;
use faer::{Conj, MatMut, Par};

/// Errors of the linear algebra layer.
#[derive(Debug, thiserror::Error)]
pub enum LinalgError {
    /// The symbolic analysis failed (out of memory, bad pattern).
    #[error("sparse LU analysis failed: {0}")]
    Symbolic(String),
    /// The numeric factorization failed: the matrix is singular.
    #[error("the system matrix is singular (sparse LU failed: {0}); check the supports")]
    Singular(String),
}

/// A square sparse pattern in compressed sparse column form (faer's symbolic matrix).
pub type Pattern = SymbolicSparseColMat<usize>;

/// Replaces the rows and columns of the `fixed` dofs by those of the identity (Dirichlet
/// conditions imposed on a matrix sharing `pattern`; the right-hand side is lifted by the
/// caller).
pub fn set_identity_rows(pattern: &Pattern, values: &mut [f64], fixed: &[bool]) {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if fixed[i] || fixed[j] {
                values[p] = if i == j { 1.0 } else { 0.0 };
            }
        }
    }
}

/// `y = A x` for a CSC matrix given by its pattern and values (overwrites `y`).
pub fn spmv_into(pattern: &Pattern, values: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    spmv_add(pattern, values, 1.0, x, y);
}

/// `y += s A x` for a CSC matrix.
pub fn spmv_add(pattern: &Pattern, values: &[f64], s: f64, x: &[f64], y: &mut [f64]) {
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    for (j, &xj) in x.iter().enumerate() {
        if xj == 0.0 {
            continue;
        }
        let sx = s * xj;
        for p in col_ptr[j]..col_ptr[j + 1] {
            y[row_idx[p]] += values[p] * sx;
        }
    }
}

/// `x^T A x` for a CSC matrix.
pub fn quadratic_form(pattern: &Pattern, values: &[f64], x: &[f64]) -> f64 {
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    let mut s = 0.0;
    for (j, &xj) in x.iter().enumerate() {
        if xj == 0.0 {
            continue;
        }
        let mut c = 0.0;
        for p in col_ptr[j]..col_ptr[j + 1] {
            c += values[p] * x[row_idx[p]];
        }
        s += c * xj;
    }
    s
}

/// Sparse LU factorization `P A Q = L U` with the symbolic part computed once.
///
/// [`SparseLu::refactor`] reuses the symbolic analysis for new values on the same pattern;
/// [`SparseLu::solve_in_place`] reuses scratch memory allocated at construction.
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    solve_scratch: MemBuffer,
    n: usize,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu").field("n", &self.n).finish()
    }
}

impl SparseLu {
    /// Analyses the pattern and factors the matrix.
    ///
    /// # Errors
    /// [`LinalgError`] when the analysis fails or the matrix is singular.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .map_err(|e| LinalgError::Symbolic(format!("{e:?}")))?;
        let solve_scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mut lu = Self {
            symbolic,
            numeric: NumericLu::new(),
            solve_scratch,
            n: pattern.nrows(),
        };
        lu.refactor(pattern, values)?;
        Ok(lu)
    }

    /// A second numeric factorization of `values` on this one's symbolic analysis (the same
    /// pattern; no new ordering).
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let mut lu = Self {
            symbolic: self.symbolic.clone(),
            numeric: NumericLu::new(),
            solve_scratch: MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
            n: self.n,
        };
        lu.refactor(pattern, values)?;
        Ok(lu)
    }

    /// Numeric factorization of new values on the pattern analysed in [`SparseLu::new`].
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        let mat = SparseColMatRef::new(pattern.as_ref(), values);
        let mut scratch = MemBuffer::new(
            self.symbolic
                .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                mat,
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        Ok(())
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Solves `A x = rhs` in place, without allocating.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let m = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        lu.solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
    }
}

/// Sparse Cholesky factorization `A = L L^T` of a symmetric positive definite matrix (only
/// the upper triangle is read), symbolic analysis (AMD ordering) once, solve without
/// allocation.
pub struct SparseLlt {
    symbolic: SymbolicCholesky<usize>,
    numeric: Vec<f64>,
    solve_scratch: MemBuffer,
    n: usize,
}

impl std::fmt::Debug for SparseLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLlt").field("n", &self.n).finish()
    }
}

impl SparseLlt {
    /// Analyses and factors.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            Default::default(),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold:
                    faer::sparse::linalg::SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .map_err(|e| LinalgError::Symbolic(format!("{e:?}")))?;
        let solve_scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let mut numeric = vec![0.0; symbolic.len_val()];
        let mat = SparseColMatRef::new(pattern.as_ref(), values);
        let mut scratch = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut numeric,
                mat,
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            numeric,
            solve_scratch,
            n: pattern.nrows(),
        })
    }

    /// Number of stored values of the factor.
    pub fn factor_nnz(&self) -> usize {
        self.numeric.len()
    }

    /// Solves `A x = rhs` in place, without allocating.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.numeric);
        let m = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        llt.solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
    }
}
