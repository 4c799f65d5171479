//! The tuned sparse LU ([`SparseLu`]): faer's simplicial numeric LU with partial pivoting on
//! a column ordering computed once (AMD or COLAMD, split for two threads from
//! `SPLIT_MIN_ORDER` on), its factors copied into the solve's layouts ([`Triangle`] by rows,
//! [`Supernodal`] dense, [`SplitLower`] in two parts and a top).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::simplicial::{self, SimplicialLu};
use faer::sparse::linalg::{amd, colamd};
use faer::sparse::SparseColMatRef;

use super::solver::Counts;
use super::split::{self, SplitLower};
use super::supernodal::{prefetch_when_large, Supernodal, DENSE_SUPERNODAL_MIN_ORDER};
use super::team::Team;
use super::triangle::Triangle;
use super::{LinalgError, Pattern};

/// The fill-reducing column ordering of a [`SparseLu`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ordering {
    /// COLAMD on `A` (faer's default for LU: it bounds the fill of `A^T A`, for any
    /// pivoting).
    Colamd,
    /// AMD on the pattern of `A + A^T` (the Cholesky ordering: the right one for a
    /// structurally symmetric matrix whose partial pivoting stays on the diagonal).
    Amd,
    /// Nested dissection of the graph of `A + A^T` (module `dissect`: multilevel vertex
    /// separators, AMD on the leaves): less fill than AMD on 3D meshes.
    NestedDissection,
}

/// Unknowns from which [`Ordering::auto`] takes nested dissection on a 3D mesh.
///
/// Measured on steel cubes of hexahedra, the step matrix `M + c K`
/// (`examples/solver3d_ladder.rs`, one thread): at 3,993 unknowns (10^3 cells) nested
/// dissection's factor has 0.80 of AMD's entries (869,889 against 1,088,400) and factors in
/// half the time (0.50 s against 1.05 s, its ordering 0.08 s); at 20,577 (18^3 cells) 0.60
/// (9.86e6 against 16.3e6) and 2.5 against 4.6 s. Below a few thousand unknowns the ordering's
/// own time weighs as much as what it saves. At 2e5 unknowns (bars of 12 x 12 x 400
/// hexahedra and 6 x 6 x 200 10-node tetrahedra, a quiet machine) the factor has 0.63 and
/// 0.71 of AMD's entries, refactors in half the time and peaks at two thirds of the memory;
/// the solve, though, is not always faster (174 against 269 ms on the hexahedra, 252 against
/// 197 ms on the tetrahedra): see `bench/peers/README.md`.
pub const DISSECTION_MIN_ORDER: usize = 5_000;

impl Ordering {
    /// The ordering for `pattern`: [`Ordering::NestedDissection`] from
    /// [`DISSECTION_MIN_ORDER`] unknowns on when its nodes hold three unknowns each on the
    /// mean (a 3D mesh: the columns of one node's unknowns are equal), else
    /// [`Ordering::Amd`] (every 2D model, two unknowns a node, keeps AMD).
    pub fn auto(pattern: &Pattern) -> Ordering {
        if pattern.ncols() >= DISSECTION_MIN_ORDER
            && super::dissect::Graph::unknowns_per_vertex(pattern) >= 2.5
        {
            Ordering::NestedDissection
        } else {
            Ordering::Amd
        }
    }
}

/// Sparse LU factorization `P A Q = L U` (faer's simplicial LU with partial pivoting) with
/// the column ordering `Q` computed once.
///
/// [`SparseLu::refactor`] reuses the ordering for new values on the same pattern;
/// [`SparseLu::solve_in_place`] reuses scratch memory allocated at construction.
pub struct SparseLu {
    /// The analyses (column orderings) and numeric factorizations made.
    pub(super) counts: Counts,
    pub(super) ordering: Ordering,
    pub(super) col_fwd: Vec<usize>,
    pub(super) col_inv: Vec<usize>,
    pub(super) row_fwd: Vec<usize>,
    pub(super) row_inv: Vec<usize>,
    /// faer's factors (emptied after each factorization: the solve uses `l`, `u`).
    pub(super) numeric: SimplicialLu<usize, f64>,
    pub(super) l: Triangle,
    pub(super) u: Triangle,
    /// `L` and `U^T` in dense supernodes (from `DENSE_SUPERNODAL_MIN_ORDER` on) or in the
    /// three parts of a split ordering; then `l` and `u` stay empty.
    pub(super) stored: Option<Stored>,
    /// The order from which dense supernodes are used (`DENSE_SUPERNODAL_MIN_ORDER`).
    pub(super) dense_from: usize,
    /// The boundaries of the ordering's parts (`split::Split::bounds`: `[0, a, b, n]` for
    /// two parts and a top), when it has them.
    pub(super) parts: Option<Vec<usize>>,
    pub(super) work: Vec<f64>,
    pub(super) n: usize,
}

/// `L` and `U^T` stored otherwise than whole by rows: whole in dense supernodes, or in the
/// three parts of an ordering split for two threads ([`SplitLower`], by rows or in dense
/// supernodes).
#[derive(Debug, Clone)]
pub(super) enum Stored {
    Supernodes(Box<(Supernodal, Supernodal)>),
    Split(Box<(SplitLower, SplitLower)>),
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.n)
            .field("ordering", &self.ordering)
            .finish()
    }
}

/// The column permutation of `ordering` for `pattern`: `(forward, inverse)`.
pub(super) fn column_ordering(
    pattern: &Pattern,
    ordering: Ordering,
) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    let n = pattern.ncols();
    let nnz = pattern.compute_nnz();
    let (mut fwd, mut inv) = (vec![0usize; n], vec![0usize; n]);
    let symbolic = |e: faer::sparse::FaerError| LinalgError::Symbolic(format!("{e:?}"));
    match ordering {
        Ordering::Colamd => {
            let mut mem = MemBuffer::new(colamd::order_scratch::<usize>(n, n, nnz));
            colamd::order(
                &mut fwd,
                &mut inv,
                pattern.as_ref(),
                Default::default(),
                MemStack::new(&mut mem),
            )
            .map_err(symbolic)?;
        }
        Ordering::Amd => {
            let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, nnz));
            amd::order(
                &mut fwd,
                &mut inv,
                pattern.as_ref(),
                Default::default(),
                MemStack::new(&mut mem),
            )
            .map_err(symbolic)?;
        }
        Ordering::NestedDissection => return super::dissect::nested_dissection(pattern),
    }
    Ok((fwd, inv))
}

impl SparseLu {
    /// The same factor solved in dense supernodes (`dense`) or by rows, whatever the order.
    #[cfg(test)]
    pub(super) fn with_layout(mut self, pattern: &Pattern, values: &[f64], dense: bool) -> Self {
        self.dense_from = if dense { 0 } else { usize::MAX };
        self.refactor(pattern, values).unwrap();
        self
    }

    /// Orders the columns by AMD (the matrices of softway are structurally symmetric: mass,
    /// stiffness, damping on one pattern) and factors the matrix.
    ///
    /// # Errors
    /// [`LinalgError`] when the analysis fails or the matrix is singular.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::with_ordering(pattern, values, Ordering::Amd)
    }

    /// Orders the columns with `ordering` and factors the matrix.
    ///
    /// # Errors
    /// [`LinalgError`] when the analysis fails or the matrix is singular.
    pub fn with_ordering(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
    ) -> Result<Self, LinalgError> {
        Self::build_depth(pattern, values, ordering, split::depth_for(pattern.nrows()))
    }

    /// Orders the columns with `ordering`, split for two threads when `split` and the
    /// ordering has two independent parts, and factors the matrix.
    #[cfg(test)]
    pub(super) fn build(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
        split: bool,
    ) -> Result<Self, LinalgError> {
        Self::build_depth(pattern, values, ordering, split as usize)
    }

    /// Orders the columns with `ordering`, split into `2^depth` parts (0: whole) where the
    /// ordering splits (`split::best_split`, then `split::deepen`), and factors the matrix.
    pub(super) fn build_depth(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
        depth: usize,
    ) -> Result<Self, LinalgError> {
        let n = pattern.nrows();
        let (mut col_fwd, mut col_inv) = column_ordering(pattern, ordering)?;
        let mut parts = None;
        if depth > 0 {
            if let Some(s) = split::best_split(pattern, &col_fwd, &col_inv) {
                let s = split::deepen(pattern, s, depth);
                (col_fwd, col_inv, parts) = (s.fwd, s.inv, Some(s.bounds));
            }
        }
        let mut lu = Self {
            counts: Counts::analysed(),
            ordering,
            col_fwd,
            col_inv,
            row_fwd: vec![0; n],
            row_inv: vec![0; n],
            numeric: SimplicialLu::new(),
            l: Triangle::default(),
            u: Triangle::default(),
            stored: None,
            dense_from: DENSE_SUPERNODAL_MIN_ORDER,
            parts,
            work: vec![0.0; n],
            n,
        };
        lu.refactor(pattern, values)?;
        Ok(lu)
    }

    /// A second numeric factorization of `values` with this one's column ordering (the
    /// same pattern; no new ordering).
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let mut lu = Self {
            counts: Counts::default(),
            ordering: self.ordering,
            col_fwd: self.col_fwd.clone(),
            col_inv: self.col_inv.clone(),
            row_fwd: vec![0; self.n],
            row_inv: vec![0; self.n],
            numeric: SimplicialLu::new(),
            l: Triangle::default(),
            u: Triangle::default(),
            stored: None,
            dense_from: self.dense_from,
            parts: self.parts.clone(),
            work: vec![0.0; self.n],
            n: self.n,
        };
        lu.refactor(pattern, values)?;
        Ok(lu)
    }

    /// Numeric factorization of new values on the pattern ordered in [`SparseLu::new`].
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is singular.
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        let n = self.n;
        let mat = SparseColMatRef::new(pattern.as_ref(), values);
        let mut scratch = MemBuffer::new(simplicial::factorize_simplicial_numeric_lu_scratch::<
            usize,
            f64,
        >(n, n));
        let col_perm = PermRef::new_checked(&self.col_fwd, &self.col_inv, n);
        simplicial::factorize_simplicial_numeric_lu(
            &mut self.row_fwd,
            &mut self.row_inv,
            &mut self.numeric,
            mat,
            col_perm,
            MemStack::new(&mut scratch),
        )
        .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        // The factors for the solve ([`Triangle`] or [`Supernodal`]); faer's copy is let go.
        let (l, u) = (
            self.numeric.l_factor_unsorted(),
            self.numeric.u_factor_unsorted(),
        );
        let (lc, lr, uc, ur) = (
            l.symbolic().col_ptr(),
            l.symbolic().row_idx(),
            u.symbolic().col_ptr(),
            u.symbolic().row_idx(),
        );
        let dense = n >= self.dense_from;
        let (tc, tr, tv) = transpose_csc(uc, ur, u.val());
        // L for the forward sweep, U^T for the backward one.
        let (fwd, bwd) = if dense {
            (split::Layout::Dense, split::Layout::Dense)
        } else {
            (
                split::Layout::Rows {
                    forward: true,
                    backward: false,
                },
                split::Layout::Rows {
                    forward: false,
                    backward: true,
                },
            )
        };
        let split = self.parts.as_ref().and_then(|bounds| {
            Some(Stored::Split(Box::new((
                SplitLower::from_lower_csc((lc, lr, l.val()), true, bounds, fwd)?,
                SplitLower::from_lower_csc((&tc, &tr, &tv), false, bounds, bwd)?,
            ))))
        });
        (self.l, self.u) = Default::default();
        self.stored = match split {
            Some(s) => Some(s),
            None if dense => Some(Stored::Supernodes(Box::new((
                Supernodal::from_lower_csc(lc, lr, l.val(), true),
                Supernodal::from_lower_csc(&tc, &tr, &tv, false),
            )))),
            None => {
                self.l = Triangle::from_csc(lc, lr, l.val(), true, false, true);
                self.u = Triangle::from_csc(uc, ur, u.val(), false, false, false);
                None
            }
        };
        match &mut self.stored {
            Some(Stored::Split(lu)) => {
                let (l, ut) = &mut **lu;
                prefetch_when_large(l.dense_parts_mut().chain(ut.dense_parts_mut()));
            }
            Some(Stored::Supernodes(lu)) => prefetch_when_large([&mut lu.0, &mut lu.1]),
            None => {}
        }
        // The solve's work vector: the split's spread vector, or the unknowns.
        let len = match &mut self.stored {
            Some(Stored::Split(lu)) => {
                lu.1.set_scatter(&self.col_fwd);
                lu.0.spread_len()
            }
            _ => n,
        };
        self.work.resize(len, 0.0);
        self.numeric = SimplicialLu::new();
        self.counts.factorizations += 1;
        Ok(())
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The column ordering.
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// The orders of the two halves solved side by side (each its parts and separators)
    /// and of the top (the root separator) after them, when the factor is split (module
    /// `split`).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match &self.stored {
            Some(Stored::Split(lu)) => Some(lu.0.sizes()),
            _ => None,
        }
    }

    /// The orders of all the parts when the factors are split: the `2^d` leaves, then each
    /// level of separators up to the top (`[part 0, part 1, top]` for two parts).
    pub fn part_orders(&self) -> Option<Vec<usize>> {
        match &self.stored {
            Some(Stored::Split(lu)) => Some(lu.0.part_orders()),
            _ => None,
        }
    }

    /// Stored entries of `L` (unit diagonal included) plus those of `U`.
    pub fn factor_nnz(&self) -> usize {
        match &self.stored {
            Some(Stored::Supernodes(lu)) => lu.0.nnz + lu.1.nnz,
            Some(Stored::Split(lu)) => lu.0.nnz() + lu.1.nnz(),
            None => self.l.nnz() + self.u.nnz(),
        }
    }

    /// Bytes of the factors that a solve reads (`L` forward, `U` backward, each once).
    pub fn solve_bytes(&self) -> usize {
        match &self.stored {
            Some(Stored::Supernodes(lu)) => lu.0.bytes() + lu.1.bytes(),
            Some(Stored::Split(lu)) => lu.0.bytes() + lu.1.bytes(),
            None => self.l.bytes() + self.u.bytes(),
        }
    }

    avx2_method! {
        /// Solves `A x = rhs` in place, without allocating: `x = Q U^{-1} L^{-1} P b` (faer's
        /// row permutation `P` gathers `b[row_fwd[i]]`, the column ordering scatters back).
        /// On AVX2's instructions where the processor has them (the macro `with_avx2`).
        pub fn solve_on / solve_avx2(&mut self, team: &Team, rhs: &mut [f64]) => solve_here
    }

    /// [`SparseLu::solve_on`] with the default team (`rayon::join` in the caller's pool).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_on(&Team::default(), rhs);
    }

    #[inline(always)]
    pub(super) fn solve_here(&mut self, team: &Team, rhs: &mut [f64]) {
        let w = &mut self.work;
        if let Some(Stored::Split(lu)) = &mut self.stored {
            // On the split's spread vector: each part solved in place.
            lu.0.gather_forward(team, &self.row_fwd, rhs, w);
            lu.1.backward_scatter(team, w, rhs);
            return;
        }
        for (wi, &r) in w.iter_mut().zip(&self.row_fwd) {
            *wi = rhs[r];
        }
        match &mut self.stored {
            Some(Stored::Supernodes(lu)) => {
                lu.0.forward(w);
                lu.1.backward(w);
            }
            Some(Stored::Split(_)) => unreachable!("solved above"),
            None => {
                self.l.solve(w);
                self.u.solve(w);
            }
        }
        for (xi, &c) in rhs.iter_mut().zip(&self.col_inv) {
            *xi = w[c];
        }
    }
}

/// The CSC arrays of the transpose of a square CSC matrix.
pub(super) fn transpose_csc(
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &[f64],
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let n = col_ptr.len() - 1;
    let nnz = col_ptr[n];
    let mut ptr = vec![0usize; n + 1];
    for &i in &row_idx[..nnz] {
        ptr[i + 1] += 1;
    }
    for i in 0..n {
        ptr[i + 1] += ptr[i];
    }
    let mut next = ptr[..n].to_vec();
    let (mut ri, mut v) = (vec![0usize; nnz], vec![0.0; nnz]);
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let q = next[row_idx[p]];
            ri[q] = j;
            v[q] = values[p];
            next[row_idx[p]] += 1;
        }
    }
    (ptr, ri, v)
}
