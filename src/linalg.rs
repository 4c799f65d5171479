//! Sparse linear algebra on one sparsity pattern: matrix-vector products, a sparse LU and a
//! sparse Cholesky factorization (faer's numeric factorizations, with a fill-reducing
//! ordering computed once), whose solves run on compact copies of the factors with memory
//! allocated once, so that the time loop does not allocate; a Matrix Market writer.
//!
//! From `SPLIT_MIN_ORDER` unknowns on, the column ordering is renumbered as two independent
//! sets of subtrees of its elimination tree followed by their ancestors (module `split`):
//! the two sets' solves run side by side on two threads (module `team`), with the same
//! result bit for bit on one thread. The kernels of the row solves are compiled for the baseline
//! processor and for AVX2, chosen at run time (the macro `with_avx2`).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::lu::simplicial::{self, SimplicialLu};
use faer::sparse::linalg::{amd, colamd};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::Side;
use faer::{MatMut, Par};

mod bisect;
mod huge;
mod split;
pub mod team;
pub use huge::{HugeBuf, HUGE_MIN_BYTES};
use split::SplitLower;
use team::Team;

/// Runs `$avx2` (an unsafe call of a function compiled with `#[target_feature(enable =
/// "avx2")]`, the same code as `$generic`) where the processor has AVX2, else `$generic`.
///
/// The kernels of the time loop (the row solves, the right-hand side) are written once,
/// `#[inline(always)]`, and compiled twice: for the baseline x86-64 (SSE2) and for AVX2,
/// chosen at run time, so that one binary runs everywhere and uses the wider instructions
/// where they exist. Measured on the paper's wheel: the free step 26.0 -> 24.x us. The same
/// operations run in the same order (no fused multiply-add: Rust does not contract), so
/// both give the same result bit for bit.
macro_rules! with_avx2 {
    ($generic:expr, $avx2:expr) => {{
        #[cfg(target_arch = "x86_64")]
        {
            if $crate::linalg::has_avx2() {
                // SAFETY: the processor has AVX2 (checked just above).
                #[allow(unused_unsafe)]
                unsafe {
                    $avx2
                }
            } else {
                $generic
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            $generic
        }
    }};
}
pub(crate) use with_avx2;

/// A method `$name` that runs the `#[inline(always)]` method `$here` through [`with_avx2`],
/// and `$twin`, the same body compiled for AVX2 (unsafe: the processor must have AVX2).
macro_rules! avx2_method {
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $twin:ident
        (&mut self $(, $a:ident: $t:ty)*) => $here:ident) => {
        $(#[$doc])*
        $vis fn $name(&mut self $(, $a: $t)*) {
            with_avx2!(self.$here($($a),*), self.$twin($($a),*))
        }

        #[doc = concat!("`", stringify!($here), "` compiled for AVX2.")]
        ///
        /// # Safety
        /// The processor must have AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn $twin(&mut self $(, $a: $t)*) {
            self.$here($($a),*)
        }
    };
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $twin:ident
        (&self $(, $a:ident: $t:ty)*) => $here:ident) => {
        $(#[$doc])*
        $vis fn $name(&self $(, $a: $t)*) {
            with_avx2!(self.$here($($a),*), self.$twin($($a),*))
        }

        #[doc = concat!("`", stringify!($here), "` compiled for AVX2.")]
        ///
        /// # Safety
        /// The processor must have AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn $twin(&self $(, $a: $t)*) {
            self.$here($($a),*)
        }
    };
}
pub(crate) use avx2_method;

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
    assert!(x.len() == pattern.ncols() && values.len() >= col_ptr[x.len()]);
    let mut s = 0.0;
    for (j, &xj) in x.iter().enumerate() {
        let range = col_ptr[j]..col_ptr[j + 1];
        // Four partial sums over the column (a dot product with a gather).
        let mut acc = [0.0; 4];
        let (ri, va) = (&row_idx[range.clone()], &values[range]);
        let (ri4, va4) = (ri.chunks_exact(4), va.chunks_exact(4));
        let (ri_rest, va_rest) = (ri4.remainder(), va4.remainder());
        for (ic, vc) in ri4.zip(va4) {
            for k in 0..4 {
                acc[k] += vc[k] * x[ic[k]];
            }
        }
        for (&i, &v) in ri_rest.iter().zip(va_rest) {
            acc[0] += v * x[i];
        }
        s += ((acc[0] + acc[1]) + (acc[2] + acc[3])) * xj;
    }
    s
}

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
}

/// A triangular factor stored for the solve by rows, in supernodes.
///
/// Each unknown is one dot product with the unknowns already found. Runs of consecutive rows
/// that share their columns outside the run and are full inside it (the two dofs of a node,
/// the dense separators at the end of the elimination) form a supernode: the unknowns of its
/// shared columns are gathered once into a contiguous buffer and every row of the run is a
/// dense dot product with that buffer and with the run's own unknowns, without indices.
/// A run of exactly two rows (most often a node's two dofs) is a pair: one gather over its
/// shared columns feeds both dot products, the two rows' values stored side by side, and
/// the entry coupling the two rows is applied after. Other runs of fewer than
/// `MIN_SUPERNODE` rows are solved row by row (a gather per entry, 32-bit indices). Every
/// dot product is summed in four partial sums (no chain of dependent
/// additions) and the inner loops hold no stores. Measured with callgrind on the paper's
/// wheel (938 dofs, 53,478 stored entries): faer's generic solve and the column-oriented
/// scatter that preceded this spent 8.8 instructions per stored entry, this layout 6.6
/// before pairs. The pairs (90% of `L`'s entries on that wheel) took its solve from 22.6
/// to 18.9 us, and that of the converged wheel (3,432 dofs) from 86.5 to 72.8 us (best of
/// repeated steps, alternated binaries).
///
/// A pair's shared columns mostly come two by two as well (the two dofs of a neighbouring
/// node, adjacent in the ordering): such a block is stored as one index and four values,
/// `x[c..c + 2]` read in one load, and on AVX2 the four products are one instruction
/// ([`blocks_dot_avx2`]). On the paper's wheel 11,310 of the 11,392 shared columns of
/// `L`'s pairs (3,014 of 3,112 in `U`) are in blocks; the free step went from 23.3 to
/// 21.1 us, that of
/// the converged wheel (3,430 dofs) from 112 to 106 us (`softway matrix`, median of five
/// rounds, alternated binaries, three times each).
///
/// Layout: for a lower triangle the rows are solved in increasing order and a supernode's
/// rows `r0..r1` hold their shared columns (all `< r0`) and, row `r`, the columns `r0..r`;
/// for an upper triangle in decreasing order, the shared columns (all `>= r1`) and, row `r`,
/// the columns `r + 1..r1`.
#[derive(Debug, Clone, Default)]
struct Triangle {
    lower: bool,
    /// Supernode `s`'s first row in `val_ptr` and `tri_ptr` (each supernode's rows there are
    /// followed by one end entry).
    sn_first: Vec<usize>,
    /// The shared columns of each supernode: `cols[cols_ptr[s]..cols_ptr[s + 1]]`.
    cols_ptr: Vec<usize>,
    cols: Vec<u32>,
    /// The `k`-th stored supernode row's values on its supernode's shared columns
    /// (`val[val_ptr[k]..]`, as many as the shared columns), then on the run's own columns
    /// (`tri_ptr[k]..val_ptr[k + 1]`).
    val_ptr: Vec<usize>,
    tri_ptr: Vec<usize>,
    val: Vec<f64>,
    diag_inv: Vec<f64>,
    /// The gathered unknowns of one supernode's shared columns.
    gathered: Vec<f64>,
    /// Rows that are no supernode, by rows (CSR; empty for the rows of supernodes).
    single_ptr: Vec<usize>,
    single_idx: Vec<u32>,
    single_val: Vec<f64>,
    /// Pairs of rows sharing their columns (the two dofs of a node): pair `p` holds its
    /// shared columns `pair_idx[pair_ptr[p]..pair_ptr[p + 1]]`, the two rows' values on them
    /// side by side (`pair_val`, same range), and the entry coupling the two rows
    /// (`pair_coupling[p]`: lower, `T[r0 + 1, r0]`; upper, `T[r0, r0 + 1]`).
    pair_ptr: Vec<usize>,
    pair_idx: Vec<u32>,
    pair_val: Vec<[f64; 2]>,
    pair_coupling: Vec<f64>,
    /// The shared columns of pairs that come two by two (`c, c + 1`: the two dofs of a
    /// neighbouring node), apart from those above: pair `p`'s blocks
    /// `blk_idx[blk_ptr[p]..blk_ptr[p + 1]]` hold `c`, `blk_val` the four values
    /// `[T[r0, c], T[r0, c + 1], T[r0 + 1, c], T[r0 + 1, c + 1]]` (one index and one
    /// contiguous load of `x` for four entries).
    blk_ptr: Vec<usize>,
    blk_idx: Vec<u32>,
    blk_val: Vec<[f64; 4]>,
    /// The processor has AVX2: the blocks run on [`blocks_dot_avx2`] (same results bit for
    /// bit as [`blocks_dot`]).
    avx2: bool,
    /// Consecutive rows solved the same way, in storage order.
    segments: Vec<(usize, usize, Segment)>,
    /// Stored off-diagonal entries.
    off_diagonal: usize,
}

/// How a [`Triangle`]'s run of rows `r0..r1` is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Segment {
    /// Row by row, a gather per entry.
    Singles,
    /// Two rows sharing their columns (`r1 = r0 + 2`), pair `p`: one gather for both.
    Pair(usize),
    /// A supernode (its index in `sn_first`): the shared columns gathered once.
    Super(usize),
}

impl Triangle {
    /// Bytes of the arrays a solve reads.
    fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.sn_first[..])
            + b(&self.cols_ptr[..])
            + b(&self.cols[..])
            + b(&self.val_ptr[..])
            + b(&self.tri_ptr[..])
            + b(&self.val[..])
            + b(&self.diag_inv[..])
            + b(&self.single_ptr[..])
            + b(&self.single_idx[..])
            + b(&self.single_val[..])
            + b(&self.pair_ptr[..])
            + b(&self.pair_idx[..])
            + b(&self.pair_val[..])
            + b(&self.pair_coupling[..])
            + b(&self.blk_ptr[..])
            + b(&self.blk_idx[..])
            + b(&self.blk_val[..])
    }

    /// From a CSC factor (row indices in any order, the diagonal stored somewhere in each
    /// column), stored by the rows of the factor (`transpose = false`) or of its transpose
    /// (`transpose = true`); `unit`: the diagonal is 1 (not stored as such); `lower`: the
    /// triangle stored is lower (else upper).
    fn from_csc(
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &[f64],
        unit: bool,
        transpose: bool,
        lower: bool,
    ) -> Self {
        let n = col_ptr.len() - 1;
        assert!(
            n <= u32::MAX as usize,
            "a factor too large for 32-bit indices"
        );
        let mut diag_inv = vec![1.0; n];
        // The rows (CSR) of the stored triangle, off-diagonal entries only.
        let mut ptr = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                assert!(i < n, "a factor's row index out of range");
                if i != j {
                    ptr[if transpose { j } else { i } + 1] += 1;
                }
            }
        }
        for r in 0..n {
            ptr[r + 1] += ptr[r];
        }
        let mut rows: Vec<(u32, f64)> = vec![(0, 0.0); ptr[n]];
        let mut next = ptr[..n].to_vec();
        for j in 0..n {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let i = row_idx[p];
                if i == j {
                    if !unit {
                        diag_inv[j] = values[p].recip();
                    }
                    continue;
                }
                let (r, c) = if transpose { (j, i) } else { (i, j) };
                assert!(
                    (c < r) == lower,
                    "an entry on the wrong side of the diagonal"
                );
                rows[next[r]] = (c as u32, values[p]);
                next[r] += 1;
            }
        }
        for r in 0..n {
            rows[ptr[r]..ptr[r + 1]].sort_unstable_by_key(|e| e.0);
        }
        let row = |r: usize| &rows[ptr[r]..ptr[r + 1]];
        // Supernodes, in increasing row order. Lower: row `r` joins the run `r0..r` when its
        // columns are those of row `r - 1` and `r - 1`. Upper: row `r` joins when the
        // columns of row `r - 1` are `r` and those of row `r`.
        let mut bounds = vec![0usize];
        for r in 1..n {
            let (a, b) = (row(r - 1), row(r));
            let joins = if lower {
                b.len() == a.len() + 1
                    && b[..a.len()].iter().zip(a).all(|(x, y)| x.0 == y.0)
                    && b[a.len()].0 as usize == r - 1
            } else {
                a.len() == b.len() + 1
                    && a[0].0 as usize == r
                    && a[1..].iter().zip(b).all(|(x, y)| x.0 == y.0)
            };
            if !joins {
                bounds.push(r);
            }
        }
        bounds.push(n);
        // Runs shorter than `MIN_SUPERNODE` rows are split into single rows: for them the
        // gather into the buffer costs more than it saves.
        let mut split = vec![0usize];
        for w in bounds.windows(2) {
            if w[1] - w[0] < MIN_SUPERNODE && w[1] - w[0] != 2 {
                split.extend(w[0] + 1..=w[1]);
            } else {
                split.push(w[1]);
            }
        }
        let bounds = split;
        let mut t = Triangle {
            lower,
            cols_ptr: vec![0],
            val_ptr: Vec::with_capacity(n + 1),
            tri_ptr: Vec::with_capacity(n),
            diag_inv,
            off_diagonal: ptr[n],
            single_ptr: vec![0],
            pair_ptr: vec![0],
            blk_ptr: vec![0],
            avx2: has_avx2(),
            ..Default::default()
        };
        let mut widest = 0;
        for w in bounds.windows(2) {
            let (r0, r1) = (w[0], w[1]);
            if r1 - r0 == 1 {
                // A single row: its entries by rows.
                let entries = row(r0);
                t.single_idx.extend(entries.iter().map(|e| e.0));
                t.single_val.extend(entries.iter().map(|e| e.1));
                t.single_ptr.push(t.single_idx.len());
                match t.segments.last_mut() {
                    Some((_, end, Segment::Singles)) if *end == r0 => *end = r1,
                    _ => t.segments.push((r0, r1, Segment::Singles)),
                }
                continue;
            }
            if r1 - r0 == 2 {
                // A pair: lower, row r0 + 1 is row r0's columns and r0; upper, row r0 is
                // r0 + 1 and row r0 + 1's columns.
                let (a, b) = (row(r0), row(r0 + 1));
                let (shared, first, second, coupling) = if lower {
                    (a, a, &b[..a.len()], b[a.len()].1)
                } else {
                    (b, &a[1..], b, a[0].1)
                };
                let mut k = 0;
                while k < shared.len() {
                    let c = shared[k].0;
                    if k + 1 < shared.len() && shared[k + 1].0 == c + 1 {
                        t.blk_idx.push(c);
                        t.blk_val
                            .push([first[k].1, first[k + 1].1, second[k].1, second[k + 1].1]);
                        k += 2;
                    } else {
                        t.pair_idx.push(c);
                        t.pair_val.push([first[k].1, second[k].1]);
                        k += 1;
                    }
                }
                t.pair_ptr.push(t.pair_idx.len());
                t.blk_ptr.push(t.blk_idx.len());
                t.pair_coupling.push(coupling);
                t.single_ptr.push(t.single_idx.len());
                t.single_ptr.push(t.single_idx.len());
                t.segments
                    .push((r0, r1, Segment::Pair(t.pair_coupling.len() - 1)));
                continue;
            }
            for _ in r0..r1 {
                t.single_ptr.push(t.single_idx.len());
            }
            let s = t.sn_first.len();
            t.sn_first.push(t.val_ptr.len());
            t.segments.push((r0, r1, Segment::Super(s)));
            // Shared columns: lower, those of row r0; upper, those of row r1 - 1.
            let shared = if lower { row(r0) } else { row(r1 - 1) };
            t.cols.extend(shared.iter().map(|e| e.0));
            t.cols_ptr.push(t.cols.len());
            widest = widest.max(shared.len());
            for r in r0..r1 {
                let own = if lower { r - r0 } else { r1 - 1 - r };
                let entries = row(r);
                debug_assert_eq!(entries.len(), shared.len() + own);
                t.val_ptr.push(t.val.len());
                if lower {
                    // Shared columns first (all < r0), then r0..r.
                    t.val.extend(entries.iter().map(|e| e.1));
                    t.tri_ptr.push(t.val.len() - own);
                } else {
                    // Own columns r + 1..r1 first (sorted), then the shared ones: stored
                    // shared first.
                    t.val.extend(entries[own..].iter().map(|e| e.1));
                    t.tri_ptr.push(t.val.len());
                    t.val.extend(entries[..own].iter().map(|e| e.1));
                }
            }
            // `val_ptr[r + 1]` of the supernode's last row.
            t.val_ptr.push(t.val.len());
            t.tri_ptr.push(t.val.len());
        }
        t.gathered = vec![0.0; widest];
        if !lower {
            t.segments.reverse();
        }
        t
    }

    /// Stored entries, diagonal included.
    fn nnz(&self) -> usize {
        self.off_diagonal + self.diag_inv.len()
    }

    avx2_method! {
        /// [`Triangle::solve`] on AVX2's instructions where the processor has them (for the
        /// parts of a split factor, solved outside the AVX2 copy of the factor's solve).
        fn solve_in_place / solve_avx2(&mut self, x: &mut [f64]) => solve
    }

    /// `x <- T^{-1} x`.
    #[inline(always)]
    fn solve(&mut self, x: &mut [f64]) {
        assert!(x.len() == self.diag_inv.len());
        for &(r0, r1, seg) in &self.segments {
            let s = match seg {
                Segment::Super(s) => s,
                Segment::Pair(p) => {
                    self.solve_pair(p, r0, x);
                    continue;
                }
                Segment::Singles => {
                    if self.lower {
                        for r in r0..r1 {
                            self.solve_single(r, x);
                        }
                    } else {
                        for r in (r0..r1).rev() {
                            self.solve_single(r, x);
                        }
                    }
                    continue;
                }
            };
            let cols = &self.cols[self.cols_ptr[s]..self.cols_ptr[s + 1]];
            let nc = cols.len();
            let g = &mut self.gathered[..nc];
            for (gk, &c) in g.iter_mut().zip(cols) {
                debug_assert!((c as usize) < x.len());
                // SAFETY: the column indices are < n (checked in `from_csc`) and
                // `x.len() == n` (asserted above).
                *gk = unsafe { *x.get_unchecked(c as usize) };
            }
            let g = &self.gathered[..nc];
            // The supernode's rows are numbered from its first value row.
            let base = self.sn_first[s];
            if self.lower {
                for r in r0..r1 {
                    let k = base + (r - r0);
                    let (p, q, e) = (self.val_ptr[k], self.tri_ptr[k], self.val_ptr[k + 1]);
                    let sum =
                        dot_dense(&self.val[p..p + nc], g) + dot_dense(&self.val[q..e], &x[r0..r]);
                    x[r] = (x[r] - sum) * self.diag_inv[r];
                }
            } else {
                for r in (r0..r1).rev() {
                    let k = base + (r - r0);
                    let (p, q, e) = (self.val_ptr[k], self.tri_ptr[k], self.val_ptr[k + 1]);
                    let sum = dot_dense(&self.val[p..p + nc], g)
                        + dot_dense(&self.val[q..e], &x[r + 1..r1]);
                    x[r] = (x[r] - sum) * self.diag_inv[r];
                }
            }
        }
    }

    /// The rows `r0, r0 + 1` of pair `p`: both dot products in one gather over their shared
    /// columns, then the two unknowns in the triangle's order.
    #[inline(always)]
    fn solve_pair(&self, p: usize, r0: usize, x: &mut [f64]) {
        let range = self.pair_ptr[p]..self.pair_ptr[p + 1];
        let (idx, val) = (&self.pair_idx[range.clone()], &self.pair_val[range]);
        let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
        let (idx2, val2) = (idx.chunks_exact(4), val.chunks_exact(4));
        let (idx_rest, val_rest) = (idx2.remainder(), val2.remainder());
        for (ic, vc) in idx2.zip(val2) {
            for k in 0..4 {
                debug_assert!((ic[k] as usize) < x.len());
                // SAFETY: the indices of a `Triangle` are < n (checked in `from_csc`) and
                // its solves assert `x.len() == n`.
                let xc = unsafe { *x.get_unchecked(ic[k] as usize) };
                a[k] += vc[k][0] * xc;
                b[k] += vc[k][1] * xc;
            }
        }
        for (&i, v) in idx_rest.iter().zip(val_rest) {
            let xc = x[i as usize];
            a[0] += v[0] * xc;
            b[0] += v[1] * xc;
        }
        // The blocks: four entries on one index and two adjacent unknowns.
        let range = self.blk_ptr[p]..self.blk_ptr[p + 1];
        let (idx, val) = (&self.blk_idx[range.clone()], &self.blk_val[range]);
        let s = if self.avx2 {
            // SAFETY: `avx2` is set only where the processor has AVX2 (`from_csc`); the
            // block columns `c, c + 1` are < n and `x.len() == n` (asserted by the solves).
            #[cfg(target_arch = "x86_64")]
            unsafe {
                blocks_dot_avx2(idx, val, x)
            }
            #[cfg(not(target_arch = "x86_64"))]
            blocks_dot(idx, val, x)
        } else {
            blocks_dot(idx, val, x)
        };
        let (sa, sb) = (
            ((a[0] + a[1]) + (a[2] + a[3])) + (s[0] + s[1]),
            ((b[0] + b[1]) + (b[2] + b[3])) + (s[2] + s[3]),
        );
        let t = self.pair_coupling[p];
        let (r1, d) = (r0 + 1, &self.diag_inv);
        if self.lower {
            x[r0] = (x[r0] - sa) * d[r0];
            x[r1] = (x[r1] - sb - t * x[r0]) * d[r1];
        } else {
            x[r1] = (x[r1] - sb) * d[r1];
            x[r0] = (x[r0] - sa - t * x[r1]) * d[r0];
        }
    }

    /// `x[r] <- (x[r] - sum_c T[r, c] x[c]) / T[r, r]` for a row that is no supernode.
    #[inline(always)]
    fn solve_single(&self, r: usize, x: &mut [f64]) {
        let range = self.single_ptr[r]..self.single_ptr[r + 1];
        let s = dot_gather(&self.single_idx[range.clone()], &self.single_val[range], x);
        x[r] = (x[r] - s) * self.diag_inv[r];
    }
}

/// A lower triangular factor `Λ` in dense supernodes, for the forward solve `Λ x = b` and the
/// backward solve `Λ^T x = b` (the supernodal layout of CHOLMOD and faer).
///
/// A supernode is a run of columns `j0..j1` of `Λ` whose rows below the run, `R`, are the
/// same and that are full inside the run; its values are one packed column-major block
/// ([`packed_col`]; `w = j1 - j0` columns, `h = w + m` rows, `m = |R|`): column `k` holds
/// its rows `k..w` of the run, then the rows `R`, with no zeros above the diagonal. The forward solve of a supernode is a dense triangular solve on `x[j0..j1]`, a dense
/// product `y = Λ[R, j0..j1] x[j0..j1]` and a scatter `x[R] -= y`; the backward solve a
/// gather `y = x[R]`, a dense product `x[j0..j1] -= Λ[R, j0..j1]^T y` and a dense triangular
/// solve. One row index is read per row of a supernode rather than per entry. Supernodes
/// of fewer than 8 columns run in one pass over their rows ([`narrow_forward`]), wider ones
/// four columns per pass ([`wide_forward`]); both compiled for AVX2 where the processor has
/// it. The wide kernels replaced faer's dense triangular solve and product, whose dispatch
/// per supernode cost more than the arithmetic: the 48-ring free step 528 -> 501 us, its
/// Cholesky 484 -> 465 us (`softway matrix`, alternated binaries, three times).
///
/// The diagonal is held as its reciprocal (the sweeps multiply: a division's latency was
/// on the chain of dependent operations of every column), the wide supernodes' triangles
/// are solved in blocks of four columns (the rest of the run updated four columns per pass,
/// as the rows `R`), and factors larger than the second-level caches prefetch the blocks
/// ahead of the sweep ([`Supernodal::prefetch`]).
///
/// A wide supernode is read in one pass, four columns at a time, each block of columns
/// whole (its rows in the run, then in `R`) before the next, with the prefetch spread over
/// the pass ([`Ahead`]): two cache lines asked for per four rows read, 32 KiB ahead. The
/// kernels had read the triangle's columns first and the rows `R` in a second pass, and
/// had asked for the next 32 KiB only when a supernode began (nothing within a large one,
/// hundreds of lines at once after it). On the 192-ring disk the split forward sweep went
/// from 6.6-7.0 to 5.6-6.1 ms, the backward from 7.0-7.3 to 5.4-6.0, the top's backward
/// from 0.75 to 0.63 ms; the free step from 18.8-19.9 to 16.4-17.1 ms (an in-process
/// probe, alternated binaries, twice). The sums are made in the same order: the same bits.
#[derive(Debug, Clone, Default)]
struct Supernodal {
    /// Supernode `s` is the columns `bounds[s]..bounds[s + 1]`.
    bounds: Vec<usize>,
    rows_ptr: Vec<usize>,
    /// The rows `R` of each supernode, then its packed block: on huge pages when large
    /// ([`HugeBuf`]).
    rows: HugeBuf<u32>,
    blk_ptr: Vec<usize>,
    blk: HugeBuf<f64>,
    /// Work for `y` (the widest `R`).
    y: Vec<f64>,
    /// Stored entries of `Λ`, diagonal included.
    nnz: usize,
    /// The sweeps prefetch the blocks and rows they will read next (`PREFETCH_AHEAD`
    /// entries ahead), for factors that stream from memory (`PREFETCH_MIN_BYTES`).
    prefetch: bool,
}

impl Supernodal {
    /// From the CSC arrays of a lower triangular `Λ` (row indices in any order, every
    /// diagonal entry stored unless `unit`: a unit diagonal, stored or not).
    fn from_lower_csc(col_ptr: &[usize], row_idx: &[usize], values: &[f64], unit: bool) -> Self {
        let n = col_ptr.len() - 1;
        assert!(
            n <= u32::MAX as usize,
            "a factor too large for 32-bit indices"
        );
        let mut cols: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|j| {
                let mut c: Vec<(usize, f64)> = (col_ptr[j]..col_ptr[j + 1])
                    .map(|p| (row_idx[p], values[p]))
                    .collect();
                c.sort_unstable_by_key(|e| e.0);
                if unit {
                    match c.first_mut() {
                        Some(e) if e.0 == j => e.1 = 1.0,
                        _ => c.insert(0, (j, 1.0)),
                    }
                }
                assert!(
                    c.first().map(|e| e.0) == Some(j),
                    "a lower factor's column without its diagonal or with entries above it"
                );
                c
            })
            .collect();
        // Column j + 1 joins column j's supernode when the rows of j below its diagonal are
        // j + 1 and the rows of j + 1 below its diagonal.
        let mut bounds = vec![0usize];
        for j in 0..n.saturating_sub(1) {
            let (a, b) = (&cols[j][1..], &cols[j + 1][1..]);
            let joins = a.len() == b.len() + 1
                && a[0].0 == j + 1
                && a[1..].iter().zip(b).all(|(x, y)| x.0 == y.0);
            if !joins {
                bounds.push(j + 1);
            }
        }
        if n > 0 {
            bounds.push(n);
        }
        let mut t = Supernodal {
            rows_ptr: vec![0],
            blk_ptr: vec![0],
            nnz: cols.iter().map(Vec::len).sum(),
            ..Default::default()
        };
        let mut widest = 0;
        let (mut rows, mut blk) = (Vec::new(), Vec::new());
        for b in bounds.windows(2) {
            let (j0, j1) = (b[0], b[1]);
            let w = j1 - j0;
            let below: Vec<usize> = cols[j1 - 1][1..].iter().map(|e| e.0).collect();
            let m = below.len();
            widest = widest.max(m);
            rows.extend(below.iter().map(|&i| i as u32));
            t.rows_ptr.push(rows.len());
            for k in 0..w {
                let col = std::mem::take(&mut cols[j0 + k]);
                debug_assert_eq!(col.len(), w - k + m);
                // Rows k..w of the run (the diagonal first, held as its reciprocal: the
                // sweeps multiply), then R in order.
                blk.push(1.0 / col[0].1);
                blk.extend(col[1..].iter().map(|e| e.1));
            }
            debug_assert_eq!(
                blk.len() - t.blk_ptr[t.blk_ptr.len() - 1],
                packed_len(w, w + m)
            );
            t.blk_ptr.push(blk.len());
        }
        (t.rows, t.blk) = (rows.into(), blk.into());
        t.bounds = bounds;
        t.y = vec![0.0; widest];
        t
    }

    avx2_method! {
        /// `x <- Λ^{-1} x`, on AVX2's instructions where the processor has them.
        fn forward / forward_avx2(&mut self, x: &mut [f64]) => forward_here
    }

    avx2_method! {
        /// `x <- Λ^{-T} x`, on AVX2's instructions where the processor has them.
        fn backward / backward_avx2(&mut self, x: &mut [f64]) => backward_here
    }

    /// Bytes of the arrays each of the two sweeps reads (the blocks, row indices and
    /// pointers).
    fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.blk[..])
            + b(&self.rows[..])
            + b(&self.bounds[..])
            + b(&self.rows_ptr[..])
            + b(&self.blk_ptr[..])
    }

    /// Supernode `s`: its first column, width, rows below the run and block.
    #[inline(always)]
    fn supernode(&self, s: usize) -> (usize, usize, &[u32], &[f64]) {
        let j0 = self.bounds[s];
        (
            j0,
            self.bounds[s + 1] - j0,
            &self.rows[self.rows_ptr[s]..self.rows_ptr[s + 1]],
            &self.blk[self.blk_ptr[s]..self.blk_ptr[s + 1]],
        )
    }

    #[inline(always)]
    fn forward_here(&mut self, x: &mut [f64]) {
        let y = &mut std::mem::take(&mut self.y);
        // The prefetch cursors: entries of `blk` and `rows` before them have been asked for.
        let (mut pv, mut pr) = (0usize, 0usize);
        for s in 0..self.bounds.len() - 1 {
            let (j0, w, rows, blk) = self.supernode(s);
            if self.prefetch {
                // Up to PREFETCH_AHEAD entries after this supernode's block (a narrow one's:
                // a wide one prefetches as it goes) and rows.
                let (v1, r1) = (self.blk_ptr[s + 1], self.rows_ptr[s + 1]);
                if w < WIDE {
                    pv = prefetch_lines(&self.blk, pv.max(v1)..v1 + PREFETCH_AHEAD).max(pv);
                }
                pr = prefetch_lines(&self.rows, pr.max(r1)..r1 + PREFETCH_AHEAD).max(pr);
            }
            match w {
                // The wide kernels prefetch their block as they go, and the entries after it.
                _ if w >= WIDE && self.prefetch => {
                    wide_forward::<true>(blk, w, rows, j0, x, y);
                    pv = pv.max(self.blk_ptr[s + 1] + PREFETCH_AHEAD);
                }
                _ if w >= WIDE => wide_forward::<false>(blk, w, rows, j0, x, y),
                1 => narrow_forward::<1>(blk, rows, j0, x),
                2 => narrow_forward::<2>(blk, rows, j0, x),
                3 => narrow_forward::<3>(blk, rows, j0, x),
                4 => narrow_forward::<4>(blk, rows, j0, x),
                5 => narrow_forward::<5>(blk, rows, j0, x),
                6 => narrow_forward::<6>(blk, rows, j0, x),
                7 => narrow_forward::<7>(blk, rows, j0, x),
                _ => unreachable!("a narrow kernel for each width below WIDE"),
            }
        }
        self.y = std::mem::take(y);
    }

    #[inline(always)]
    fn backward_here(&mut self, x: &mut [f64]) {
        let y = &mut std::mem::take(&mut self.y);
        // The prefetch cursors: entries of `blk` and `rows` from them on have been asked for.
        let (mut pv, mut pr) = (self.blk.len(), self.rows.len());
        for s in (0..self.bounds.len() - 1).rev() {
            let (j0, w, rows, blk) = self.supernode(s);
            if self.prefetch {
                // Up to PREFETCH_AHEAD entries before this supernode's block (a narrow one's:
                // a wide one prefetches as it goes) and rows.
                let (v0, r0) = (self.blk_ptr[s], self.rows_ptr[s]);
                let (lo_v, lo_r) = (
                    v0.saturating_sub(PREFETCH_AHEAD),
                    r0.saturating_sub(PREFETCH_AHEAD),
                );
                if w < WIDE {
                    prefetch_lines(&self.blk, lo_v..pv.min(v0));
                    pv = pv.min(lo_v);
                }
                prefetch_lines(&self.rows, lo_r..pr.min(r0));
                pr = pr.min(lo_r);
            }
            match w {
                // The wide kernels prefetch their block as they go, and the entries before it.
                _ if w >= WIDE && self.prefetch => {
                    wide_backward::<true>(blk, w, rows, j0, x, y);
                    pv = pv.min(self.blk_ptr[s].saturating_sub(PREFETCH_AHEAD));
                }
                _ if w >= WIDE => wide_backward::<false>(blk, w, rows, j0, x, y),
                1 => narrow_backward::<1>(blk, rows, j0, x),
                2 => narrow_backward::<2>(blk, rows, j0, x),
                3 => narrow_backward::<3>(blk, rows, j0, x),
                4 => narrow_backward::<4>(blk, rows, j0, x),
                5 => narrow_backward::<5>(blk, rows, j0, x),
                6 => narrow_backward::<6>(blk, rows, j0, x),
                7 => narrow_backward::<7>(blk, rows, j0, x),
                _ => unreachable!("a narrow kernel for each width below WIDE"),
            }
        }
        self.y = std::mem::take(y);
    }
}

/// Bytes of the factors from which the dense supernodes' sweeps prefetch their blocks
/// ([`Supernodal::prefetch`]): below, a solve's factors stay in the second-level caches
/// between steps (2 MiB a core on the development host) and prefetching only adds
/// instructions. Factors in the last-level cache gain from it as much as those in memory,
/// since the wide kernels prefetch as they go ([`Ahead`]): the 48-ring disk (17 MB, in the
/// last-level cache) went from 0.47-0.48 to 0.38-0.40 ms a free step with the Coriolis term
/// on the right-hand side, from 0.47-0.48 to 0.42-0.44 ms in the exact scheme (an in-process
/// probe, alternated binaries, twice), where the threshold had been 64 MiB. Dense
/// supernodes are only used from 10,000 unknowns on, whose factors are larger.
const PREFETCH_MIN_BYTES: usize = 4 << 20;

/// How far ahead of the block being solved the sweeps prefetch, in entries: 32 KiB of
/// values and 16 KiB of row indices. With the 192-ring disk's factors streaming from memory
/// (176 MB a sweep), the split forward sweep took 7.3-7.6 ms instead of 8.5-8.9, the
/// backward 7.9-8.3 instead of 9.4-10.1 (alternated, same session); 4 and 16 KiB gained
/// less, and the non-temporal hint lost. Within the wide kernels ([`Ahead`]) the same
/// distance was best again: the 192-ring step 16.5-16.9 ms, against 17.4-18.3 at 16 KiB,
/// 17.3-18.1 at 64 KiB and 18.0-18.5 at 128 KiB (one binary, alternated, twice).
const PREFETCH_AHEAD: usize = 4096;

/// The narrowest supernode solved by the wide kernels ([`wide_forward`]); narrower ones
/// have a kernel each ([`narrow_forward`]).
const WIDE: usize = 8;

/// Turns on the prefetch of every one of `factors` (the dense supernodes of one solve) when
/// together they hold `PREFETCH_MIN_BYTES` or more, off otherwise.
fn prefetch_when_large<'a>(factors: impl IntoIterator<Item = &'a mut Supernodal>) {
    let factors: Vec<&mut Supernodal> = factors.into_iter().collect();
    let on = factors.iter().map(|f| f.bytes()).sum::<usize>() >= PREFETCH_MIN_BYTES;
    for f in factors {
        f.prefetch = on;
    }
}

/// Prefetches the cache lines of `data[range]` (its end clamped to the length; an empty
/// range asks for nothing) and returns the clamped end.
#[inline(always)]
fn prefetch_lines<T>(data: &[T], range: std::ops::Range<usize>) -> usize {
    let end = range.end.min(data.len());
    let step = (64 / std::mem::size_of::<T>()).max(1);
    for i in (range.start..end).step_by(step) {
        prefetch(data.as_ptr().wrapping_add(i));
    }
    end
}

/// Prefetches the cache lines of `data[range]` (its end clamped to the length), one per 64
/// bytes whatever the size of `T`.
#[inline(always)]
pub(crate) fn prefetch_span<T>(data: &[T], range: std::ops::Range<usize>) {
    let size = std::mem::size_of::<T>();
    let (start, end) = (range.start * size, range.end.min(data.len()) * size);
    let base = data.as_ptr().cast::<u8>();
    for b in (start..end).step_by(64) {
        prefetch(base.wrapping_add(b));
    }
}

/// Asks for the cache line at `p` in the second-level cache (a hint: no fault, no effect
/// on the results; nothing on other architectures).
#[inline(always)]
fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint; it never faults, whatever the address.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T1};
        _mm_prefetch::<_MM_HINT_T1>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Entries of a packed supernode block of `w` columns and `h` rows (column `k` holds its
/// rows `k..h`: no zeros above the diagonal).
#[inline(always)]
const fn packed_len(w: usize, h: usize) -> usize {
    w * h - (w * w - w) / 2
}

/// Column `k` of a packed supernode block of `h` rows ([`packed_len`]): its rows `k..h`,
/// the diagonal (as its reciprocal) first, then the rest of the run, then the rows below it.
#[inline(always)]
fn packed_col(blk: &[f64], h: usize, k: usize) -> &[f64] {
    let start = packed_start(h, k);
    &blk[start..start + h - k]
}

/// A prefetch that runs through a block ahead of a wide kernel's reads, two cache lines per
/// block of four rows of four columns read (the 128 bytes read), spread over the pass
/// rather than asked for at once; nothing at all unless `P`.
#[derive(Clone, Copy)]
struct Ahead<const P: bool> {
    /// The next line to ask for (a hint's address: it may lie outside the block).
    p: *const f64,
    /// `1` when the pass runs up the block, `-1` down.
    dir: isize,
}

impl<const P: bool> Ahead<P> {
    /// From entry `at` of `blk` up (`dir = 1`) or down (`dir = -1`).
    #[inline(always)]
    fn new(blk: &[f64], at: isize, dir: isize) -> Self {
        Self {
            p: blk.as_ptr().wrapping_offset(at),
            dir,
        }
    }

    /// Asks for the next two lines.
    #[inline(always)]
    fn next(&mut self) {
        if P {
            prefetch(self.p);
            prefetch(self.p.wrapping_offset(8 * self.dir));
            self.p = self.p.wrapping_offset(16 * self.dir);
        }
    }
}

/// Four values as an array (`c` has four).
#[inline(always)]
fn quad(c: &[f64]) -> [f64; 4] {
    [c[0], c[1], c[2], c[3]]
}

/// `out[q] -= (c0[q] v0 + c1[q] v1) + (c2[q] v2 + c3[q] v3)` for every `q` of `out` (four
/// columns of a supernode's block, each a contiguous stream, in one pass), with `pf` moved
/// on as the rows are read. Four rows at a time taken as arrays ([`quad`]), which LLVM
/// turns into one four-wide operation per column; indexing the chunks row by row had left
/// it scalar (sixteen multiplications a pass instead of four). Lane by lane the same
/// operations in the same order: the same bits. On the 48-ring disk the top's forward sweep
/// went from 0.034 to 0.031 ms and the exact free step from 0.465-0.476 to 0.447-0.456 ms
/// (an in-process probe, alternated binaries, 15 rounds of 1,000 steps, four times).
#[inline(always)]
fn sub_columns4<const P: bool>(out: &mut [f64], c: [&[f64]; 4], v: [f64; 4], pf: &mut Ahead<P>) {
    let m = out.len();
    let m4 = m - m % 4;
    for ((((o, p0), p1), p2), p3) in out[..m4]
        .chunks_exact_mut(4)
        .zip(c[0][..m4].chunks_exact(4))
        .zip(c[1][..m4].chunks_exact(4))
        .zip(c[2][..m4].chunks_exact(4))
        .zip(c[3][..m4].chunks_exact(4))
    {
        pf.next();
        let (p0, p1, p2, p3) = (quad(p0), quad(p1), quad(p2), quad(p3));
        let r: [f64; 4] = std::array::from_fn(|l| {
            o[l] - ((p0[l] * v[0] + p1[l] * v[1]) + (p2[l] * v[2] + p3[l] * v[3]))
        });
        o.copy_from_slice(&r);
    }
    for q in m4..m {
        out[q] -= (c[0][q] * v[0] + c[1][q] * v[1]) + (c[2][q] * v[2] + c[3][q] * v[3]);
    }
}

/// The four dot products `c_k . y` (four columns of a supernode's block against `y`) in one
/// pass, each in four partial sums (rows `q..q + 4` one vector), with `pf` moved on as the
/// rows are read.
#[inline(always)]
fn dot_columns4<const P: bool>(c: [&[f64]; 4], y: &[f64], pf: &mut Ahead<P>) -> [f64; 4] {
    let m = y.len();
    let m4 = m - m % 4;
    let (mut a0, mut a1, mut a2, mut a3) = ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
    for ((((yc, p0), p1), p2), p3) in y[..m4]
        .chunks_exact(4)
        .zip(c[0][..m4].chunks_exact(4))
        .zip(c[1][..m4].chunks_exact(4))
        .zip(c[2][..m4].chunks_exact(4))
        .zip(c[3][..m4].chunks_exact(4))
    {
        pf.next();
        for l in 0..4 {
            a0[l] += p0[l] * yc[l];
            a1[l] += p1[l] * yc[l];
            a2[l] += p2[l] * yc[l];
            a3[l] += p3[l] * yc[l];
        }
    }
    let mut acc = [a0, a1, a2, a3];
    for (a, cc) in acc.iter_mut().zip(&c) {
        for q in m4..m {
            a[0] += cc[q] * y[q];
        }
    }
    acc.map(|a| (a[0] + a[1]) + (a[2] + a[3]))
}

/// Offset of column `k` in a packed supernode block of `h` rows ([`packed_col`]).
#[inline(always)]
const fn packed_start(h: usize, k: usize) -> usize {
    k * h - (k * k - k) / 2
}

/// The forward solve of a supernode of `w` columns `j0..j0 + w` (layout of
/// [`narrow_forward`], the diagonal held as its reciprocal), one pass over its block in
/// blocks of four columns: each block's own small triangle on `x[j0..]`, then the run's
/// rows below it updated four columns per pass, then `y -= Λ[R, k..k + 4] (-x_k..)`;
/// last `x[R] -= y`. With `P`, the lines `PREFETCH_AHEAD` entries ahead of the pass are
/// asked for as it goes ([`Ahead`]).
#[inline(always)]
fn wide_forward<const P: bool>(
    blk: &[f64],
    w: usize,
    rows: &[u32],
    j0: usize,
    x: &mut [f64],
    y: &mut [f64],
) {
    let (m, h) = (rows.len(), w + rows.len());
    debug_assert_eq!(blk.len(), packed_len(w, h));
    let xs = &mut x[j0..j0 + w];
    let y = &mut y[..m];
    y.fill(0.0);
    let below = |k: usize| &packed_col(blk, h, k)[w - k..];
    let mut k = 0;
    while k < w {
        let kb = (w - k).min(4);
        let mut pf = Ahead::<P>::new(blk, (packed_start(h, k) + PREFETCH_AHEAD) as isize, 1);
        for kk in k..k + kb {
            let col = packed_col(blk, h, kk);
            let xk = xs[kk] * col[0];
            xs[kk] = xk;
            for i in kk + 1..k + kb {
                xs[i] -= col[i - kk] * xk;
            }
        }
        if kb == 4 {
            if k + 4 < w {
                // Rows k + 4..w of columns k..k + 4.
                let c = std::array::from_fn(|l| &packed_col(blk, h, k + l)[4 - l..w - k - l]);
                let v = [xs[k], xs[k + 1], xs[k + 2], xs[k + 3]];
                sub_columns4(&mut xs[k + 4..], c, v, &mut pf);
            }
            let c = [below(k), below(k + 1), below(k + 2), below(k + 3)];
            let v = [-xs[k], -xs[k + 1], -xs[k + 2], -xs[k + 3]];
            sub_columns4(y, c, v, &mut pf);
        } else {
            for kk in k..w {
                let (c, xk) = (below(kk), xs[kk]);
                for (yq, &cq) in y.iter_mut().zip(c) {
                    *yq += cq * xk;
                }
            }
        }
        k += kb;
    }
    for (&i, &yq) in rows.iter().zip(y.iter()) {
        x[i as usize] -= yq;
    }
}

/// The backward solve of a supernode of `w` columns (layout of [`narrow_forward`], the
/// diagonal held as its reciprocal), one pass over its block in blocks of four columns from
/// the last: `y = x[R]` first, then for each block `x_k -= Λ[R, k] . y` (four dot products
/// in one pass), the run's rows below the block the same way, and the block's own small
/// transposed triangle. With `P`, the lines `PREFETCH_AHEAD` entries below the pass (it runs
/// down the block) are asked for as it goes ([`Ahead`]).
#[inline(always)]
fn wide_backward<const P: bool>(
    blk: &[f64],
    w: usize,
    rows: &[u32],
    j0: usize,
    x: &mut [f64],
    y: &mut [f64],
) {
    let (m, h) = (rows.len(), w + rows.len());
    debug_assert_eq!(blk.len(), packed_len(w, h));
    let y = &mut y[..m];
    for (yq, &i) in y.iter_mut().zip(rows) {
        *yq = x[i as usize];
    }
    let below = |k: usize| &packed_col(blk, h, k)[w - k..];
    let xs = &mut x[j0..j0 + w];
    for k in (0..w).step_by(4).rev() {
        let kb = (w - k).min(4);
        // Down from the line below PREFETCH_AHEAD entries before the block's first column.
        let at = packed_start(h, k) as isize - PREFETCH_AHEAD as isize;
        let mut pf = Ahead::<P>::new(blk, at - 8, -1);
        if kb == 4 {
            let d = dot_columns4(
                [below(k), below(k + 1), below(k + 2), below(k + 3)],
                y,
                &mut pf,
            );
            for (l, dl) in d.iter().enumerate() {
                xs[k + l] -= dl;
            }
            if k + 4 < w {
                // Rows k + 4..w of columns k..k + 4.
                let c = std::array::from_fn(|l| &packed_col(blk, h, k + l)[4 - l..w - k - l]);
                let d = dot_columns4(c, &xs[k + 4..], &mut pf);
                for (l, dl) in d.iter().enumerate() {
                    xs[k + l] -= dl;
                }
            }
        } else {
            for kk in k..w {
                xs[kk] -= dot_dense(below(kk), y);
            }
        }
        for kk in (k..k + kb).rev() {
            let col = packed_col(blk, h, kk);
            let mut a = xs[kk];
            for i in kk + 1..k + kb {
                a -= col[i - kk] * xs[i];
            }
            xs[kk] = a * col[0];
        }
    }
}

/// The forward solve of a narrow supernode of `W` columns `j0..j0 + W` (packed block `blk`
/// of `W + m` rows, [`packed_col`]; rows below the run `rows`) in one pass over its rows: the `W x W`
/// triangle on `x[j0..]`, then each row `i` of `rows` gets `x[i] -= sum_k blk[i, k] x_k`
/// (no work vector: faer's dispatch and three passes over one cost more for these).
#[inline(always)]
fn narrow_forward<const W: usize>(blk: &[f64], rows: &[u32], j0: usize, x: &mut [f64]) {
    let h = W + rows.len();
    debug_assert_eq!(blk.len(), packed_len(W, h));
    let mut xs = [0.0; W];
    xs.copy_from_slice(&x[j0..j0 + W]);
    for k in 0..W {
        let col = packed_col(blk, h, k);
        let xk = xs[k] * col[0];
        xs[k] = xk;
        for i in k + 1..W {
            xs[i] -= col[i - k] * xk;
        }
    }
    x[j0..j0 + W].copy_from_slice(&xs);
    let cols: [&[f64]; W] = std::array::from_fn(|k| &packed_col(blk, h, k)[W - k..]);
    // Four rows at a time, their sums as one array (a four-wide operation per column).
    let m = rows.len();
    let m4 = m - m % 4;
    for (q, r) in (0..m4).step_by(4).zip(rows.chunks_exact(4)) {
        let mut s = [0.0; 4];
        for k in 0..W {
            let c = quad(&cols[k][q..q + 4]);
            for l in 0..4 {
                s[l] += c[l] * xs[k];
            }
        }
        for (&i, sl) in r.iter().zip(s) {
            x[i as usize] -= sl;
        }
    }
    for (q, &i) in rows.iter().enumerate().skip(m4) {
        let mut s = 0.0;
        for k in 0..W {
            s += cols[k][q] * xs[k];
        }
        x[i as usize] -= s;
    }
}

/// The backward solve of a narrow supernode (layout of [`narrow_forward`]) in one pass over
/// its rows: `x_k -= sum_i blk[i, k] x[i]` over `rows`, then the transposed triangle.
#[inline(always)]
fn narrow_backward<const W: usize>(blk: &[f64], rows: &[u32], j0: usize, x: &mut [f64]) {
    let h = W + rows.len();
    debug_assert_eq!(blk.len(), packed_len(W, h));
    let cols: [&[f64]; W] = std::array::from_fn(|k| &packed_col(blk, h, k)[W - k..]);
    // Four rows at a time into four partial sums per column: one sum per column would be
    // one chain of dependent additions, a row per addition's latency.
    let m = rows.len();
    let m4 = m - m % 4;
    // part[k][l]: column k's sum over rows q + l, four rows a pass (one four-wide operation
    // per column).
    let mut part = [[0.0; 4]; W];
    for (q, r) in (0..m4).step_by(4).zip(rows.chunks_exact(4)) {
        let xq = [r[0], r[1], r[2], r[3]].map(|i| x[i as usize]);
        for k in 0..W {
            let c = quad(&cols[k][q..q + 4]);
            for l in 0..4 {
                part[k][l] += c[l] * xq[l];
            }
        }
    }
    for q in m4..m {
        let xi = x[rows[q] as usize];
        for k in 0..W {
            part[k][0] += cols[k][q] * xi;
        }
    }
    let acc: [f64; W] =
        std::array::from_fn(|k| (part[k][0] + part[k][1]) + (part[k][2] + part[k][3]));
    for k in (0..W).rev() {
        let col = packed_col(blk, h, k);
        let mut a = x[j0 + k] - acc[k];
        for i in k + 1..W {
            a -= col[i - k] * x[j0 + i];
        }
        x[j0 + k] = a * col[0];
    }
}

/// The columns (CSC: column pointers, row indices, values) of the lower triangular factor
/// held by faer's supernodal Cholesky `sn` with the values `val`: supernode `s`, columns
/// `j0..j1`, is a column-major block of `j1 - j0 + |P|` rows (the diagonal block, then the
/// rows `P` below it); column `j0 + k` is its rows `k..` of the diagonal block and `P`.
/// Entries that are exactly zero off the diagonal are left out: they are the padding of
/// faer's relaxed supernodes (outside the elimination's structure, they stay zero), so the
/// columns are those of the simplicial factor and a solve reads no more bytes.
fn supernodal_columns(
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

/// The CSC arrays of the transpose of a square CSC matrix.
fn transpose_csc(
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

/// The smallest order from which the factors are solved in dense supernodes
/// ([`Supernodal`]); smaller factors by rows ([`Triangle`]), whose supernodes are narrow.
/// Measured: on the paper's wheel (938 dofs) the rows take fewer instructions, on the
/// converged wheel (3,430 dofs) about 10% less time; on the 48-ring disk (14,114 dofs) the
/// dense supernodes take about 10% less time.
const DENSE_SUPERNODAL_MIN_ORDER: usize = 10_000;

/// The fewest rows of a supernode of a [`Triangle`] (runs of two rows are pairs, other
/// shorter runs are solved row by row).
const MIN_SUPERNODE: usize = 4;

/// Whether the processor has AVX2 (the one test of [`with_avx2`] and of the block kernels'
/// flags).
pub(crate) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The blocks of a pair of rows `r0, r0 + 1` of a [`Triangle`]: block `k` is the column
/// `c = idx[k]` and the next, its values `val[k] = [T[r0, c], T[r0, c + 1], T[r0 + 1, c],
/// T[r0 + 1, c + 1]]`. Returns the lane sums `s` of `val[k][l] * [x[c], x[c + 1], x[c],
/// x[c + 1]][l]`, even blocks and odd blocks in two sums added lane by lane at the end (row
/// `r0`'s dot product is `s[0] + s[1]`, row `r0 + 1`'s `s[2] + s[3]`): the order of
/// [`blocks_dot_avx2`]'s lanes, so that both give the same bits.
///
/// # Panics
/// When `c + 1` is out of range of `x` for a block (debug builds; the factors' indices are
/// checked when they are built).
#[inline(always)]
fn blocks_dot(idx: &[u32], val: &[[f64; 4]], x: &[f64]) -> [f64; 4] {
    let (mut s0, mut s1) = ([0.0; 4], [0.0; 4]);
    let lanes = |c: u32| {
        let c = c as usize;
        debug_assert!(c + 1 < x.len());
        // SAFETY: a block's columns `c, c + 1` are < n (checked in `Triangle::from_csc`)
        // and the solves assert `x.len() == n`.
        let (x0, x1) = unsafe { (*x.get_unchecked(c), *x.get_unchecked(c + 1)) };
        [x0, x1, x0, x1]
    };
    let (idx2, val2) = (idx.chunks_exact(2), val.chunks_exact(2));
    let (idx_rest, val_rest) = (idx2.remainder(), val2.remainder());
    for (ic, vc) in idx2.zip(val2) {
        let (x0, x1) = (lanes(ic[0]), lanes(ic[1]));
        for l in 0..4 {
            s0[l] += vc[0][l] * x0[l];
            s1[l] += vc[1][l] * x1[l];
        }
    }
    for (&c, v) in idx_rest.iter().zip(val_rest) {
        let x0 = lanes(c);
        for l in 0..4 {
            s0[l] += v[l] * x0[l];
        }
    }
    [s0[0] + s1[0], s0[1] + s1[1], s0[2] + s1[2], s0[3] + s1[3]]
}

/// [`blocks_dot`] on 256-bit registers: per block one broadcast of `x[c..c + 2]` to both
/// halves, one product and one sum of four lanes (the compiler does not find this layout
/// itself; left to itself it permuted the values or kept to 128-bit registers, 0.5 us
/// slower per step on the paper's wheel).
///
/// # Safety
/// The processor must have AVX2, and `c + 1 < x.len()` for every block column `c`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn blocks_dot_avx2(idx: &[u32], val: &[[f64; 4]], x: &[f64]) -> [f64; 4] {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd, _mm256_storeu_pd,
    };
    debug_assert_eq!(idx.len(), val.len());
    let (mut s0, mut s1) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let xp = x.as_ptr();
    let vp = val.as_ptr() as *const f64;
    let n2 = idx.len() / 2;
    for k in 0..n2 {
        let (c0, c1) = (
            *idx.get_unchecked(2 * k) as usize,
            *idx.get_unchecked(2 * k + 1) as usize,
        );
        debug_assert!(c0 + 1 < x.len() && c1 + 1 < x.len());
        let x0 = broadcast2(xp.add(c0));
        let x1 = broadcast2(xp.add(c1));
        let v0 = _mm256_loadu_pd(vp.add(8 * k));
        let v1 = _mm256_loadu_pd(vp.add(8 * k + 4));
        s0 = _mm256_add_pd(s0, _mm256_mul_pd(v0, x0));
        s1 = _mm256_add_pd(s1, _mm256_mul_pd(v1, x1));
    }
    if idx.len() % 2 == 1 {
        let k = idx.len() - 1;
        let c = *idx.get_unchecked(k) as usize;
        debug_assert!(c + 1 < x.len());
        let x0 = broadcast2(xp.add(c));
        s0 = _mm256_add_pd(s0, _mm256_mul_pd(_mm256_loadu_pd(vp.add(4 * k)), x0));
    }
    let mut out = [0.0; 4];
    _mm256_storeu_pd(out.as_mut_ptr(), _mm256_add_pd(s0, s1));
    out
}

/// `[p[0], p[1], p[0], p[1]]`: two adjacent `f64`s, unaligned, in both halves of a 256-bit
/// register (one `vbroadcastf128`; a `&__m128d` to them would claim an alignment they do
/// not have).
///
/// # Safety
/// The processor must have AVX2 and `p`, `p + 1` must be readable.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn broadcast2(p: *const f64) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::{_mm256_set_m128d, _mm_loadu_pd};
    let t = _mm_loadu_pd(p);
    _mm256_set_m128d(t, t)
}

/// `sum_k a[k] b[k]` over the shorter of the two, in four partial sums.
#[inline(always)]
fn dot_dense(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (a_rest, b_rest) = (a4.remainder(), b4.remainder());
    for (ac, bc) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] += ac[k] * bc[k];
        }
    }
    for (p, q) in a_rest.iter().zip(b_rest) {
        acc[0] += p * q;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// `sum_k val[k] x[idx[k]]` in four partial sums (the additions are not one chain of
/// dependent operations).
///
/// # Panics
/// When an index is out of range of `x` (debug builds; the factors' indices are checked
/// when they are built).
#[inline(always)]
fn dot_gather(idx: &[u32], val: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (idx4, val4) = (idx.chunks_exact(4), val.chunks_exact(4));
    let (idx_rest, val_rest) = (idx4.remainder(), val4.remainder());
    for (ic, vc) in idx4.zip(val4) {
        for k in 0..4 {
            debug_assert!((ic[k] as usize) < x.len());
            // SAFETY: the indices of a `Triangle` are < n (checked in `from_csc`) and its
            // solves assert `x.len() == n`.
            acc[k] += vc[k] * unsafe { *x.get_unchecked(ic[k] as usize) };
        }
    }
    for (&i, &v) in idx_rest.iter().zip(val_rest) {
        acc[0] += v * x[i as usize];
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// Sparse LU factorization `P A Q = L U` (faer's simplicial LU with partial pivoting) with
/// the column ordering `Q` computed once.
///
/// [`SparseLu::refactor`] reuses the ordering for new values on the same pattern;
/// [`SparseLu::solve_in_place`] reuses scratch memory allocated at construction.
pub struct SparseLu {
    ordering: Ordering,
    col_fwd: Vec<usize>,
    col_inv: Vec<usize>,
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    /// faer's factors (emptied after each factorization: the solve uses `l`, `u`).
    numeric: SimplicialLu<usize, f64>,
    l: Triangle,
    u: Triangle,
    /// `L` and `U^T` in dense supernodes (from `DENSE_SUPERNODAL_MIN_ORDER` on) or in the
    /// three parts of a split ordering; then `l` and `u` stay empty.
    stored: Option<Stored>,
    /// The order from which dense supernodes are used (`DENSE_SUPERNODAL_MIN_ORDER`).
    dense_from: usize,
    /// The ordering's two independent parts, positions `0..a` and `a..b`, before the top
    /// (`split::two_subtrees`), when it has them.
    parts: Option<(usize, usize)>,
    work: Vec<f64>,
    n: usize,
}

/// `L` and `U^T` stored otherwise than whole by rows: whole in dense supernodes, or in the
/// three parts of an ordering split for two threads ([`SplitLower`], by rows or in dense
/// supernodes).
#[derive(Debug, Clone)]
enum Stored {
    Supernodes(Box<(Supernodal, Supernodal)>),
    Split(Box<(SplitLower, SplitLower)>),
}

/// The order from which the column ordering is split into two independent parts and a top
/// (`split::two_subtrees`) for solves on two threads (by rows below
/// `DENSE_SUPERNODAL_MIN_ORDER`, in dense supernodes from it on). The split is made whatever
/// the thread count, so that a run's result does not depend on it. Measured with
/// `softway matrix` (median of five rounds, alternated binaries, twice), the free step by
/// rows, whole against split, on two threads: 2,054 dofs (18 rings) 57 -> 37 us, 3,432
/// (`wheel.toml`) 108 -> 55 us, 7,948 (576 rim nodes) 335 -> 180 us; on one thread the
/// split costs 10-20% (57 -> 62-67, 100 -> 118, 330 -> 338-367 us). On the paper's wheel
/// (938 dofs) it gave 18 against 20 us per free step and nothing in the run's loop.
///
/// From the same order the time loop's other work on whole vectors runs on two threads as
/// well (the right-hand side's halves, the held nodes' columns, the energies): the steps
/// there already hand work to the second thread.
pub(crate) const SPLIT_MIN_ORDER: usize = 1_500;

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.n)
            .field("ordering", &self.ordering)
            .finish()
    }
}

/// The column permutation of `ordering` for `pattern`: `(forward, inverse)`.
fn column_ordering(
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
    }
    Ok((fwd, inv))
}

impl SparseLu {
    /// The same factor solved in dense supernodes (`dense`) or by rows, whatever the order.
    #[cfg(test)]
    fn with_layout(mut self, pattern: &Pattern, values: &[f64], dense: bool) -> Self {
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
        Self::build(
            pattern,
            values,
            ordering,
            pattern.nrows() >= SPLIT_MIN_ORDER,
        )
    }

    /// Orders the columns with `ordering`, split for two threads when `split` and the
    /// ordering has two independent parts, and factors the matrix.
    fn build(
        pattern: &Pattern,
        values: &[f64],
        ordering: Ordering,
        split: bool,
    ) -> Result<Self, LinalgError> {
        let n = pattern.nrows();
        let (mut col_fwd, mut col_inv) = column_ordering(pattern, ordering)?;
        let mut parts = None;
        if split {
            if let Some(s) = split::best_split(pattern, &col_fwd, &col_inv) {
                (col_fwd, col_inv, parts) = (s.fwd, s.inv, Some((s.a, s.b)));
            }
        }
        let mut lu = Self {
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
            parts: self.parts,
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
        let split = self.parts.and_then(|ab| {
            Some(Stored::Split(Box::new((
                SplitLower::from_lower_csc(lc, lr, l.val(), true, ab, fwd)?,
                SplitLower::from_lower_csc(&tc, &tr, &tv, false, ab, bwd)?,
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

    /// The orders of the two parts solved side by side and of the top after them, when the
    /// factor is split for two threads (module `split`).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match &self.stored {
            Some(Stored::Split(lu)) => Some(lu.0.sizes()),
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
        /// On AVX2's instructions where the processor has them (the macro `with_avx2`); a
        /// split factor's parts side by side on `team`'s threads.
        pub fn solve_on / solve_avx2(&mut self, team: &Team, rhs: &mut [f64]) => solve_here
    }

    /// [`SparseLu::solve_on`] with the default team (`rayon::join` in the caller's pool).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_on(&Team::default(), rhs);
    }

    #[inline(always)]
    fn solve_here(&mut self, team: &Team, rhs: &mut [f64]) {
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

/// Sparse Cholesky factorization `A = L L^T` of a symmetric positive definite matrix (only
/// the upper triangle is read), symbolic analysis (AMD ordering) once, solve without
/// allocation.
pub struct SparseLlt {
    symbolic: SymbolicCholesky<usize>,
    /// faer's factor (emptied after each factorization: the solve uses `l`).
    numeric: Vec<f64>,
    l: Triangle,
    /// `L^T` by rows (the columns of `L`).
    lt: Triangle,
    /// `L` in dense supernodes (from `DENSE_SUPERNODAL_MIN_ORDER` on) or in the three parts
    /// of a split ordering; then `l` and `lt` stay empty.
    stored: Option<StoredLower>,
    /// The order from which dense supernodes are used (`DENSE_SUPERNODAL_MIN_ORDER`).
    dense_from: usize,
    /// The ordering's two independent parts, positions `0..a` and `a..b`, before the top
    /// (`split::two_subtrees`), when it has them.
    parts: Option<(usize, usize)>,
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    work: Vec<f64>,
    n: usize,
}

/// A Cholesky factor `L` stored otherwise than whole by rows: whole in dense supernodes, or
/// in the three parts of an ordering split for two threads ([`SplitLower`], by rows or in
/// dense supernodes).
#[derive(Debug, Clone)]
enum StoredLower {
    Supernodes(Supernodal),
    Split(Box<SplitLower>),
}

impl std::fmt::Debug for SparseLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLlt").field("n", &self.n).finish()
    }
}

impl SparseLlt {
    /// The same factor solved in dense supernodes (`dense`) or by rows, whatever the order.
    #[cfg(test)]
    fn with_layout(mut self, pattern: &Pattern, values: &[f64], dense: bool) -> Self {
        self.dense_from = if dense { 0 } else { usize::MAX };
        self.refactor(pattern, values).unwrap();
        self
    }

    /// Analyses (AMD ordering, split into two independent parts and a top for two threads
    /// from `SPLIT_MIN_ORDER` on, as [`SparseLu`]) and factors.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::build(pattern, values, pattern.nrows() >= SPLIT_MIN_ORDER)
    }

    /// Analyses, with the AMD ordering split for two threads when `split` and the ordering
    /// has two independent parts, and factors.
    fn build(pattern: &Pattern, values: &[f64], split: bool) -> Result<Self, LinalgError> {
        let supernodal = pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER;
        Self::build_with(pattern, values, split, supernodal)
    }

    /// [`SparseLlt::build`] with faer's supernodal factorization (`supernodal`) or its
    /// simplicial one.
    fn build_with(
        pattern: &Pattern,
        values: &[f64],
        split: bool,
        supernodal: bool,
    ) -> Result<Self, LinalgError> {
        let n = pattern.nrows();
        let mut parts = None;
        let mut custom = None;
        if split {
            let (fwd, inv) = column_ordering(pattern, Ordering::Amd)?;
            if let Some(s) = split::best_split(pattern, &fwd, &inv) {
                custom = Some((s.fwd, s.inv));
                parts = Some((s.a, s.b));
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
        let ordering = match &custom {
            Some((f, i)) => SymmetricOrdering::Custom(PermRef::new_checked(f, i, n)),
            None => SymmetricOrdering::Amd,
        };
        let symbolic = factorize_symbolic_cholesky(pattern.as_ref(), Side::Upper, ordering, params)
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
            symbolic,
            l: Triangle::default(),
            lt: Triangle::default(),
            stored: None,
            dense_from: DENSE_SUPERNODAL_MIN_ORDER,
            parts,
            perm_fwd,
            perm_inv,
            work: vec![0.0; n],
            n,
        };
        llt.refactor(pattern, values)?;
        Ok(llt)
    }

    /// A second factorization of `values` on the same pattern (faer's symbolic Cholesky
    /// cannot be cloned: the analysis is made again, which is cheap beside the factor).
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when the matrix is not positive definite.
    pub fn with_values(&self, pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        Self::new(pattern, values)
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
        let split = self.parts.and_then(|ab| {
            SplitLower::from_lower_csc(cp, ri, numeric, false, ab, layout)
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

    /// The orders of the two parts solved side by side and of the top after them, when the
    /// factor is split for two threads (module `split`).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match &self.stored {
            Some(StoredLower::Split(l)) => Some(l.sizes()),
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

    #[inline(always)]
    fn solve_here(&mut self, team: &Team, rhs: &mut [f64]) {
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

/// Which factorization a step matrix gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorKind {
    /// LU with partial pivoting and the given column ordering (the reference: any matrix).
    Lu(Ordering),
    /// Cholesky `L L^T` (AMD ordering): symmetric positive definite matrices only.
    Llt,
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
        if is_symmetric(pattern, values, 1e-14) {
            if let Ok(f) = Factor::new(pattern, values, FactorKind::Llt) {
                return Ok(f);
            }
        }
        Factor::new(pattern, values, FactorKind::Lu(Ordering::Amd))
    }

    /// The kind.
    pub fn kind(&self) -> FactorKind {
        match self {
            Factor::Lu(lu) => FactorKind::Lu(lu.ordering()),
            Factor::Llt(_) => FactorKind::Llt,
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
        }
    }

    /// The orders of the two parts solved side by side and of the top, when the factor is
    /// split for two threads ([`SparseLu::parts`], [`SparseLlt::parts`]).
    pub fn parts(&self) -> Option<(usize, usize, usize)> {
        match self {
            Factor::Lu(lu) => lu.parts(),
            Factor::Llt(llt) => llt.parts(),
        }
    }

    /// Stored entries of the factors (`L + U`, or `L`).
    pub fn factor_nnz(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.factor_nnz(),
            Factor::Llt(llt) => llt.factor_nnz(),
        }
    }

    /// Bytes of the factors that a solve reads, as stored (each sweep's arrays; one copy
    /// read by both sweeps counts twice).
    pub fn solve_bytes(&self) -> usize {
        match self {
            Factor::Lu(lu) => lu.solve_bytes(),
            Factor::Llt(llt) => llt.solve_bytes(),
        }
    }

    /// Solves `A x = rhs` in place, without allocating (a split factor's parts side by
    /// side through the default team, `rayon::join` in the caller's pool).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_on(&Team::default(), rhs);
    }

    /// Solves `A x = rhs` in place, without allocating, a split factor's parts side by side
    /// on `team`'s threads (the same bits on any team).
    pub fn solve_on(&mut self, team: &Team, rhs: &mut [f64]) {
        match self {
            Factor::Lu(lu) => lu.solve_on(team, rhs),
            Factor::Llt(llt) => llt.solve_on(team, rhs),
        }
    }
}

/// faer's own sparse LU (its COLAMD ordering and generic solves), with its solve scratch:
/// the reference softway's factors ([`SparseLu`], [`SparseLlt`]) are checked and timed
/// against (the unit tests here, `tests/factor.rs`, `benches/step.rs`). The solver does not
/// use it.
pub struct FaerLu {
    n: usize,
    symbolic: faer::sparse::linalg::lu::SymbolicLu<usize>,
    numeric: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    mem: MemBuffer,
}

impl std::fmt::Debug for FaerLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaerLu").field("n", &self.n).finish()
    }
}

impl FaerLu {
    /// Factors `values` on `pattern`.
    ///
    /// # Errors
    /// [`LinalgError`] when faer cannot factor the matrix.
    pub fn new(pattern: &Pattern, values: &[f64]) -> Result<Self, LinalgError> {
        use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu};
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .map_err(|e| LinalgError::Symbolic(format!("{e:?}")))?;
        let mut numeric = NumericLu::new();
        let mut mem = MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_lu(
                &mut numeric,
                SparseColMatRef::new(pattern.as_ref(), values),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| LinalgError::Singular(format!("{e:?}")))?;
        let mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self {
            n: pattern.nrows(),
            symbolic,
            numeric,
            mem,
        })
    }

    /// `rhs <- A^{-1} rhs`.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric)
            .solve_in_place_with_conj(
                faer::Conj::No,
                MatMut::from_column_major_slice_mut(rhs, self.n, 1),
                Par::Seq,
                MemStack::new(&mut self.mem),
            );
    }
}

/// True when the values on `pattern` are symmetric to within `rel_tol` times the largest
/// magnitude (the pattern itself must be structurally symmetric: an entry without its
/// transposed partner makes the matrix unsymmetric).
pub fn is_symmetric(pattern: &Pattern, values: &[f64], rel_tol: f64) -> bool {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let scale = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let tol = rel_tol * scale;
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i <= j {
                continue;
            }
            // Entry (i, j) below the diagonal: find (j, i) in column i.
            let col = &ri[cp[i]..cp[i + 1]];
            match col.binary_search(&j) {
                Ok(q) => {
                    if (values[p] - values[cp[i] + q]).abs() > tol {
                        return false;
                    }
                }
                Err(_) => return false,
            }
        }
    }
    true
}

/// For each stored entry `(i, j)` of `pattern`, the position of `(j, i)`; None when the
/// pattern is not structurally symmetric.
pub fn transpose_positions(pattern: &Pattern) -> Option<Vec<usize>> {
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut t = vec![0; cp[pattern.ncols()]];
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            let col = &ri[cp[i]..cp[i + 1]];
            t[p] = cp[i] + col.binary_search(&j).ok()?;
        }
    }
    Some(t)
}

/// Writes the matrix `values` on `pattern` to `out` in Matrix Market coordinate format
/// (`real general`, 1-based indices, every stored entry).
///
/// # Errors
/// I/O errors of `out`.
pub fn write_matrix_market<W: std::io::Write>(
    out: &mut W,
    pattern: &Pattern,
    values: &[f64],
    comment: &str,
) -> std::io::Result<()> {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    writeln!(out, "%%MatrixMarket matrix coordinate real general")?;
    for line in comment.lines() {
        writeln!(out, "% {line}")?;
    }
    writeln!(
        out,
        "{} {} {}",
        pattern.nrows(),
        pattern.ncols(),
        values.len()
    )?;
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            writeln!(out, "{} {} {:e}", ri[p] + 1, j + 1, values[p])?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// A structurally symmetric, unsymmetric matrix with two unknowns per node (a ring of
    /// nodes, each coupled to its neighbours and to a hub), skew terms as a Coriolis matrix
    /// makes them; diagonally dominant. Returns the pattern, the values and, if
    /// `symmetric`, no skew terms.
    fn test_matrix(nodes: usize, symmetric: bool) -> (Pattern, Vec<f64>) {
        let n = 2 * nodes;
        let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
        let mut couple = |a: usize, b: usize, w: f64| {
            for (da, db) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (i, j) = (2 * a + da, 2 * b + db);
                let skew = if symmetric || a == b { 0.0 } else { 0.01 * w };
                let v = -w * (1.0 + 0.1 * (da + 2 * db) as f64);
                t.push(Triplet::new(i, j, v + skew));
                t.push(Triplet::new(j, i, v - skew));
            }
        };
        for a in 0..nodes {
            couple(a, (a + 1) % nodes, 1.0 + 0.3 * (a as f64).sin());
            couple(a, (a + 7) % nodes, 0.5);
            if a % 5 == 0 {
                couple(a, 0, 0.2);
            }
        }
        // The diagonal dominates the rows; the skew part of each node's own block.
        let mut row_sum = vec![0.0; n];
        for e in &t {
            row_sum[e.row] += e.val.abs();
        }
        for (i, s) in row_sum.iter().enumerate() {
            t.push(Triplet::new(i, i, 1.0 + s));
        }
        for a in 0..nodes {
            if !symmetric {
                t.push(Triplet::new(2 * a, 2 * a + 1, 0.05));
                t.push(Triplet::new(2 * a + 1, 2 * a, -0.05));
            }
        }
        let m = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        (m.symbolic().to_owned().unwrap(), m.val().to_vec())
    }

    /// The matrix of `test_matrix`'s kind on a grid of `nx` by `ny` nodes (each coupled to
    /// its right, upper and upper-right neighbours): a planar graph, whose elimination tree
    /// branches as a mesh's does.
    fn grid_matrix(nx: usize, ny: usize) -> (Pattern, Vec<f64>) {
        grid_matrix_skew(nx, ny, 0.01)
    }

    /// The same with the skew part `skew` (0: symmetric positive definite).
    fn grid_matrix_skew(nx: usize, ny: usize, skew: f64) -> (Pattern, Vec<f64>) {
        let n = 2 * nx * ny;
        let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
        let node = |x: usize, y: usize| x + nx * y;
        for y in 0..ny {
            for x in 0..nx {
                for (dx, dy, w) in [(1, 0, 1.0), (0, 1, 0.8), (1, 1, 0.3)] {
                    if x + dx >= nx || y + dy >= ny {
                        continue;
                    }
                    let (a, b) = (node(x, y), node(x + dx, y + dy));
                    for (da, db) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        let (i, j) = (2 * a + da, 2 * b + db);
                        let v = -w * (1.0 + 0.1 * (da + 2 * db) as f64);
                        t.push(Triplet::new(i, j, v + skew * w));
                        t.push(Triplet::new(j, i, v - skew * w));
                    }
                }
            }
        }
        let mut row_sum = vec![0.0; n];
        for e in &t {
            row_sum[e.row] += e.val.abs();
        }
        for (i, s) in row_sum.iter().enumerate() {
            t.push(Triplet::new(i, i, 1.0 + s));
        }
        let m = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        (m.symbolic().to_owned().unwrap(), m.val().to_vec())
    }

    /// The factor `build(split)` with and without the split into two
    /// independent parts and a top: the parts are balanced, the fill is that of AMD or,
    /// when the split took the graph's bisection, within 5% of it, the solve reproduces
    /// faer's LU to 1e-13, and its result is the same, bit for bit, on one thread and on two.
    fn split_solves_alike(pattern: &Pattern, values: &[f64], build: impl Fn(bool) -> Factor) {
        let n = pattern.nrows();
        let b = rhs(n);
        let x_ref = faer_solve(pattern, values, &b);
        let whole = build(false);
        assert!(whole.parts().is_none());
        let mut split = build(true);
        let kind = split.kind();
        let (p0, p1, top) = split.parts().expect("a split ordering");
        assert_eq!(p0 + p1 + top, n);
        assert!(
            p0.min(p1) * 3 > p0.max(p1) && top * 10 < n,
            "{kind:?}: parts of {p0} and {p1} unknowns, top {top}"
        );
        let (fill, amd) = (split.factor_nnz(), whole.factor_nnz());
        assert!(
            20 * fill <= 21 * amd,
            "{kind:?}: fill {fill} against AMD's {amd}"
        );
        let mut on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut x = b.clone();
            pool.install(|| split.solve_in_place(&mut x));
            x
        };
        let (x1, x2) = (on(1), on(2));
        assert!(x1.iter().zip(&x2).all(|(p, q)| p.to_bits() == q.to_bits()));
        // On a team of the caller's thread and its own helper.
        let mut x3 = b.clone();
        split.solve_on(&Team::new(team::Par::threads(2)), &mut x3);
        assert!(x1.iter().zip(&x3).all(|(p, q)| p.to_bits() == q.to_bits()));
        let d = max_rel_diff(&x1, &x_ref);
        assert!(d < 1e-13, "{kind:?} split against faer's LU: {d:e}");
    }

    /// Two disconnected copies of a grid: their elimination trees are two equal subtrees, so
    /// the split puts one copy in each part and leaves no top.
    #[test]
    fn two_disconnected_grids_split_into_the_two_without_a_top() {
        let (p1, v1) = grid_matrix(12, 9);
        let m = p1.nrows();
        let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
        for copy in 0..2 {
            for j in 0..m {
                for q in p1.col_ptr()[j]..p1.col_ptr()[j + 1] {
                    let i = p1.row_idx()[q];
                    t.push(Triplet::new(copy * m + i, copy * m + j, v1[q]));
                }
            }
        }
        let mat = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(2 * m, 2 * m, &t)
            .unwrap();
        let pattern = mat.symbolic().to_owned().unwrap();
        let (fwd, inv) = column_ordering(&pattern, Ordering::Amd).unwrap();
        let split::Split {
            fwd: new_fwd, a, b, ..
        } = split::two_subtrees(&pattern, &fwd, &inv).expect("a split");
        assert_eq!((a, b), (m, 2 * m), "the parts of {} unknowns", 2 * m);
        let copy_of = |k: usize| new_fwd[k] / m;
        assert!((1..m).all(|k| copy_of(k) == copy_of(0)));
        assert!((m + 1..2 * m).all(|k| copy_of(k) == copy_of(m)));
        assert_ne!(copy_of(0), copy_of(m));
    }

    /// On the hexagonal disk of 48 rings (14,114 unknowns) AMD's split has a top of 456
    /// unknowns, the chain of its last eliminations. The split taken is the bisection's,
    /// whose top is about the separator across a diameter, `2 (2 r + 1)` unknowns: a
    /// shorter critical path for a fill within 2% of AMD's.
    #[test]
    fn the_disk_is_split_across_a_diameter() {
        use crate::mesh::generators::disk_rings;
        use crate::wheel::{Support, WheelModel, WheelSpec};
        let rings = 48;
        let spec = WheelSpec {
            support: Support::CentrePinned,
            ..WheelSpec::paper()
        };
        let w = WheelModel::new(disk_rings(0.1, rings).unwrap(), spec).unwrap();
        let pattern = w.model.pattern();
        let n = pattern.ncols();
        let (fwd, inv) = column_ordering(pattern, Ordering::Amd).unwrap();
        let own = split::two_subtrees(pattern, &fwd, &inv).expect("AMD's split");
        let best = split::best_split(pattern, &fwd, &inv).expect("a split");
        let diameter = 2 * (2 * rings + 1);
        let (top, own_top) = (n - best.b, n - own.b);
        assert!(
            best.critical < own.critical && 2 * top <= 3 * diameter,
            "top {top} (AMD's {own_top}), critical path {} (AMD's {})",
            best.critical,
            own.critical
        );
        assert!(50 * best.entries <= 51 * own.entries);
    }

    /// By rows and in dense supernodes.
    #[test]
    fn split_factor_solves_alike_on_one_thread_and_two() {
        let (pattern, values) = grid_matrix(60, 50);
        for dense in [false, true] {
            split_solves_alike(&pattern, &values, |split| {
                Factor::Lu(
                    SparseLu::build(&pattern, &values, Ordering::Amd, split)
                        .unwrap()
                        .with_layout(&pattern, &values, dense),
                )
            });
        }
    }

    /// The same for the Cholesky factor of a symmetric matrix.
    #[test]
    fn split_cholesky_solves_alike_on_one_thread_and_two() {
        let (pattern, values) = grid_matrix_skew(60, 50, 0.0);
        for dense in [false, true] {
            split_solves_alike(&pattern, &values, |split| {
                Factor::Llt(
                    SparseLlt::build(&pattern, &values, split)
                        .unwrap()
                        .with_layout(&pattern, &values, dense),
                )
            });
        }
    }

    /// The same for a system large enough for dense supernodes, LU and Cholesky.
    #[test]
    fn large_split_solves_alike_on_one_thread_and_two() {
        let (pattern, values) = grid_matrix_skew(160, 160, 0.0);
        assert!(pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER);
        split_solves_alike(&pattern, &values, |split| {
            Factor::Llt(SparseLlt::build(&pattern, &values, split).unwrap())
        });
        let (pattern, values) = grid_matrix_skew(160, 160, 0.01);
        split_solves_alike(&pattern, &values, |split| {
            Factor::Lu(SparseLu::build(&pattern, &values, Ordering::Amd, split).unwrap())
        });
    }

    /// The solves compiled for AVX2 (chosen at run time) give the baseline's result bit for
    /// bit: the same operations in the same order, by rows and in dense supernodes, LU and
    /// Cholesky.
    #[test]
    fn avx2_solves_match_the_baseline_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            for symmetric in [false, true] {
                let (pattern, values) = test_matrix(300, symmetric);
                let b = rhs(pattern.nrows());
                let same =
                    |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
                for dense in [false, true] {
                    let mut lu = SparseLu::new(&pattern, &values)
                        .unwrap()
                        .with_layout(&pattern, &values, dense);
                    let (mut x, mut y) = (b.clone(), b.clone());
                    // The baseline without the AVX2 block kernel (`blocks_dot`).
                    (lu.l.avx2, lu.u.avx2) = (false, false);
                    lu.solve_here(&Team::default(), &mut x);
                    (lu.l.avx2, lu.u.avx2) = (true, true);
                    // SAFETY: the processor has AVX2 (checked above).
                    unsafe { lu.solve_avx2(&Team::default(), &mut y) };
                    assert!(same(&x, &y), "LU, dense {dense}");
                    if symmetric {
                        let mut llt = SparseLlt::new(&pattern, &values)
                            .unwrap()
                            .with_layout(&pattern, &values, dense);
                        let (mut x, mut y) = (b.clone(), b.clone());
                        (llt.l.avx2, llt.lt.avx2) = (false, false);
                        llt.solve_here(&Team::default(), &mut x);
                        (llt.l.avx2, llt.lt.avx2) = (true, true);
                        // SAFETY: as above.
                        unsafe { llt.solve_avx2(&Team::default(), &mut y) };
                        assert!(same(&x, &y), "Cholesky, dense {dense}");
                    }
                }
            }
        }
    }

    /// The AVX2 block kernel gives the bits of the portable one, for every number of
    /// blocks (odd counts take its remainder path), and the dot products they stand for.
    #[test]
    fn block_kernel_matches_the_portable_one_bit_for_bit() {
        let n = 40;
        let x: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).cos() * 1e3).collect();
        for len in 0..12 {
            let idx: Vec<u32> = (0..len).map(|k| ((7 * k + 3) % (n - 1)) as u32).collect();
            let val: Vec<[f64; 4]> = (0..len)
                .map(|k| {
                    let f = |l: usize| ((k * 4 + l) as f64 * 0.91).sin() / 3.0;
                    [f(0), f(1), f(2), f(3)]
                })
                .collect();
            let s = blocks_dot(&idx, &val, &x);
            // Row r0's dot product is s[0] + s[1], row r0 + 1's s[2] + s[3].
            let (mut r0, mut r1) = (0.0, 0.0);
            for (&c, v) in idx.iter().zip(&val) {
                let c = c as usize;
                r0 += v[0] * x[c] + v[1] * x[c + 1];
                r1 += v[2] * x[c] + v[3] * x[c + 1];
            }
            let scale = x.iter().map(|v| v.abs()).sum::<f64>();
            assert!(((s[0] + s[1]) - r0).abs() <= 1e-14 * scale, "{len} blocks");
            assert!(((s[2] + s[3]) - r1).abs() <= 1e-14 * scale, "{len} blocks");
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2 and every `c + 1 < n`.
                let t = unsafe { blocks_dot_avx2(&idx, &val, &x) };
                let bits = |a: [f64; 4]| a.map(f64::to_bits);
                assert_eq!(bits(s), bits(t), "{len} blocks");
            }
        }
    }

    fn rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect()
    }

    fn max_rel_diff(x: &[f64], y: &[f64]) -> f64 {
        let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        x.iter()
            .zip(y)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
            / scale
    }

    /// faer's own LU and solve: the reference ([`FaerLu`]).
    /// The dense supernodal layout on a mesh-like grid solves as faer's LU does (1e-13)
    /// through supernodes of every narrow width (the one-pass kernels, `W < 8`) and wide
    /// ones (four columns per pass, with a remainder), for the LU and the Cholesky factor;
    /// the AVX2 copies of the sweeps give the baseline's bits.
    #[test]
    fn narrow_and_wide_supernodes_solve_alike() {
        for symmetric in [false, true] {
            let (pattern, values) = grid_matrix_skew(14, 14, if symmetric { 0.0 } else { 0.01 });
            let n = pattern.nrows();
            let b = rhs(n);
            let x_ref = faer_solve(&pattern, &values, &b);
            let kind = if symmetric {
                FactorKind::Llt
            } else {
                FactorKind::Lu(Ordering::Amd)
            };
            let f = match Factor::new(&pattern, &values, kind).unwrap() {
                Factor::Lu(lu) => Factor::Lu(lu.with_layout(&pattern, &values, true)),
                Factor::Llt(l) => Factor::Llt(l.with_layout(&pattern, &values, true)),
            };
            let sn = match &f {
                Factor::Lu(SparseLu {
                    stored: Some(Stored::Supernodes(lu)),
                    ..
                }) => lu.0.clone(),
                Factor::Llt(SparseLlt {
                    stored: Some(StoredLower::Supernodes(l)),
                    ..
                }) => l.clone(),
                _ => panic!("no dense layout"),
            };
            let mut widths: Vec<usize> = sn.bounds.windows(2).map(|w| w[1] - w[0]).collect();
            widths.sort_unstable();
            widths.dedup();
            assert!(
                widths.iter().filter(|&&w| w < 8).count() >= 3
                    && widths.iter().any(|&w| w >= 8 && w % 4 != 0),
                "widths {widths:?}"
            );
            // Packed blocks hold the factor's entries and nothing else (no zeros above the
            // diagonals), and a solve reads them twice for Cholesky, once each for LU.
            assert_eq!(sn.blk.len(), sn.nnz);
            let sn_bytes = sn.bytes();
            assert!(
                sn_bytes > 8 * sn.nnz && sn_bytes < 10 * sn.nnz,
                "{sn_bytes}"
            );
            match &f {
                Factor::Llt(_) => assert_eq!(f.solve_bytes(), 2 * sn_bytes),
                Factor::Lu(SparseLu {
                    stored: Some(Stored::Supernodes(lu)),
                    ..
                }) => assert_eq!(f.solve_bytes(), sn_bytes + lu.1.bytes()),
                Factor::Lu(_) => unreachable!("dense layout above"),
            }
            // The prefetch (on for factors that stream from memory) is a hint: the same bits.
            let (mut x, mut y) = (b.clone(), b.clone());
            let mut with = sn.clone();
            with.prefetch = true;
            let mut without = sn.clone();
            without.prefetch = false;
            with.forward(&mut x);
            with.backward(&mut x);
            without.forward(&mut y);
            without.backward(&mut y);
            assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let mut sn = sn;
                let (mut x, mut y) = (b.clone(), b.clone());
                sn.forward_here(&mut x);
                sn.backward_here(&mut x);
                // SAFETY: the processor has AVX2 (checked above).
                unsafe {
                    sn.forward_avx2(&mut y);
                    sn.backward_avx2(&mut y);
                }
                assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
            }
            let mut f = f;
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            let d = max_rel_diff(&x, &x_ref);
            assert!(d < 1e-13, "symmetric {symmetric}: {d:e}");
        }
    }

    /// faer's supernodal Cholesky (used from 10,000 dofs on), converted to columns, gives
    /// the simplicial factor's columns (the relaxed supernodes' zeros left out: the same
    /// stored entries) and solves as faer's LU does, by rows, in dense supernodes and split.
    #[test]
    fn supernodal_cholesky_gives_the_simplicial_columns() {
        let (pattern, values) = grid_matrix_skew(16, 15, 0.0);
        let b = rhs(pattern.nrows());
        let x_ref = faer_solve(&pattern, &values, &b);
        for split in [false, true] {
            let simplicial = SparseLlt::build_with(&pattern, &values, split, false).unwrap();
            for dense in [false, true] {
                let mut f = SparseLlt::build_with(&pattern, &values, split, true)
                    .unwrap()
                    .with_layout(&pattern, &values, dense);
                assert!(matches!(
                    f.symbolic.raw(),
                    SymbolicCholeskyRaw::Supernodal(_)
                ));
                assert_eq!(f.factor_nnz(), simplicial.factor_nnz(), "split {split}");
                let mut x = b.clone();
                f.solve_in_place(&mut x);
                let d = max_rel_diff(&x, &x_ref);
                assert!(d < 1e-13, "split {split}, dense {dense}: {d:e}");
            }
        }
    }

    /// `Factor::auto`: a Cholesky on a symmetric positive definite matrix, an LU on an
    /// unsymmetric one and on a symmetric indefinite one, each solving as faer's LU does.
    #[test]
    fn auto_factor_chooses_by_symmetry_and_definiteness() {
        let (pattern, spd) = test_matrix(60, true);
        let (unsym_pattern, unsym) = test_matrix(60, false);
        // Indefinite: the diagonal of one node's dofs negated (still regular).
        let mut indef = spd.clone();
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        for j in [10, 11] {
            for p in cp[j]..cp[j + 1] {
                if ri[p] == j {
                    indef[p] = -indef[p];
                }
            }
        }
        let b = rhs(pattern.nrows());
        for (pattern, values, cholesky) in [
            (&pattern, &spd, true),
            (&unsym_pattern, &unsym, false),
            (&pattern, &indef, false),
        ] {
            let mut f = Factor::auto(pattern, values).unwrap();
            assert_eq!(f.kind() == FactorKind::Llt, cholesky, "{:?}", f.kind());
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            let d = max_rel_diff(&x, &faer_solve(pattern, values, &b));
            assert!(d < 1e-12, "{:?}: {d:e}", f.kind());
        }
    }

    fn faer_solve(pattern: &Pattern, values: &[f64], b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        FaerLu::new(pattern, values).unwrap().solve_in_place(&mut x);
        x
    }

    use SparseLlt as LltLayout;
    use SparseLu as LuLayout;

    fn widest_rows(t: &Triangle) -> usize {
        t.segments
            .iter()
            .filter(|s| matches!(s.2, Segment::Super(_)))
            .map(|s| s.1 - s.0)
            .max()
            .unwrap_or(0)
    }

    /// The supernodal row solves (LU with either ordering, Cholesky) reproduce faer's LU
    /// and its solve to 1e-13 relative, and their factors have supernodes of several rows
    /// and, by rows, pairs of rows solved together.
    #[test]
    fn supernodal_solves_reproduce_faers_lu() {
        for (nodes, symmetric) in [(40, false), (300, false), (300, true)] {
            let (pattern, values) = test_matrix(nodes, symmetric);
            let n = 2 * nodes;
            let b = rhs(n);
            let x_ref = faer_solve(&pattern, &values, &b);
            let mut kinds = vec![
                FactorKind::Lu(Ordering::Amd),
                FactorKind::Lu(Ordering::Colamd),
            ];
            if symmetric {
                kinds.push(FactorKind::Llt);
            }
            for kind in kinds {
                for dense in [false, true] {
                    let f = Factor::new(&pattern, &values, kind).unwrap();
                    let mut f = match f {
                        Factor::Lu(lu) => Factor::Lu(lu.with_layout(&pattern, &values, dense)),
                        Factor::Llt(l) => Factor::Llt(l.with_layout(&pattern, &values, dense)),
                    };
                    let mut x = b.clone();
                    f.solve_in_place(&mut x);
                    let d = max_rel_diff(&x, &x_ref);
                    assert!(d < 1e-13, "{nodes} nodes, {kind:?}, dense {dense}: {d:e}");
                    // The supernodes of the elimination: several columns of `L` (rows of
                    // `U`) that share their rows.
                    let widest = match &f {
                        Factor::Lu(LuLayout {
                            stored: Some(Stored::Supernodes(lu)),
                            ..
                        }) => lu.1.bounds.windows(2).map(|w| w[1] - w[0]).max().unwrap(),
                        Factor::Llt(LltLayout {
                            stored: Some(StoredLower::Supernodes(ut)),
                            ..
                        }) => ut.bounds.windows(2).map(|w| w[1] - w[0]).max().unwrap(),
                        Factor::Lu(lu) => widest_rows(&lu.u),
                        Factor::Llt(llt) => widest_rows(&llt.lt),
                    };
                    assert!(
                        widest >= MIN_SUPERNODE,
                        "{nodes} nodes, {kind:?}: no supernode"
                    );
                    // The row layout also solves pairs of rows (a node's two dofs) together.
                    let pairs = |t: &Triangle| {
                        t.segments
                            .iter()
                            .filter(|s| matches!(s.2, Segment::Pair(_)))
                            .count()
                    };
                    let pairs = match &f {
                        Factor::Lu(lu) if !dense => pairs(&lu.l) + pairs(&lu.u),
                        Factor::Llt(llt) if !dense => pairs(&llt.l) + pairs(&llt.lt),
                        _ => 1,
                    };
                    assert!(pairs > 0, "{nodes} nodes, {kind:?}: no pair of rows");
                    // And, in pairs, blocks of two columns (a neighbouring node's dofs).
                    let blocks = match &f {
                        Factor::Lu(lu) if !dense => lu.l.blk_idx.len() + lu.u.blk_idx.len(),
                        Factor::Llt(llt) if !dense => llt.l.blk_idx.len() + llt.lt.blk_idx.len(),
                        _ => 1,
                    };
                    assert!(blocks > 0, "{nodes} nodes, {kind:?}: no block of columns");
                }
            }
        }
    }
}
