//! The solver behind one trait ([`Factorization`]): factor on a pattern, refactor new values
//! on the same symbolic analysis, solve in place without allocating, and count the symbolic
//! analyses and numeric factorizations made. [`Factor`] is the step matrices' factor: the
//! tuned LU or Cholesky.

use super::{is_symmetric, Ordering, Pattern, SparseLlt, SparseLu};

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

/// A sparse direct solver of `A x = b` for the matrices of one sparsity pattern.
///
/// Its work splits in two: a symbolic analysis of the pattern (the fill-reducing ordering
/// and, for Cholesky, the elimination tree and the structure of the factor), made once, and
/// a numeric factorization of each matrix on that pattern. The step matrix
/// `A = M + alpha h C + alpha^2 h^2/2 K` (paper Eq. 18; [`crate::time::step`]) keeps the pattern of `M`,
/// `C` and `K` for every step length `h`: another `h` (the subdivision's contact events) is a
/// numeric factorization on the run's one analysis ([`Factorization::refactor`],
/// [`Factorization::with_values`]). The solve runs in place on memory allocated when
/// factoring, so that the time loop does not allocate.
///
/// The counts are kept by the factorization itself, where the work is done:
/// [`Factorization::symbolic_analyses`] is 1 for one made by [`Factorization::factor`] and
/// 0 for one made by [`Factorization::with_values`] (which shares the analysis), and every
/// successful numeric factorization adds one to [`Factorization::numeric_factorizations`].
///
/// Implementations: the reference, faer's own factorizations and solves
/// ([`super::FaerLu`], [`super::FaerLlt`]), and the tuned ones ([`SparseLu`], [`SparseLlt`]
/// and [`Factor`], their compact rows, dense supernodes and two-part split), checked
/// against the reference (the tests of this module, `tests/factor.rs`).
pub trait Factorization: Sized {
    /// Analyses `pattern` and factors `values` on it.
    ///
    /// # Errors
    /// [`LinalgError`] when the analysis fails or the matrix cannot be factored (singular;
    /// for a Cholesky factorization, not positive definite).
    fn factor(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError>;

    /// Factors new `values` on the same `pattern`, on the existing symbolic analysis.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix cannot be factored.
    fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError>;

    /// A second factorization, of `values` on the same `pattern`, sharing this one's
    /// symbolic analysis (none of its own).
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix cannot be factored.
    fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError>;

    /// `rhs <- A^{-1} rhs`, without allocating.
    fn solve_in_place(&mut self, rhs: &mut [f64]);

    /// Order of the matrix.
    fn n(&self) -> usize;

    /// Symbolic analyses this factorization made (1 from [`Factorization::factor`], 0 from
    /// [`Factorization::with_values`]; never more from [`Factorization::refactor`]).
    fn symbolic_analyses(&self) -> usize;

    /// Numeric factorizations this factorization made, the first one included.
    fn numeric_factorizations(&self) -> usize;
}

/// The counts of a [`Factorization`]: symbolic analyses and numeric factorizations made.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Counts {
    /// Symbolic analyses made.
    pub(super) analyses: usize,
    /// Numeric factorizations made.
    pub(super) factorizations: usize,
}

impl Counts {
    /// The counts of a factorization that made its own analysis and no numeric factorization
    /// yet.
    pub(super) fn analysed() -> Self {
        Self {
            analyses: 1,
            factorizations: 0,
        }
    }
}

/// [`Factorization`] for a type with inherent `refactor`, `with_values`, `solve_in_place`
/// and `n` and a field `counts` ([`Counts`]), factored by `$factor`.
macro_rules! factorization_by_counts {
    ($t:ty, $factor:expr) => {
        impl $crate::linalg::Factorization for $t {
            fn factor(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
                $factor(pattern, values)
            }
            fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
                <$t>::refactor(self, pattern, values)
            }
            fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
                <$t>::with_values(self, pattern, values)
            }
            fn solve_in_place(&mut self, rhs: &mut [f64]) {
                <$t>::solve_in_place(self, rhs)
            }
            fn n(&self) -> usize {
                <$t>::n(self)
            }
            fn symbolic_analyses(&self) -> usize {
                self.counts.analyses
            }
            fn numeric_factorizations(&self) -> usize {
                self.counts.factorizations
            }
        }
    };
}
pub(super) use factorization_by_counts;

factorization_by_counts!(SparseLu, SparseLu::new);
factorization_by_counts!(SparseLlt, SparseLlt::new);

/// The step matrices' factor: [`Factorization::factor`] is [`Factor::auto`].
impl Factorization for Factor {
    fn factor(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Factor::auto(pattern, values)
    }
    fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        Factor::refactor(self, pattern, values)
    }
    fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Factor::with_values(self, pattern, values)
    }
    fn solve_in_place(&mut self, rhs: &mut [f64]) {
        Factor::solve_in_place(self, rhs)
    }
    fn n(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.n(),
            Factor::Llt(llt) => llt.n(),
            Factor::FaerLu(f) => f.n(),
            Factor::FaerLlt(f) => f.n(),
        }
    }
    fn symbolic_analyses(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.counts.analyses,
            Factor::Llt(llt) => llt.counts.analyses,
            Factor::FaerLu(f) => Factorization::symbolic_analyses(&**f),
            Factor::FaerLlt(f) => Factorization::symbolic_analyses(&**f),
        }
    }
    fn numeric_factorizations(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.counts.factorizations,
            Factor::Llt(llt) => llt.counts.factorizations,
            Factor::FaerLu(f) => Factorization::numeric_factorizations(&**f),
            Factor::FaerLlt(f) => Factorization::numeric_factorizations(&**f),
        }
    }
}

/// Whose factorizations and solves a run's step matrices get: softway's tuned kernels (the
/// default) or faer's own sparse LU and Cholesky with their generic solves, the reference
/// they are checked and timed against ([`super::reference`]; `softway run --solver faer`).
/// The two give the same answers to rounding (not the same bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    /// softway's factors and solves (`src/linalg/lu.rs`, `llt.rs`, `split/`).
    #[default]
    Softway,
    /// faer's ([`super::FaerLu`], [`super::FaerLlt`]).
    Faer,
}

impl Backend {
    /// The name on the command line and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Softway => "softway",
            Backend::Faer => "faer",
        }
    }
}

impl std::str::FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "softway" => Ok(Backend::Softway),
            "faer" => Ok(Backend::Faer),
            other => Err(format!(
                "unknown solver \"{other}\": allowed \"softway\" (the default, the tuned kernels) or \"faer\" (faer's own factorizations, the reference)"
            )),
        }
    }
}

/// Which factorization a step matrix gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorKind {
    /// LU with partial pivoting and the given column ordering (the reference: any matrix).
    Lu(Ordering),
    /// Cholesky `L L^T` (the ordering of [`Ordering::auto`]: AMD, nested dissection on a
    /// large 3D mesh): symmetric positive definite matrices only.
    Llt,
    /// faer's LU ([`Backend::Faer`]).
    FaerLu,
    /// faer's Cholesky ([`Backend::Faer`]).
    FaerLlt,
}

/// A factored step matrix: LU (the reference) or Cholesky.
// One or two per stepper: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug)]
pub enum Factor {
    /// LU.
    Lu(SparseLu),
    /// Cholesky.
    Llt(SparseLlt),
    /// faer's LU ([`Backend::Faer`]).
    FaerLu(Box<super::FaerLu>),
    /// faer's Cholesky ([`Backend::Faer`]).
    FaerLlt(Box<super::FaerLlt>),
}

impl Factor {
    /// Factors `values` on `pattern` as `kind` says.
    ///
    /// # Errors
    /// [`LinalgError`] when the matrix is singular (or, for [`FactorKind::Llt`], not
    /// positive definite).
    pub fn new(pattern: &Pattern, values: &[f64], kind: FactorKind) -> Result<Self, LinalgError> {
        Ok(match kind {
            FactorKind::Lu(o) => Factor::Lu(SparseLu::with_ordering(pattern, values, o)?),
            FactorKind::Llt => Factor::Llt(SparseLlt::new(pattern, values)?),
            FactorKind::FaerLu => Factor::FaerLu(Box::new(super::FaerLu::new(pattern, values)?)),
            FactorKind::FaerLlt => Factor::FaerLlt(Box::new(super::FaerLlt::new(pattern, values)?)),
        })
    }

    /// A Cholesky factor where the matrix is symmetric (to 1e-14 of its largest entry) and
    /// positive definite, else an LU (AMD): the Cholesky halves the factor and, from 10,000
    /// dofs on, runs on faer's supernodal kernels (the 192-ring disk's stiffness in seconds
    /// where the LU takes about a minute).
    ///
    /// # Errors
    /// [`LinalgError`] when the matrix is singular.
    pub fn auto(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::auto_on(Backend::Softway, pattern, values)
    }

    /// [`Factor::auto`] by `backend`'s factorizations: on faer's, its Cholesky where the
    /// matrix is symmetric and positive definite, else its LU.
    ///
    /// # Errors
    /// [`LinalgError`] when the matrix is singular.
    pub fn auto_on(
        backend: Backend,
        pattern: &Pattern,
        values: &[f64],
    ) -> Result<Self, LinalgError> {
        let (llt, lu) = match backend {
            Backend::Softway => (FactorKind::Llt, FactorKind::Lu(Ordering::auto(pattern))),
            Backend::Faer => (FactorKind::FaerLlt, FactorKind::FaerLu),
        };
        if is_symmetric(pattern, values, 1e-14) {
            if let Ok(f) = Factor::new(pattern, values, llt) {
                return Ok(f);
            }
        }
        Factor::new(pattern, values, lu)
    }

    /// The kind.
    pub fn kind(&self) -> FactorKind {
        match self {
            Factor::Lu(lu) => FactorKind::Lu(lu.ordering()),
            Factor::Llt(_) => FactorKind::Llt,
            Factor::FaerLu(_) => FactorKind::FaerLu,
            Factor::FaerLlt(_) => FactorKind::FaerLlt,
        }
    }

    /// A second numeric factorization on the same analysis.
    ///
    /// # Errors
    /// As [`Factor::new`].
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Ok(match self {
            Factor::Lu(lu) => Factor::Lu(lu.with_values(pattern, values)?),
            Factor::Llt(llt) => Factor::Llt(llt.with_values(pattern, values)?),
            Factor::FaerLu(f) => Factor::FaerLu(Box::new(f.with_values(pattern, values)?)),
            Factor::FaerLlt(f) => Factor::FaerLlt(Box::new(f.with_values(pattern, values)?)),
        })
    }

    /// New values on the same analysis.
    ///
    /// # Errors
    /// As [`Factor::new`].
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        match self {
            Factor::Lu(lu) => lu.refactor(pattern, values),
            Factor::Llt(llt) => llt.refactor(pattern, values),
            Factor::FaerLu(f) => f.refactor(pattern, values),
            Factor::FaerLlt(f) => f.refactor(pattern, values),
        }
    }

    /// The orders of the two parts solved side by side and of the top, when the factor is
    /// split for two threads ([`SparseLu::parts`], [`SparseLlt::parts`]).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match self {
            Factor::Lu(lu) => lu.parts(),
            Factor::Llt(llt) => llt.parts(),
            Factor::FaerLu(_) | Factor::FaerLlt(_) => None,
        }
    }

    /// The orders of all the parts when the factor is split ([`SparseLu::part_orders`],
    /// [`SparseLlt::part_orders`]): the leaves, then each level of separators up to the top.
    pub fn part_orders(&self) -> Option<Vec<usize>> {
        match self {
            Factor::Lu(lu) => lu.part_orders(),
            Factor::Llt(llt) => llt.part_orders(),
            Factor::FaerLu(_) | Factor::FaerLlt(_) => None,
        }
    }

    /// Stored entries of the factors (`L + U`, or `L`).
    pub fn factor_nnz(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.factor_nnz(),
            Factor::Llt(llt) => llt.factor_nnz(),
            // faer's LU keeps its supernodal factors its own way: not counted.
            Factor::FaerLu(_) => 0,
            Factor::FaerLlt(f) => f.factor_nnz(),
        }
    }

    /// Bytes of the factors that a solve reads, as stored (each sweep's arrays; one copy
    /// read by both sweeps counts twice).
    pub fn solve_bytes(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.solve_bytes(),
            Factor::Llt(llt) => llt.solve_bytes(),
            Factor::FaerLu(_) => 0,
            Factor::FaerLlt(f) => {
                f.factor_nnz() * (std::mem::size_of::<f64>() + std::mem::size_of::<usize>()) * 2
            }
        }
    }

    /// Solves `A x = rhs` in place, without allocating (a split factor's parts side by
    /// side through the default team, `rayon::join` in the caller's pool).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_on(&super::team::Team::default(), rhs);
    }

    /// Solves `A X = B` in place for the `k` right-hand sides of `rhs` (column `c` in
    /// `rhs[c n..(c + 1) n]`): a Cholesky factor in dense supernodes solves them in blocks
    /// ([`SparseLlt::solve_many_on`]), every other factor one column at a time.
    ///
    /// # Panics
    /// If `rhs` is not `k` columns of the order.
    pub fn solve_many_on(&mut self, team: &super::team::Team, rhs: &mut [f64], k: usize) {
        let n = self.n();
        assert_eq!(rhs.len(), n * k, "{k} columns of {n}");
        match self {
            Factor::Llt(llt) => llt.solve_many_on(team, rhs, k),
            _ => {
                for col in rhs.chunks_exact_mut(n.max(1)) {
                    self.solve_on(team, col);
                }
            }
        }
    }

    /// Solves `A x = rhs` in place, without allocating, a split factor's parts side by side
    /// on `team`'s threads (the same bits on any team).
    pub fn solve_on(&mut self, team: &super::team::Team, rhs: &mut [f64]) {
        match self {
            Factor::Lu(lu) => lu.solve_on(team, rhs),
            Factor::Llt(llt) => llt.solve_on(team, rhs),
            Factor::FaerLu(f) => f.solve_in_place(rhs),
            Factor::FaerLlt(f) => f.solve_in_place(rhs),
        }
    }
}
