//! The tuned sparse Cholesky factorization ([`SparseLlt`]): faer's symbolic analysis (AMD,
//! or nested dissection on a large 3D mesh: [`Ordering::auto`]; split for two threads from
//! `SPLIT_MIN_ORDER` on) made once and shared, its numeric
//! factor copied into the solve's layouts as [`super::SparseLu`]'s.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::SparseColMatRef;
use faer::{Par, Side};
use std::sync::Arc;

use super::lu::{column_ordering, Ordering};
use super::solver::Counts;
use super::split::{self, SplitLower};
use super::supernodal::{
    prefetch_when_large, BlockRow, Supernodal, BLOCK_RHS, DENSE_SUPERNODAL_MIN_ORDER,
};
use super::team::Team;
use super::triangle::Triangle;
use super::{LinalgError, Pattern};

/// Sparse Cholesky factorization `A = L L^T` of a symmetric positive definite matrix (only
/// the upper triangle is read), symbolic analysis (AMD or nested dissection ordering) once,
/// solve without allocation.
///
/// The symbolic analysis is held behind an [`Arc`] (as faer's own `SymbolicLlt`): a second
/// factorization of other values on the same pattern ([`SparseLlt::with_values`]) shares it
/// and makes no analysis of its own.
pub struct SparseLlt {
    /// faer's symbolic analysis: the ordering, the elimination tree, the factor's structure.
    pub(super) symbolic: Arc<SymbolicCholesky<usize>>,
    /// The analyses and numeric factorizations made.
    pub(super) counts: Counts,
    /// The fill-reducing ordering.
    pub(super) ordering: Ordering,
    /// faer's factor (emptied after each factorization: the solve uses `l`).
    pub(super) numeric: Vec<f64>,
    pub(super) l: Triangle,
    /// `L^T` by rows (the columns of `L`).
    pub(super) lt: Triangle,
    /// `L` in dense supernodes (from `DENSE_SUPERNODAL_MIN_ORDER` on) or in the three parts
    /// of a split ordering; then `l` and `lt` stay empty.
    pub(super) stored: Option<StoredLower>,
    /// The order from which dense supernodes are used (`DENSE_SUPERNODAL_MIN_ORDER`).
    pub(super) dense_from: usize,
    /// The boundaries of the ordering's parts (`split::Split::bounds`: `[0, a, b, n]` for
    /// two parts and a top), when it has them.
    pub(super) parts: Option<Vec<usize>>,
    pub(super) perm_fwd: Vec<usize>,
    pub(super) perm_inv: Vec<usize>,
    pub(super) work: Vec<f64>,
    /// The blocks of right-hand sides of [`SparseLlt::solve_many_on`] (the sweeps' block, then
    /// the unknowns'; made at its first call).
    pub(super) block: Vec<BlockRow>,
    pub(super) n: usize,
}

/// A Cholesky factor `L` stored otherwise than whole by rows: whole in dense supernodes, or
/// in the three parts of an ordering split for two threads ([`SplitLower`], by rows or in
/// dense supernodes).
#[derive(Debug, Clone)]
pub(super) enum StoredLower {
    Supernodes(Supernodal),
    Split(Box<SplitLower>),
}

/// The fewest columns [`SparseLlt::solve_many_on`] solves as a block: fewer go one solve
/// each (a block of eight costs about three single solves: 64 columns of the 18^3 hex8 cube
/// took 249 ms in blocks against 726 ms one by one, `cargo bench --bench solver3d --
/// columns`), so the one or two new columns of a rolling step are not padded to eight.
pub const BLOCK_MIN_RHS: usize = 3;

impl std::fmt::Debug for SparseLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLlt").field("n", &self.n).finish()
    }
}

impl SparseLlt {
    /// The same factor solved in dense supernodes (`dense`) or by rows, whatever the order.
    #[cfg(test)]
    pub(super) fn with_layout(mut self, pattern: &Pattern, values: &[f64], dense: bool) -> Self {
        self.dense_from = if dense { 0 } else { usize::MAX };
        self.refactor(pattern, values).unwrap();
        self
    }

    /// Analyses (the ordering [`Ordering::auto`] chooses: AMD, or nested dissection on a
    /// large 3D mesh; split into two independent parts and a top for two threads from
    /// `SPLIT_MIN_ORDER` on, as [`super::SparseLu`]) and factors.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::with_ordering(pattern, values, Ordering::auto(pattern))
    }

    /// Analyses with the fill-reducing `ordering` (split for two threads from
    /// `SPLIT_MIN_ORDER` on) and factors.
    ///
    /// # Errors
    /// [`LinalgError`] when the ordering fails or the matrix is not positive definite.
    pub fn with_ordering(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
    ) -> Result<Self, LinalgError> {
        let supernodal = pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER;
        let depth = split::depth_for(pattern.nrows());
        Self::build_ordered(pattern, values, ordering, depth, supernodal)
    }

    /// [`SparseLlt::with_ordering`] with the ordering split into `2^depth` parts (0: whole)
    /// where it splits, whatever the order: to measure the split against another depth
    /// (`examples/split_parts.rs`).
    ///
    /// # Errors
    /// [`LinalgError`] when the ordering fails or the matrix is not positive definite.
    pub fn with_split_depth(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
        depth: usize,
    ) -> Result<Self, LinalgError> {
        let supernodal = pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER;
        Self::build_ordered(pattern, values, ordering, depth, supernodal)
    }

    /// Analyses, with the AMD ordering split for two threads when `split` and the ordering
    /// has two independent parts, and factors.
    #[cfg(test)]
    pub(super) fn build(
        pattern: &Pattern,
        values: &[f64],
        split: bool,
    ) -> Result<Self, LinalgError> {
        let supernodal = pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER;
        Self::build_with(pattern, values, split, supernodal)
    }

    /// [`SparseLlt::build`] with faer's supernodal factorization (`supernodal`) or its
    /// simplicial one.
    #[cfg(test)]
    pub(super) fn build_with(
        pattern: &Pattern,
        values: &[f64],
        split: bool,
        supernodal: bool,
    ) -> Result<Self, LinalgError> {
        Self::build_ordered(pattern, values, Ordering::Amd, split as usize, supernodal)
    }

    /// [`SparseLlt::build_with`] on `ordering`, split to `depth` (0: whole): AMD's split
    /// is the better of its own and its bisection's (`split::best_split`); another
    /// ordering's is its own elimination tree's (`split::two_subtrees`: nested dissection's
    /// first separator is its top); below it, `split::deepen`.
    pub(super) fn build_ordered(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
        depth: usize,
        supernodal: bool,
    ) -> Result<Self, LinalgError> {
        let split = depth > 0;
        let n = pattern.nrows();
        let mut parts = None;
        let mut custom = None;
        if split || ordering != Ordering::Amd {
            let (fwd, inv) = column_ordering(pattern, ordering)?;
            let s = match (split, ordering) {
                (false, _) => None,
                (true, Ordering::Amd) => split::best_split(pattern, &fwd, &inv),
                (true, _) => split::two_subtrees(pattern, &fwd, &inv),
            };
            match s {
                Some(s) => {
                    let s = split::deepen(pattern, s, depth);
                    custom = Some((s.fwd, s.inv));
                    parts = Some(s.bounds);
                }
                None if ordering != Ordering::Amd => custom = Some((fwd, inv)),
                None => {}
            }
        }
        // From the order of the dense layout on, faer's supernodal factorization (dense
        // kernels on its relaxed supernodes), converted to the layout's columns; below it
        // the simplicial one, whose columns the rows are built from directly.
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: if supernodal {
                faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL
            } else {
                faer::sparse::linalg::SupernodalThreshold::FORCE_SIMPLICIAL
            },
            ..Default::default()
        };
        let faer_ordering = match &custom {
            Some((f, i)) => SymmetricOrdering::Custom(PermRef::new_checked(f, i, n)),
            None => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern.as_ref(), Side::Upper, faer_ordering, params)
                .map_err(|e| LinalgError::Symbolic(format!("{e:?}")))?;
        let (perm_fwd, perm_inv) = match symbolic.perm() {
            Some(p) => {
                let (f, i) = p.arrays();
                (f.to_vec(), i.to_vec())
            }
            None => ((0..n).collect(), (0..n).collect()),
        };
        let mut llt = Self {
            numeric: Vec::new(),
            symbolic: Arc::new(symbolic),
            counts: Counts::analysed(),
            ordering,
            l: Triangle::default(),
            lt: Triangle::default(),
            stored: None,
            dense_from: DENSE_SUPERNODAL_MIN_ORDER,
            parts,
            perm_fwd,
            perm_inv,
            work: vec![0.0; n],
            block: Vec::new(),
            n,
        };
        llt.refactor(pattern, values)?;
        Ok(llt)
    }

    /// A second numeric factorization of `values` on the same pattern, on this one's
    /// symbolic analysis (shared, not made again: no analysis is counted for it).
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        let mut llt = Self {
            numeric: Vec::new(),
            symbolic: Arc::clone(&self.symbolic),
            counts: Counts::default(),
            ordering: self.ordering,
            l: Triangle::default(),
            lt: Triangle::default(),
            stored: None,
            dense_from: self.dense_from,
            parts: self.parts.clone(),
            perm_fwd: self.perm_fwd.clone(),
            perm_inv: self.perm_inv.clone(),
            work: vec![0.0; self.n],
            block: Vec::new(),
            n: self.n,
        };
        llt.refactor(pattern, values)?;
        Ok(llt)
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The fill-reducing ordering.
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// Numeric factorization of new values on the same pattern.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn refactor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LinalgError> {
        let mat = SparseColMatRef::new(pattern.as_ref(), values);
        let mut scratch = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.numeric.resize(self.symbolic.len_val(), 0.0);
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.numeric,
                mat,
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        let columns;
        let (cp, ri, numeric): (&[usize], &[usize], &[f64]) = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(simp) => {
                (simp.col_ptr(), simp.row_idx(), &self.numeric)
            }
            SymbolicCholeskyRaw::Supernodal(sn) => {
                columns = supernodal_columns(sn, &self.numeric);
                (&columns.0, &columns.1, &columns.2)
            }
        };
        let dense = self.n >= self.dense_from;
        let layout = if dense {
            split::Layout::Dense
        } else {
            split::Layout::Rows {
                forward: true,
                backward: true,
            }
        };
        let split = self.parts.as_ref().and_then(|bounds| {
            SplitLower::from_lower_csc((cp, ri, numeric), false, bounds, layout)
                .map(|l| StoredLower::Split(Box::new(l)))
        });
        (self.l, self.lt) = Default::default();
        self.stored = match split {
            Some(s) => Some(s),
            None if dense => Some(StoredLower::Supernodes(Supernodal::from_lower_csc(
                cp, ri, numeric, false,
            ))),
            None => {
                self.l = Triangle::from_csc(cp, ri, numeric, false, false, true);
                self.lt = Triangle::from_csc(cp, ri, numeric, false, true, false);
                None
            }
        };
        match &mut self.stored {
            Some(StoredLower::Split(l)) => prefetch_when_large(l.dense_parts_mut()),
            Some(StoredLower::Supernodes(l)) => prefetch_when_large([l]),
            None => {}
        }
        // The solve's work vector: the split's spread vector, or the unknowns.
        let len = match &mut self.stored {
            Some(StoredLower::Split(l)) => {
                l.set_scatter(&self.perm_fwd);
                l.spread_len()
            }
            _ => self.n,
        };
        self.work.resize(len, 0.0);
        self.numeric = Vec::new();
        self.counts.factorizations += 1;
        Ok(())
    }

    /// Number of stored values of the factor `L` (diagonal included).
    pub fn factor_nnz(&self) -> usize {
        match &self.stored {
            Some(StoredLower::Supernodes(l)) => l.nnz,
            Some(StoredLower::Split(l)) => l.nnz(),
            None => self.l.nnz(),
        }
    }

    /// Bytes of the factor that a solve reads: dense supernodes twice (one copy for both
    /// sweeps), by rows the two copies (`L` and `L^T`) once each.
    pub fn solve_bytes(&self) -> usize {
        match &self.stored {
            Some(StoredLower::Supernodes(l)) => 2 * l.bytes(),
            Some(StoredLower::Split(l)) => l.solve_bytes(),
            None => self.l.bytes() + self.lt.bytes(),
        }
    }

    /// The orders of the two halves solved side by side (each its parts and separators)
    /// and of the top (the root separator) after them, when the factor is split (module
    /// `split`).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match &self.stored {
            Some(StoredLower::Split(l)) => Some(l.sizes()),
            _ => None,
        }
    }

    /// The orders of all the parts when the factor is split: its `2^d` leaves, then each
    /// level of separators up to the top (`[part 0, part 1, top]` for two parts).
    pub fn part_orders(&self) -> Option<Vec<usize>> {
        match &self.stored {
            Some(StoredLower::Split(l)) => Some(l.part_orders()),
            _ => None,
        }
    }

    /// The work of each part when the factor is split, in the order of
    /// [`SparseLlt::part_orders`]: the load balance of the leaves side by side is the
    /// largest leaf's work over their mean.
    pub fn part_work(&self) -> Option<Vec<super::PartWork>> {
        match &self.stored {
            Some(StoredLower::Split(l)) => Some(l.part_work()),
            _ => None,
        }
    }

    avx2_method! {
        /// Solves `A x = rhs` in place, without allocating: `x = P^T L^{-T} L^{-1} P b` (the
        /// fill-reducing permutation `P` gathers `b[perm_fwd[i]]`). On AVX2's instructions where
        /// the processor has them (the macro `with_avx2`).
        pub fn solve_on / solve_avx2(&mut self, team: &Team, rhs: &mut [f64]) => solve_here
    }

    /// [`SparseLlt::solve_on`] with the default team (`rayon::join` in the caller's pool).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_on(&Team::default(), rhs);
    }

    /// Solves `A X = B` in place for the `k` right-hand sides of `rhs` (column `c` in
    /// `rhs[c n..(c + 1) n]`): on a factor in dense supernodes, [`BLOCK_RHS`] columns a sweep
    /// (the factor read once for them; a block of eight costs about three single solves), a
    /// last group of fewer than [`BLOCK_MIN_RHS`] columns one solve each; on other factors one
    /// solve a column. The work block is made at the first call and kept.
    ///
    /// # Panics
    /// If `rhs` is not `k` columns of the order.
    pub fn solve_many_on(&mut self, team: &Team, rhs: &mut [f64], k: usize) {
        // Fewer columns than `BLOCK_MIN_RHS` (a block's last ones included) go one by one.
        let n = self.n;
        assert_eq!(rhs.len(), n * k, "{k} columns of {n}");
        let spread = match &self.stored {
            Some(StoredLower::Supernodes(_)) => n,
            Some(StoredLower::Split(l)) if l.is_dense() => l.spread_len(),
            _ => {
                for col in rhs.chunks_exact_mut(n) {
                    self.solve_on(team, col);
                }
                return;
            }
        };
        if self.block.len() != spread + n {
            self.block = vec![[0.0; BLOCK_RHS]; spread + n];
        }
        for first in (0..k).step_by(BLOCK_RHS) {
            let cols = (k - first).min(BLOCK_RHS);
            let rhs = &mut rhs[first * n..(first + cols) * n];
            if cols < BLOCK_MIN_RHS {
                for col in rhs.chunks_exact_mut(n) {
                    self.solve_on(team, col);
                }
                continue;
            }
            let (x, b) = self.block.split_at_mut(spread);
            for (i, bi) in b.iter_mut().enumerate() {
                *bi = std::array::from_fn(|c| if c < cols { rhs[c * n + i] } else { 0.0 });
            }
            match &self.stored {
                Some(StoredLower::Supernodes(l)) => {
                    for (xi, &r) in x.iter_mut().zip(&self.perm_fwd) {
                        *xi = b[r];
                    }
                    l.forward_block(x);
                    l.backward_block(x);
                    for (bi, &p) in b.iter_mut().zip(&self.perm_inv) {
                        *bi = x[p];
                    }
                }
                Some(StoredLower::Split(l)) => l.solve_block(&self.perm_fwd, x, b),
                None => unreachable!("a block layout (above)"),
            }
            for (i, bi) in b.iter().enumerate() {
                for c in 0..cols {
                    rhs[c * n + i] = bi[c];
                }
            }
        }
    }

    #[inline(always)]
    pub(super) fn solve_here(&mut self, team: &Team, rhs: &mut [f64]) {
        let w = &mut self.work;
        if let Some(StoredLower::Split(l)) = &mut self.stored {
            // On the split's spread vector: each part solved in place.
            l.gather_forward(team, &self.perm_fwd, rhs, w);
            l.backward_scatter(team, w, rhs);
            return;
        }
        for (wi, &r) in w.iter_mut().zip(&self.perm_fwd) {
            *wi = rhs[r];
        }
        match &mut self.stored {
            Some(StoredLower::Supernodes(l)) => {
                l.forward(w);
                l.backward(w);
            }
            Some(StoredLower::Split(_)) => unreachable!("solved above"),
            None => {
                self.l.solve(w);
                self.lt.solve(w);
            }
        }
        for (xi, &c) in rhs.iter_mut().zip(&self.perm_inv) {
            *xi = w[c];
        }
    }
}

/// The columns (CSC: column pointers, row indices, values) of the lower triangular factor
/// held by faer's supernodal Cholesky `sn` with the values `val`: supernode `s`, columns
/// `j0..j1`, is a column-major block of `j1 - j0 + |P|` rows (the diagonal block, then the
/// rows `P` below it); column `j0 + k` is its rows `k..` of the diagonal block and `P`.
/// Entries that are exactly zero off the diagonal are left out: they are the padding of
/// faer's relaxed supernodes (outside the elimination's structure, they stay zero), so the
/// columns are those of the simplicial factor and a solve reads no more bytes.
pub(super) fn supernodal_columns(
    sn: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    val: &[f64],
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let n = sn.nrows();
    let (mut cp, mut ri, mut vals) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
    cp.push(0);
    let (begin, end, vptr) = (
        sn.supernode_begin(),
        sn.supernode_end(),
        sn.col_ptr_for_val(),
    );
    for s in 0..sn.n_supernodes() {
        let (j0, j1) = (begin[s], end[s]);
        let pattern = sn.supernode(s).pattern();
        let (w, rows) = (j1 - j0, j1 - j0 + pattern.len());
        let blk = &val[vptr[s]..vptr[s + 1]];
        debug_assert_eq!(blk.len(), rows * w);
        for k in 0..w {
            let col = &blk[k * rows..(k + 1) * rows];
            for (r, &v) in col.iter().enumerate().skip(k) {
                if v != 0.0 || r == k {
                    ri.push(if r < w { j0 + r } else { pattern[r - w] });
                    vals.push(v);
                }
            }
            cp.push(ri.len());
        }
    }
    (cp, ri, vals)
}
