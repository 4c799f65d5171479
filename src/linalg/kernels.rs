//! The small kernels the row solves are made of (dot products with a gather, the AVX2 block
//! kernel of a pair of rows), the run-time test for AVX2 and the cache prefetch hints.

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
pub(super) fn blocks_dot(idx: &[u32], val: &[[f64; 4]], x: &[f64]) -> [f64; 4] {
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
pub(super) unsafe fn blocks_dot_avx2(idx: &[u32], val: &[[f64; 4]], x: &[f64]) -> [f64; 4] {
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
pub(super) fn dot_dense(a: &[f64], b: &[f64]) -> f64 {
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
pub(super) fn dot_gather(idx: &[u32], val: &[f64], x: &[f64]) -> f64 {
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

/// Prefetches the cache lines of `data[range]` (its end clamped to the length; an empty
/// range asks for nothing) and returns the clamped end.
#[inline(always)]
pub(super) fn prefetch_lines<T>(data: &[T], range: std::ops::Range<usize>) -> usize {
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
pub(super) fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint; it never faults, whatever the address.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T1};
        _mm_prefetch::<_MM_HINT_T1>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
