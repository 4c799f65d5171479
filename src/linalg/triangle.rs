//! A triangular factor stored by rows for the row solves (orders below
//! `DENSE_SUPERNODAL_MIN_ORDER`): supernodes, pairs of rows and single rows ([`Triangle`]).

#[cfg(target_arch = "x86_64")]
use super::kernels::blocks_dot_avx2;
use super::kernels::{blocks_dot, dot_dense, dot_gather, has_avx2};

/// The fewest rows of a supernode of a [`Triangle`] (runs of two rows are pairs, other
/// shorter runs are solved row by row).
pub(super) const MIN_SUPERNODE: usize = 4;

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
pub(super) struct Triangle {
    pub(super) lower: bool,
    /// Supernode `s`'s first row in `val_ptr` and `tri_ptr` (each supernode's rows there are
    /// followed by one end entry).
    pub(super) sn_first: Vec<usize>,
    /// The shared columns of each supernode: `cols[cols_ptr[s]..cols_ptr[s + 1]]`.
    pub(super) cols_ptr: Vec<usize>,
    pub(super) cols: Vec<u32>,
    /// The `k`-th stored supernode row's values on its supernode's shared columns
    /// (`val[val_ptr[k]..]`, as many as the shared columns), then on the run's own columns
    /// (`tri_ptr[k]..val_ptr[k + 1]`).
    pub(super) val_ptr: Vec<usize>,
    pub(super) tri_ptr: Vec<usize>,
    pub(super) val: Vec<f64>,
    pub(super) diag_inv: Vec<f64>,
    /// The gathered unknowns of one supernode's shared columns.
    pub(super) gathered: Vec<f64>,
    /// Rows that are no supernode, by rows (CSR; empty for the rows of supernodes).
    pub(super) single_ptr: Vec<usize>,
    pub(super) single_idx: Vec<u32>,
    pub(super) single_val: Vec<f64>,
    /// Pairs of rows sharing their columns (the two dofs of a node): pair `p` holds its
    /// shared columns `pair_idx[pair_ptr[p]..pair_ptr[p + 1]]`, the two rows' values on them
    /// side by side (`pair_val`, same range), and the entry coupling the two rows
    /// (`pair_coupling[p]`: lower, `T[r0 + 1, r0]`; upper, `T[r0, r0 + 1]`).
    pub(super) pair_ptr: Vec<usize>,
    pub(super) pair_idx: Vec<u32>,
    pub(super) pair_val: Vec<[f64; 2]>,
    pub(super) pair_coupling: Vec<f64>,
    /// The shared columns of pairs that come two by two (`c, c + 1`: the two dofs of a
    /// neighbouring node), apart from those above: pair `p`'s blocks
    /// `blk_idx[blk_ptr[p]..blk_ptr[p + 1]]` hold `c`, `blk_val` the four values
    /// `[T[r0, c], T[r0, c + 1], T[r0 + 1, c], T[r0 + 1, c + 1]]` (one index and one
    /// contiguous load of `x` for four entries).
    pub(super) blk_ptr: Vec<usize>,
    pub(super) blk_idx: Vec<u32>,
    pub(super) blk_val: Vec<[f64; 4]>,
    /// The processor has AVX2: the blocks run on [`blocks_dot_avx2`] (same results bit for
    /// bit as [`blocks_dot`]).
    pub(super) avx2: bool,
    /// Consecutive rows solved the same way, in storage order.
    pub(super) segments: Vec<(usize, usize, Segment)>,
    /// Stored off-diagonal entries.
    pub(super) off_diagonal: usize,
}

/// How a [`Triangle`]'s run of rows `r0..r1` is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Segment {
    /// Row by row, a gather per entry.
    Singles,
    /// Two rows sharing their columns (`r1 = r0 + 2`), pair `p`: one gather for both.
    Pair(usize),
    /// A supernode (its index in `sn_first`): the shared columns gathered once.
    Super(usize),
}

impl Triangle {
    /// Bytes of the arrays a solve reads.
    pub(super) fn bytes(&self) -> usize {
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
    pub(super) fn from_csc(
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
                t.push_single(r0, row(r0));
                continue;
            }
            if r1 - r0 == 2 {
                t.push_pair(r0, row(r0), row(r0 + 1));
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

    /// Stores row `r` alone, its off-diagonal `entries` (sorted by column) by rows.
    fn push_single(&mut self, r: usize, entries: &[(u32, f64)]) {
        self.single_idx.extend(entries.iter().map(|e| e.0));
        self.single_val.extend(entries.iter().map(|e| e.1));
        self.single_ptr.push(self.single_idx.len());
        match self.segments.last_mut() {
            Some((_, end, Segment::Singles)) if *end == r => *end = r + 1,
            _ => self.segments.push((r, r + 1, Segment::Singles)),
        }
    }

    /// Stores the rows `r0, r0 + 1` as a pair, from their off-diagonal entries `a` and `b`
    /// (sorted by column): lower, row `r0 + 1` is row `r0`'s columns and `r0`; upper, row
    /// `r0` is `r0 + 1` and row `r0 + 1`'s columns.
    fn push_pair(&mut self, r0: usize, a: &[(u32, f64)], b: &[(u32, f64)]) {
        let (shared, first, second, coupling) = if self.lower {
            (a, a, &b[..a.len()], b[a.len()].1)
        } else {
            (b, &a[1..], b, a[0].1)
        };
        let mut k = 0;
        while k < shared.len() {
            let c = shared[k].0;
            if k + 1 < shared.len() && shared[k + 1].0 == c + 1 {
                self.blk_idx.push(c);
                self.blk_val
                    .push([first[k].1, first[k + 1].1, second[k].1, second[k + 1].1]);
                k += 2;
            } else {
                self.pair_idx.push(c);
                self.pair_val.push([first[k].1, second[k].1]);
                k += 1;
            }
        }
        self.pair_ptr.push(self.pair_idx.len());
        self.blk_ptr.push(self.blk_idx.len());
        self.pair_coupling.push(coupling);
        self.single_ptr.push(self.single_idx.len());
        self.single_ptr.push(self.single_idx.len());
        self.segments
            .push((r0, r0 + 2, Segment::Pair(self.pair_coupling.len() - 1)));
    }

    /// Stored entries, diagonal included.
    pub(super) fn nnz(&self) -> usize {
        self.off_diagonal + self.diag_inv.len()
    }

    avx2_method! {
        /// [`Triangle::solve`] on AVX2's instructions where the processor has them (for the
        /// parts of a split factor, solved outside the AVX2 copy of the factor's solve).
        pub(super) fn solve_in_place / solve_avx2(&mut self, x: &mut [f64]) => solve
    }

    /// `x <- T^{-1} x`.
    #[inline(always)]
    pub(super) fn solve(&mut self, x: &mut [f64]) {
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
    pub(super) fn solve_pair(&self, p: usize, r0: usize, x: &mut [f64]) {
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
    pub(super) fn solve_single(&self, r: usize, x: &mut [f64]) {
        let range = self.single_ptr[r]..self.single_ptr[r + 1];
        let s = dot_gather(&self.single_idx[range.clone()], &self.single_val[range], x);
        x[r] = (x[r] - s) * self.diag_inv[r];
    }
}
