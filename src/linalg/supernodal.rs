//! A lower triangular factor in dense supernodes ([`Supernodal`]) for the forward and
//! backward sweeps of the large orders, with its packed blocks, its narrow and wide kernels
//! and their prefetch.

use super::huge::HugeBuf;
use super::kernels::{dot_dense, prefetch, prefetch_lines};

/// The smallest order from which the factors are solved in dense supernodes
/// ([`Supernodal`]); smaller factors by rows ([`Triangle`]), whose supernodes are narrow.
/// Measured: on the paper's wheel (938 dofs) the rows take fewer instructions, on the
/// converged wheel (3,430 dofs) about 10% less time; on the 48-ring disk (14,114 dofs) the
/// dense supernodes take about 10% less time.
pub(super) const DENSE_SUPERNODAL_MIN_ORDER: usize = 10_000;

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
pub(super) struct Supernodal {
    /// Supernode `s` is the columns `bounds[s]..bounds[s + 1]`.
    pub(super) bounds: Vec<usize>,
    pub(super) rows_ptr: Vec<usize>,
    /// The rows `R` of each supernode, then its packed block: on huge pages when large
    /// ([`HugeBuf`]).
    pub(super) rows: HugeBuf<u32>,
    pub(super) blk_ptr: Vec<usize>,
    pub(super) blk: HugeBuf<f64>,
    /// Work for `y` (the widest `R`).
    pub(super) y: Vec<f64>,
    /// Stored entries of `Λ`, diagonal included.
    pub(super) nnz: usize,
    /// The sweeps prefetch the blocks and rows they will read next (`PREFETCH_AHEAD`
    /// entries ahead), for factors that stream from memory (`PREFETCH_MIN_BYTES`).
    pub(super) prefetch: bool,
}

impl Supernodal {
    /// From the CSC arrays of a lower triangular `Λ` (row indices in any order, every
    /// diagonal entry stored unless `unit`: a unit diagonal, stored or not).
    pub(super) fn from_lower_csc(
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &[f64],
        unit: bool,
    ) -> Self {
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
        pub(super) fn forward / forward_avx2(&mut self, x: &mut [f64]) => forward_here
    }

    avx2_method! {
        /// `x <- Λ^{-T} x`, on AVX2's instructions where the processor has them.
        pub(super) fn backward / backward_avx2(&mut self, x: &mut [f64]) => backward_here
    }

    /// Bytes of the arrays each of the two sweeps reads (the blocks, row indices and
    /// pointers).
    pub(super) fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.blk[..])
            + b(&self.rows[..])
            + b(&self.bounds[..])
            + b(&self.rows_ptr[..])
            + b(&self.blk_ptr[..])
    }

    /// Supernode `s`: its first column, width, rows below the run and block.
    #[inline(always)]
    pub(super) fn supernode(&self, s: usize) -> (usize, usize, &[u32], &[f64]) {
        let j0 = self.bounds[s];
        (
            j0,
            self.bounds[s + 1] - j0,
            &self.rows[self.rows_ptr[s]..self.rows_ptr[s + 1]],
            &self.blk[self.blk_ptr[s]..self.blk_ptr[s + 1]],
        )
    }

    #[inline(always)]
    pub(super) fn forward_here(&mut self, x: &mut [f64]) {
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
    pub(super) fn backward_here(&mut self, x: &mut [f64]) {
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

/// Right-hand sides a block sweep carries (`Supernodal::forward_block`): the factor is read
/// once for this many columns, each entry used on a row of them (one four-wide operation
/// twice). A block of fewer columns is padded with zeros by the caller.
pub const BLOCK_RHS: usize = 8;

/// One row of a block of right-hand sides ([`BLOCK_RHS`] columns side by side).
pub type BlockRow = [f64; BLOCK_RHS];

impl Supernodal {
    avx2_method! {
    /// `X <- Λ^{-1} X` for the [`BLOCK_RHS`] right-hand sides of `x` (row `i` of every column
    /// in `x[i]`): each supernode's block read once for all of them, four columns at a time
    /// ([`forward_columns`]). The sums are not made in the single sweep's order: the same
    /// values to round-off, not the same bits. On AVX2's instructions where the processor has
    /// them (no fused operations: the same bits as without).
    pub(super) fn forward_block / forward_block_avx2(&self, x: &mut [BlockRow]) => forward_block_here
    }

    avx2_method! {
        /// `X <- Λ^{-T} X` for the right-hand sides of `x` ([`Self::forward_block`]'s layout),
        /// on AVX2's instructions where the processor has them.
        pub(super) fn backward_block / backward_block_avx2(&self, x: &mut [BlockRow]) => backward_block_here
    }

    #[inline(always)]
    pub(super) fn forward_block_here(&self, x: &mut [BlockRow]) {
        for s in 0..self.bounds.len() - 1 {
            let (j0, w, rows, blk) = self.supernode(s);
            let mut k = 0;
            while k + 8 <= w {
                forward_columns::<8>(blk, w, rows, j0, k, x);
                k += 8;
            }
            while k + 4 <= w {
                forward_columns::<4>(blk, w, rows, j0, k, x);
                k += 4;
            }
            while k < w {
                forward_columns::<1>(blk, w, rows, j0, k, x);
                k += 1;
            }
        }
    }

    #[inline(always)]
    pub(super) fn backward_block_here(&self, x: &mut [BlockRow]) {
        for s in (0..self.bounds.len() - 1).rev() {
            let (j0, w, rows, blk) = self.supernode(s);
            let mut k = w;
            while k >= 8 {
                backward_columns::<8>(blk, w, rows, j0, k - 8, x);
                k -= 8;
            }
            while k >= 4 {
                backward_columns::<4>(blk, w, rows, j0, k - 4, x);
                k -= 4;
            }
            while k > 0 {
                backward_columns::<1>(blk, w, rows, j0, k - 1, x);
                k -= 1;
            }
        }
    }
}

/// The forward solve of the `NB` columns `k..k + NB` of a supernode (block `blk`, `w`
/// columns from `j0`, rows below the run `rows`) on a block of right-hand sides: their own
/// triangle, then every row below them in the run and in `rows` loaded once for the `NB`
/// columns (`NB x BLOCK_RHS` products a row).
#[inline(always)]
fn forward_columns<const NB: usize>(
    blk: &[f64],
    w: usize,
    rows: &[u32],
    j0: usize,
    k: usize,
    x: &mut [BlockRow],
) {
    let h = w + rows.len();
    let mut xs = [[0.0; BLOCK_RHS]; NB];
    for j in 0..NB {
        let col = packed_col(blk, h, k + j);
        let mut xj = x[j0 + k + j];
        for (i, xi) in xs.iter().enumerate().take(j) {
            let l = packed_col(blk, h, k + i)[j - i];
            for c in 0..BLOCK_RHS {
                xj[c] -= l * xi[c];
            }
        }
        xs[j] = xj.map(|v| v * col[0]);
        x[j0 + k + j] = xs[j];
    }
    // Column k + j from the first row below the NB columns: its entries NB - j on.
    let cols: [&[f64]; NB] = std::array::from_fn(|j| &packed_col(blk, h, k + j)[NB - j..]);
    let below = w - k - NB;
    let update = |q: usize, xr: &mut BlockRow| {
        for j in 0..NB {
            let l = cols[j][q];
            for c in 0..BLOCK_RHS {
                xr[c] -= l * xs[j][c];
            }
        }
    };
    for q in 0..below {
        update(q, &mut x[j0 + k + NB + q]);
    }
    for (q, &r) in rows.iter().enumerate() {
        update(below + q, &mut x[r as usize]);
    }
}

/// The backward solve of the `NB` columns `k..k + NB` of a supernode on a block of
/// right-hand sides ([`forward_columns`]'s layout): every row below them read once for the
/// `NB` columns' sums, then their own transposed triangle.
#[inline(always)]
fn backward_columns<const NB: usize>(
    blk: &[f64],
    w: usize,
    rows: &[u32],
    j0: usize,
    k: usize,
    x: &mut [BlockRow],
) {
    let h = w + rows.len();
    let cols: [&[f64]; NB] = std::array::from_fn(|j| &packed_col(blk, h, k + j)[NB - j..]);
    let below = w - k - NB;
    let mut acc = [[0.0; BLOCK_RHS]; NB];
    let mut gather = |q: usize, xr: &BlockRow| {
        for j in 0..NB {
            let l = cols[j][q];
            for c in 0..BLOCK_RHS {
                acc[j][c] += l * xr[c];
            }
        }
    };
    for q in 0..below {
        gather(q, &x[j0 + k + NB + q]);
    }
    for (q, &r) in rows.iter().enumerate() {
        gather(below + q, &x[r as usize]);
    }
    for j in (0..NB).rev() {
        let col = packed_col(blk, h, k + j);
        let mut a = x[j0 + k + j];
        for c in 0..BLOCK_RHS {
            a[c] -= acc[j][c];
        }
        for i in j + 1..NB {
            let xi = x[j0 + k + i];
            for c in 0..BLOCK_RHS {
                a[c] -= col[i - j] * xi[c];
            }
        }
        x[j0 + k + j] = a.map(|v| v * col[0]);
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
pub(super) const PREFETCH_MIN_BYTES: usize = 4 << 20;

/// How far ahead of the block being solved the sweeps prefetch, in entries: 32 KiB of
/// values and 16 KiB of row indices. With the 192-ring disk's factors streaming from memory
/// (176 MB a sweep), the split forward sweep took 7.3-7.6 ms instead of 8.5-8.9, the
/// backward 7.9-8.3 instead of 9.4-10.1 (alternated, same session); 4 and 16 KiB gained
/// less, and the non-temporal hint lost. Within the wide kernels ([`Ahead`]) the same
/// distance was best again: the 192-ring step 16.5-16.9 ms, against 17.4-18.3 at 16 KiB,
/// 17.3-18.1 at 64 KiB and 18.0-18.5 at 128 KiB (one binary, alternated, twice).
pub(super) const PREFETCH_AHEAD: usize = 4096;

/// The narrowest supernode solved by the wide kernels ([`wide_forward`]); narrower ones
/// have a kernel each ([`narrow_forward`]).
pub(super) const WIDE: usize = 8;

/// Turns on the prefetch of every one of `factors` (the dense supernodes of one solve) when
/// together they hold `PREFETCH_MIN_BYTES` or more, off otherwise.
pub(super) fn prefetch_when_large<'a>(factors: impl IntoIterator<Item = &'a mut Supernodal>) {
    let factors: Vec<&mut Supernodal> = factors.into_iter().collect();
    let on = factors.iter().map(|f| f.bytes()).sum::<usize>() >= PREFETCH_MIN_BYTES;
    for f in factors {
        f.prefetch = on;
    }
}

/// Entries of a packed supernode block of `w` columns and `h` rows (column `k` holds its
/// rows `k..h`: no zeros above the diagonal).
#[inline(always)]
pub(super) const fn packed_len(w: usize, h: usize) -> usize {
    w * h - (w * w - w) / 2
}

/// Column `k` of a packed supernode block of `h` rows ([`packed_len`]): its rows `k..h`,
/// the diagonal (as its reciprocal) first, then the rest of the run, then the rows below it.
#[inline(always)]
pub(super) fn packed_col(blk: &[f64], h: usize, k: usize) -> &[f64] {
    let start = packed_start(h, k);
    &blk[start..start + h - k]
}

/// A prefetch that runs through a block ahead of a wide kernel's reads, two cache lines per
/// block of four rows of four columns read (the 128 bytes read), spread over the pass
/// rather than asked for at once; nothing at all unless `P`.
#[derive(Clone, Copy)]
pub(super) struct Ahead<const P: bool> {
    /// The next line to ask for (a hint's address: it may lie outside the block).
    pub(super) p: *const f64,
    /// `1` when the pass runs up the block, `-1` down.
    pub(super) dir: isize,
}

impl<const P: bool> Ahead<P> {
    /// From entry `at` of `blk` up (`dir = 1`) or down (`dir = -1`).
    #[inline(always)]
    pub(super) fn new(blk: &[f64], at: isize, dir: isize) -> Self {
        Self {
            p: blk.as_ptr().wrapping_offset(at),
            dir,
        }
    }

    /// Asks for the next two lines.
    #[inline(always)]
    pub(super) fn next(&mut self) {
        if P {
            prefetch(self.p);
            prefetch(self.p.wrapping_offset(8 * self.dir));
            self.p = self.p.wrapping_offset(16 * self.dir);
        }
    }
}

/// Four values as an array (`c` has four).
#[inline(always)]
pub(super) fn quad(c: &[f64]) -> [f64; 4] {
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
pub(super) fn sub_columns4<const P: bool>(
    out: &mut [f64],
    c: [&[f64]; 4],
    v: [f64; 4],
    pf: &mut Ahead<P>,
) {
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
pub(super) fn dot_columns4<const P: bool>(
    c: [&[f64]; 4],
    y: &[f64],
    pf: &mut Ahead<P>,
) -> [f64; 4] {
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
pub(super) const fn packed_start(h: usize, k: usize) -> usize {
    k * h - (k * k - k) / 2
}

/// The forward solve of a supernode of `w` columns `j0..j0 + w` (layout of
/// [`narrow_forward`], the diagonal held as its reciprocal), one pass over its block in
/// blocks of four columns: each block's own small triangle on `x[j0..]`, then the run's
/// rows below it updated four columns per pass, then `y -= Λ[R, k..k + 4] (-x_k..)`;
/// last `x[R] -= y`. With `P`, the lines `PREFETCH_AHEAD` entries ahead of the pass are
/// asked for as it goes ([`Ahead`]).
#[inline(always)]
pub(super) fn wide_forward<const P: bool>(
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
pub(super) fn wide_backward<const P: bool>(
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
pub(super) fn narrow_forward<const W: usize>(blk: &[f64], rows: &[u32], j0: usize, x: &mut [f64]) {
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
pub(super) fn narrow_backward<const W: usize>(blk: &[f64], rows: &[u32], j0: usize, x: &mut [f64]) {
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
