//! The right-hand side's kernels: the rows stored alone, the pairs of rows and their blocks
//! (general or compact, with or without `G`), compiled for the baseline processor and for
//! AVX2 (the same bits), with the prefetch of the blocks ahead.

use super::{BlockForm, RhsOperator, RHS_AHEAD};

impl RhsOperator {
    avx2_method! {
        /// `b[i] = h f[i] + (B v0 - h K u0)[i]` for the rows `i` stored alone, on AVX2's
        /// instructions where the processor has them (`linalg::with_avx2`).
        pub(super) fn singles_into / singles_avx2(
            &self,
            h: f64,
            f: &[f64],
            u0: &[f64],
            v0: &[f64],
            b: &mut [f64]
        ) => singles_here
    }

    #[inline(always)]
    pub(super) fn singles_here(&self, h: f64, f: &[f64], u0: &[f64], v0: &[f64], b: &mut [f64]) {
        let n = v0.len();
        assert!(u0.len() == n && f.len() == n);
        for (k, &i) in self.single.iter().enumerate() {
            let range = self.ptr[k]..self.ptr[k + 1];
            let (idx, bk) = (&self.idx[range.clone()], &self.bk[range]);
            let (mut sb, mut sk) = ([0.0; 2], [0.0; 2]);
            let (idx2, bk2) = (idx.chunks_exact(2), bk.chunks_exact(2));
            let (idx_rest, bk_rest) = (idx2.remainder(), bk2.remainder());
            for (ic, vc) in idx2.zip(bk2) {
                for k in 0..2 {
                    let j = ic[k] as usize;
                    debug_assert!(j < n);
                    // SAFETY: the column indices are < n (built from the pattern in
                    // `RhsOperator::new`) and `v0.len() == u0.len() == n` (asserted above).
                    let (vj, uj) = unsafe { (*v0.get_unchecked(j), *u0.get_unchecked(j)) };
                    sb[k] += vc[k][0] * vj;
                    sk[k] += vc[k][1] * uj;
                }
            }
            for (&j, v) in idx_rest.iter().zip(bk_rest) {
                sb[0] += v[0] * v0[j as usize];
                sk[0] += v[1] * u0[j as usize];
            }
            b[i] = h * f[i] + ((sb[0] + sb[1]) - h * (sk[0] + sk[1]));
        }
    }

    avx2_method! {
        /// `b[i - offset] = h f[i] + (B v0 - h K u0)[i]` for the rows `i` of the pairs `pairs`
        /// (`fuv = [f, u0, v0]`), on AVX2's instructions where the processor has them
        /// (`linalg::with_avx2`).
        pub(super) fn pairs_into / pairs_avx2(
            &self,
            pairs: std::ops::Range<usize>,
            offset: usize,
            h: f64,
            fuv: [&[f64]; 3],
            b: &mut [f64]
        ) => pairs_here
    }

    #[inline(always)]
    pub(super) fn pairs_here(
        &self,
        pairs: std::ops::Range<usize>,
        offset: usize,
        h: f64,
        [f, u0, v0]: [&[f64]; 3],
        b: &mut [f64],
    ) {
        let n = v0.len();
        assert!(u0.len() == n && f.len() == n);
        let mut ahead = self.blocks_ahead(pairs.start);
        for k in pairs {
            ahead(self.blk_ptr[k]);
            let i = self.pair[k] - offset;
            let range = self.pair_ptr[k]..self.pair_ptr[k + 1];
            let (idx, bk) = (&self.pair_idx[range.clone()], &self.pair_bk[range]);
            // [B v of row i, K u of row i, B v of row i + 1, K u of row i + 1].
            let mut s = [0.0; 4];
            for (&j, v) in idx.iter().zip(bk) {
                let j = j as usize;
                debug_assert!(j < n);
                // SAFETY: the column indices are < n (built from the pattern in
                // `RhsOperator::new`) and `v0.len() == u0.len() == n` (asserted above).
                let (vj, uj) = unsafe { (*v0.get_unchecked(j), *u0.get_unchecked(j)) };
                s[0] += v[0] * vj;
                s[1] += v[1] * uj;
                s[2] += v[2] * vj;
                s[3] += v[3] * uj;
            }
            let range = self.blk_ptr[k]..self.blk_ptr[k + 1];
            let idx = &self.blk_idx[range.clone()];
            let (no_g, uva): (&[[f64; 4]], _) = (&[], [u0, v0, &[][..]]);
            let (sb, sk) = match self.blk_form {
                BlockForm::General => {
                    self.blocks::<false, _, _>(idx, &self.blk_bk[range], no_g, 0.0, uva)
                }
                BlockForm::Skew => {
                    let kd = SkewD {
                        kd: &self.blk_kd[range],
                        c2: self.c2,
                    };
                    self.blocks::<false, _, _>(idx, kd, no_g, 0.0, uva)
                }
                BlockForm::Diagonal => {
                    let kd = DiagD {
                        kd: &self.blk_kd[range],
                        c2: self.c2,
                    };
                    self.blocks::<false, _, _>(idx, kd, no_g, 0.0, uva)
                }
            };
            let r = self.pair[k];
            b[i] = h * f[r] + ((s[0] + (sb[0] + sb[1])) - h * (s[1] + (sk[0] + sk[1])));
            b[i + 1] = h * f[r + 1] + ((s[2] + (sb[2] + sb[3])) - h * (s[3] + (sk[2] + sk[3])));
        }
    }

    avx2_method! {
        /// The same as `pairs_into` with the skew part: `b[i - offset] = h f[i] + (B v0 - h (K
        /// u0 + G (v0 + c a0)))[i]` (`fuva = [f, u0, v0, a0]`).
        pub(super) fn pairs_g_into / pairs_g_avx2(
            &self,
            pairs: std::ops::Range<usize>,
            offset: usize,
            h: f64,
            c: f64,
            fuva: [&[f64]; 4],
            b: &mut [f64]
        ) => pairs_g_here
    }

    #[inline(always)]
    pub(super) fn pairs_g_here(
        &self,
        pairs: std::ops::Range<usize>,
        offset: usize,
        h: f64,
        c: f64,
        [f, u0, v0, a0]: [&[f64]; 4],
        b: &mut [f64],
    ) {
        let n = v0.len();
        assert!(u0.len() == n && a0.len() == n && f.len() == n);
        let mut ahead = self.blocks_ahead(pairs.start);
        for k in pairs {
            ahead(self.blk_ptr[k]);
            let i = self.pair[k] - offset;
            let range = self.pair_ptr[k]..self.pair_ptr[k + 1];
            let (idx, bk, g) = (
                &self.pair_idx[range.clone()],
                &self.pair_bk[range.clone()],
                &self.pair_g[range],
            );
            // [B v, K u + G w of row i, the same of row i + 1], w = v0 + c a0.
            let mut s = [0.0; 4];
            for ((&j, v), gj) in idx.iter().zip(bk).zip(g) {
                let j = j as usize;
                debug_assert!(j < n);
                // SAFETY: the column indices are < n (built from the pattern in
                // `RhsOperator::new`) and the three vectors have length n (asserted above).
                let (vj, uj, aj) = unsafe {
                    (
                        *v0.get_unchecked(j),
                        *u0.get_unchecked(j),
                        *a0.get_unchecked(j),
                    )
                };
                let wj = vj + c * aj;
                s[0] += v[0] * vj;
                s[1] += v[1] * uj + gj[0] * wj;
                s[2] += v[2] * vj;
                s[3] += v[3] * uj + gj[1] * wj;
            }
            // The blocks: lanes `[i j, i j+1, i+1 j, i+1 j+1]`.
            let range = self.blk_ptr[k]..self.blk_ptr[k + 1];
            let idx = &self.blk_idx[range.clone()];
            let uva = [u0, v0, a0];
            let (sb, sk) = match self.blk_form {
                BlockForm::Diagonal => {
                    let kd = &self.blk_kd[range];
                    let vals = DiagD { kd, c2: self.c2 };
                    self.blocks::<true, _, _>(idx, vals, SlotSkew(kd), c, uva)
                }
                BlockForm::General => {
                    self.blocks_g(idx, &self.blk_bk[range.clone()], range, c, uva)
                }
                BlockForm::Skew => {
                    let vals = SkewD {
                        kd: &self.blk_kd[range.clone()],
                        c2: self.c2,
                    };
                    self.blocks_g(idx, vals, range, c, uva)
                }
            };
            let r = self.pair[k];
            b[i] = h * f[r] + ((s[0] + (sb[0] + sb[1])) - h * (s[1] + (sk[0] + sk[1])));
            b[i + 1] = h * f[r + 1] + ((s[2] + (sb[2] + sb[3])) - h * (s[3] + (sk[2] + sk[3])));
        }
    }

    /// A prefetch of the blocks for the pairs from `first` on: called with the first block
    /// of each pair in turn, it asks for the lines of the blocks' values, column indices and
    /// skew values `RHS_AHEAD` blocks after it that it has not asked for yet (a pair's few
    /// lines at a time), with [`RhsOperator::prefetch`]; nothing otherwise.
    #[inline(always)]
    pub(super) fn blocks_ahead(&self, first: usize) -> impl FnMut(usize) + '_ {
        let on = self.prefetch;
        let mut done = self.blk_ptr.get(first).map_or(0, |&e| e + RHS_AHEAD);
        move |e: usize| {
            let want = e + RHS_AHEAD;
            if on && want > done {
                use crate::linalg::prefetch_span as span;
                span(&self.blk_idx, done..want);
                span(&self.blk_bk, done..want);
                span(&self.blk_kd, done..want);
                span(&self.blk_g, done..want);
                span(&self.blk_gs, done..want);
                done = want;
            }
        }
    }

    /// Bytes of the blocks' arrays.
    pub(super) fn blk_bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.blk_idx[..])
            + b(&self.blk_bk[..])
            + b(&self.blk_kd[..])
            + b(&self.blk_g[..])
            + b(&self.blk_gs[..])
    }

    /// [`RhsOperator::blocks`] with the skew part held apart from the values (`blk_g` or
    /// `blk_gs`, the blocks `range`).
    #[inline(always)]
    pub(super) fn blocks_g<V: BlockValues>(
        &self,
        idx: &[u32],
        vals: V,
        range: std::ops::Range<usize>,
        c: f64,
        uva: [&[f64]; 3],
    ) -> ([f64; 4], [f64; 4]) {
        if self.blk_g.is_empty() {
            self.blocks::<true, _, _>(idx, vals, ScalarSkew(&self.blk_gs[range]), c, uva)
        } else {
            self.blocks::<true, _, _>(idx, vals, &self.blk_g[range], c, uva)
        }
    }

    /// [`rhs_blocks`], on AVX2 where the processor has it.
    #[inline(always)]
    pub(super) fn blocks<const G: bool, V: BlockValues, S: SkewBlocks>(
        &self,
        idx: &[u32],
        vals: V,
        g: S,
        c: f64,
        uva: [&[f64]; 3],
    ) -> ([f64; 4], [f64; 4]) {
        if self.avx2 {
            // SAFETY: `avx2` is set only where the processor has AVX2 (`new`); the block
            // columns `j, j + 1` are < n and the vectors read have length n (asserted by
            // the callers); `vals` (and with `G`, `g`) have a block for each of `idx`.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                rhs_blocks_avx2::<G, V, S>(idx, vals, g, c, uva)
            }
            #[cfg(not(target_arch = "x86_64"))]
            rhs_blocks::<G, V, S>(idx, vals, g, c, uva)
        } else {
            rhs_blocks::<G, V, S>(idx, vals, g, c, uva)
        }
    }

    /// `b[i] -= h (G (v0 + c a0))[i]` for the rows `i` stored alone (the skew part's share
    /// of `singles_into`).
    pub(super) fn singles_g_into(&self, h: f64, c: f64, v0: &[f64], a0: &[f64], b: &mut [f64]) {
        for (k, &i) in self.single.iter().enumerate() {
            let range = self.ptr[k]..self.ptr[k + 1];
            let s: f64 = self.idx[range.clone()]
                .iter()
                .zip(&self.g[range])
                .map(|(&j, gj)| gj * (v0[j as usize] + c * a0[j as usize]))
                .sum();
            b[i] -= h * s;
        }
    }
}

#[cfg(target_arch = "x86_64")]
use crate::linalg::broadcast2;
#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute_pd,
    _mm256_set1_pd, _mm256_set_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd,
    _mm256_xor_pd,
};

/// The blocks of a pair of rows `i, i + 1` of [`RhsOperator`]: `(sb, sk)`, the lane sums of
/// `B`'s and `K`'s four values of each block times `[v0[j], v0[j + 1], v0[j], v0[j + 1]]`
/// and the same of `u0` (row `i`'s `(B v0)_i` share is `sb[0] + sb[1]`, row `i + 1`'s
/// `sb[2] + sb[3]`). With the skew part (`G`), `sk` also holds `G`'s four values `g` times
/// the lanes of `w = v0 + c a0` (each lane `K u + G w` summed as `K_l u_l + G_l w_l`);
/// without it `g` and `a0` are not read. The order of [`rhs_blocks_avx2`]'s lanes, so that
/// both give the same bits.
///
/// # Panics
/// When `j + 1` is out of range of a vector for a block (debug builds; the indices come
/// from the pattern), or with `G` when `g` is shorter than `idx`.
#[inline(always)]
pub(super) fn rhs_blocks<const G: bool, V: BlockValues, S: SkewBlocks>(
    idx: &[u32],
    vals: V,
    g: S,
    c: f64,
    [u0, v0, a0]: [&[f64]; 3],
) -> ([f64; 4], [f64; 4]) {
    assert!(vals.len() >= idx.len() && (!G || g.len() >= idx.len()));
    let (mut sb, mut sk) = ([0.0; 4], [0.0; 4]);
    for (e, &j) in idx.iter().enumerate() {
        let j = j as usize;
        debug_assert!(j + 1 < v0.len() && j + 1 < u0.len() && (!G || j + 1 < a0.len()));
        // SAFETY: a block's columns `j, j + 1` are < n (`RhsOperator::new`) and the vectors
        // have length n (asserted by the callers).
        let (vl, ul) = unsafe {
            (
                [*v0.get_unchecked(j), *v0.get_unchecked(j + 1)],
                [*u0.get_unchecked(j), *u0.get_unchecked(j + 1)],
            )
        };
        // SAFETY: `e < vals.len()` (asserted above).
        let (bl, kl) = unsafe { vals.lanes(e) };
        for l in 0..4 {
            sb[l] += bl[l] * vl[l % 2];
        }
        if G {
            // SAFETY: as above; `e < g.len()` (asserted above).
            let (al, gj) =
                unsafe { ([*a0.get_unchecked(j), *a0.get_unchecked(j + 1)], g.block(e)) };
            for l in 0..4 {
                let w = vl[l % 2] + c * al[l % 2];
                sk[l] += kl[l] * ul[l % 2] + gj[l] * w;
            }
        } else {
            for l in 0..4 {
                sk[l] += kl[l] * ul[l % 2];
            }
        }
    }
    (sb, sk)
}

/// [`rhs_blocks`] on 256-bit registers, the same operations lane by lane: per block one
/// broadcast of `v0[j..j + 2]` and one of `u0[j..j + 2]` (and of `a0[j..j + 2]`) to both
/// halves, two products (four) and their sums.
///
/// # Safety
/// The processor must have AVX2, `j + 1` must be below the length of the vectors read for
/// every block column `j`, and with `G`, `g.len() >= idx.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn rhs_blocks_avx2<const G: bool, V: BlockValues, S: SkewBlocks>(
    idx: &[u32],
    vals: V,
    g: S,
    c: f64,
    [u0, v0, a0]: [&[f64]; 3],
) -> ([f64; 4], [f64; 4]) {
    debug_assert!(vals.len() >= idx.len() && (!G || g.len() >= idx.len()));
    let (mut sb, mut sk) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let cc = _mm256_set1_pd(c);
    for (e, &j) in idx.iter().enumerate() {
        let j = j as usize;
        debug_assert!(j + 1 < v0.len() && j + 1 < u0.len() && (!G || j + 1 < a0.len()));
        let vl = broadcast2(v0.as_ptr().add(j));
        let ul = broadcast2(u0.as_ptr().add(j));
        let (bl, kl) = vals.lanes_avx2(e);
        sb = _mm256_add_pd(sb, _mm256_mul_pd(bl, vl));
        let ku = _mm256_mul_pd(kl, ul);
        if G {
            let al = broadcast2(a0.as_ptr().add(j));
            let w = _mm256_add_pd(vl, _mm256_mul_pd(cc, al));
            let gw = _mm256_mul_pd(_mm256_loadu_pd(g.block(e).as_ptr()), w);
            sk = _mm256_add_pd(sk, _mm256_add_pd(ku, gw));
        } else {
            sk = _mm256_add_pd(sk, ku);
        }
    }
    let (mut b, mut k) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(b.as_mut_ptr(), sb);
    _mm256_storeu_pd(k.as_mut_ptr(), sk);
    (b, k)
}

/// The values of the blocks of a pair of rows for [`rhs_blocks`]: `B`'s four and `K`'s
/// four, lanes `[i j, i j+1, i+1 j, i+1 j+1]` ([`BlockForm`]).
pub(super) trait BlockValues: Copy {
    /// Blocks held.
    fn len(&self) -> usize;
    /// Block `e`'s values of `B` and of `K`.
    ///
    /// # Safety
    /// `e < self.len()`.
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]);
    /// The same in two registers, by the same operations.
    ///
    /// # Safety
    /// `e < self.len()`, and the processor has AVX2 (called from AVX2 code, into which it
    /// is inlined).
    #[cfg(target_arch = "x86_64")]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d);
}

/// [`BlockForm::General`]: `B`'s four values, then `K`'s.
impl BlockValues for &[[f64; 8]] {
    fn len(&self) -> usize {
        <[[f64; 8]]>::len(self)
    }
    #[inline(always)]
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]) {
        // SAFETY: `e < len` (the caller's contract).
        let v = unsafe { self.get_unchecked(e) };
        ([v[0], v[1], v[2], v[3]], [v[4], v[5], v[6], v[7]])
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d) {
        // SAFETY: `e < len` and AVX2 (the caller's contract).
        unsafe {
            let v = self.get_unchecked(e).as_ptr();
            (_mm256_loadu_pd(v), _mm256_loadu_pd(v.add(4)))
        }
    }
}

/// [`BlockForm::Skew`] (`DIAGONAL` false): `[K's four, d, s]`, `B = [[d, s], [-s, d]] - c2
/// K`; [`BlockForm::Diagonal`] (`DIAGONAL` true): `[K's four, d, g]`, `B = [[d, 0], [0, d]] -
/// c2 K` (`g` is [`SlotSkew`]'s).
#[derive(Clone, Copy)]
pub(super) struct CompactD<'a, const DIAGONAL: bool> {
    kd: &'a [[f64; 6]],
    c2: f64,
}

/// [`BlockForm::Skew`]'s values.
pub(super) type SkewD<'a> = CompactD<'a, false>;
/// [`BlockForm::Diagonal`]'s values.
pub(super) type DiagD<'a> = CompactD<'a, true>;

impl<const DIAGONAL: bool> BlockValues for CompactD<'_, DIAGONAL> {
    fn len(&self) -> usize {
        self.kd.len()
    }
    #[inline(always)]
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]) {
        // SAFETY: `e < len` (the caller's contract).
        let v = unsafe { self.kd.get_unchecked(e) };
        let (c2, d) = (self.c2, v[4]);
        // `D`'s off-diagonal pair.
        let (s1, s2) = if DIAGONAL { (0.0, 0.0) } else { (v[5], -v[5]) };
        (
            [d - c2 * v[0], s1 - c2 * v[1], s2 - c2 * v[2], d - c2 * v[3]],
            [v[0], v[1], v[2], v[3]],
        )
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d) {
        // SAFETY: `e < len` and AVX2 (the caller's contract).
        unsafe {
            let v = self.kd.get_unchecked(e).as_ptr();
            let k = _mm256_loadu_pd(v);
            let d = if DIAGONAL {
                // [d, +0, +0, d].
                _mm256_blend_pd::<0b1001>(_mm256_setzero_pd(), _mm256_set1_pd(*v.add(4)))
            } else {
                // [d, s, d, s] -> [d, s, s, d] -> [d, s, -s, d] (a sign flip, exact).
                let ds = _mm256_permute_pd::<0b0110>(broadcast2(v.add(4)));
                _mm256_xor_pd(ds, _mm256_set_pd(0.0, -0.0, 0.0, 0.0))
            };
            (
                _mm256_sub_pd(d, _mm256_mul_pd(_mm256_set1_pd(self.c2), k)),
                k,
            )
        }
    }
}

/// The skew part's blocks of a pair of rows for [`rhs_blocks`]: four values each, lanes
/// `[i j, i j+1, i+1 j, i+1 j+1]`.
pub(super) trait SkewBlocks: Copy {
    /// Blocks held.
    fn len(&self) -> usize;
    /// Block `e`'s four values.
    ///
    /// # Safety
    /// `e < self.len()`.
    unsafe fn block(&self, e: usize) -> [f64; 4];
}

impl SkewBlocks for &[[f64; 4]] {
    fn len(&self) -> usize {
        <[[f64; 4]]>::len(self)
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        unsafe { *self.get_unchecked(e) }
    }
}

/// Skew blocks `[[0, -g], [g, 0]]` held by their one value `g`: the wheel's Coriolis term
/// (`2 Omega J m_ab`, `crate::frame::add_coriolis`), a quarter of the bytes of four values.
/// Block `e` is `[+0, -g, g, +0]`, the four values it was made from, bit for bit
/// ([`ScalarSkew::holds`]).
#[derive(Clone, Copy)]
pub(super) struct ScalarSkew<'a>(&'a [f64]);

impl ScalarSkew<'_> {
    /// The four values `g` are `[+0, -x, x, +0]` for some `x`, bit for bit.
    pub(super) fn holds(g: &[f64; 4]) -> bool {
        g[0].to_bits() == 0 && g[3].to_bits() == 0 && g[1].to_bits() == (-g[2]).to_bits()
    }
}

impl SkewBlocks for ScalarSkew<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        let g = unsafe { *self.0.get_unchecked(e) };
        [0.0, -g, g, 0.0]
    }
}

/// [`BlockForm::Diagonal`]'s skew blocks `[[0, -g], [g, 0]]`, `g` the sixth value of each
/// block (as [`ScalarSkew`]).
#[derive(Clone, Copy)]
pub(super) struct SlotSkew<'a>(&'a [[f64; 6]]);

impl SkewBlocks for SlotSkew<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        let g = unsafe { self.0.get_unchecked(e)[5] };
        [0.0, -g, g, 0.0]
    }
}
