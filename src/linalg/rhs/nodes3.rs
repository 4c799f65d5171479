//! The right-hand side of a 3D solid's step by node blocks: three rows (a node's three
//! dofs) with one column list, their columns in aligned triples (a neighbouring node's
//! three dofs), each 3 x 3 block held as `K`'s nine values and two more.
//!
//! In a solid, `M = M_s (x) I_3` (the scalar mass, `crate::frame3d::scalar_mass`) and the
//! Coriolis term of a spin about a coordinate axis `e_k` is `G = 2 M_s (x) Omega [e_k]_x`
//! (`crate::frame3d::add_coriolis`), so that a block of `D = M - (1 - alpha) h C_s` is `d
//! I_3` and one of `G` is `g [e_k]_x`. With `z = c2 v0 + h u0` (`c2 = (alpha - alpha^2/2)
//! h^2`, `B = D - c2 K`) the right-hand side is
//!
//! ```text
//! b = h f + D v0 - K z - h G (v0 + c a0),
//! ```
//!
//! read as eleven values a block of nine entries (`[K's nine by rows, d, g]`, 88 bytes
//! and a 32-bit column index) where the rows of pairs read `B`'s and `K`'s values and the
//! skew part's beside them (some 26 bytes an entry). The form is taken only when `M`, the
//! symmetric part of `C` and `G` have it bit for bit, block by block
//! ([`Nodes3::new`]): then `D`'s three diagonal values are one for every step length and
//! `G`'s block is `g [e_k]_x` exactly.

use crate::linalg::team::Team;
use crate::linalg::HugeBuf;

/// A block's values: `K`'s nine by rows, `d` and `g`.
pub(super) type Block = [f64; 11];

/// Node rows of three by blocks (module docs).
#[derive(Debug, Clone)]
pub(super) struct Nodes3 {
    /// Triple `t` is rows `3 t .. 3 t + 3`; its blocks are `ptr[t]..ptr[t + 1]`.
    ptr: Vec<usize>,
    /// Each block's first column `j` (its columns `j, j + 1, j + 2`).
    idx: HugeBuf<u32>,
    /// Each block's values ([`Block`]).
    val: HugeBuf<Block>,
    /// Each block's nine positions in the pattern (by columns), by rows.
    src: Vec<[usize; 9]>,
    /// The spin's axis `k` of `G = g [e_k]_x` (any, without `G`).
    axis: usize,
    /// `(alpha - alpha^2/2) h^2` of the values held.
    c2: f64,
    /// The triple from which the second of two threads forms the rows.
    mid: usize,
}

/// `[e_k]_x`'s two entries: `(p, q)` holds `+1`, `(q, p)` holds `-1`.
fn skew_slots(k: usize) -> (usize, usize) {
    ((k + 2) % 3, (k + 1) % 3)
}

impl Nodes3 {
    /// The node blocks of the pattern whose rows are `row(i)` (`(column, position)` in
    /// column order), when every row is one of a triple `3 t, 3 t + 1, 3 t + 2` with one
    /// column list of aligned triples, `M`'s and `C`'s (the symmetric part with `G` on the
    /// right-hand side) blocks are `x I_3` and `G`'s are `g [e_k]_x` for one axis `k`, bit
    /// for bit; `None` otherwise (the rows by pairs then).
    pub(super) fn new<'r>(
        n: usize,
        row: impl Fn(usize) -> &'r [(u32, usize)],
        values: &super::RhsValues,
    ) -> Option<Self> {
        if n == 0 || n % 3 != 0 {
            return None;
        }
        let (mut ptr, mut idx, mut src) = (vec![0], Vec::new(), Vec::new());
        for t in 0..n / 3 {
            let r = [row(3 * t), row(3 * t + 1), row(3 * t + 2)];
            let len = r[0].len();
            if len % 3 != 0 || r.iter().any(|x| x.len() != len) {
                return None;
            }
            for e in (0..len).step_by(3) {
                let j = r[0][e].0;
                let aligned =
                    j % 3 == 0 && (0..3).all(|b| r.iter().all(|x| x[e + b].0 == j + b as u32));
                if !aligned {
                    return None;
                }
                idx.push(j);
                src.push(std::array::from_fn(|l| r[l / 3][e + l % 3].1));
            }
            ptr.push(idx.len());
        }
        let axis = Self::form(&src, values)?;
        let half = idx.len() / 2;
        let mid = ptr.partition_point(|&p| p < half).min(n / 3);
        let mut nodes = Self {
            ptr,
            idx: idx.into(),
            val: vec![[0.0; 11]; src.len()].into(),
            src,
            axis,
            c2: 0.0,
            mid,
        };
        nodes.refill(values);
        Some(nodes)
    }

    /// The axis `k` when every block's `M` and `C` are `x I_3` and `G` is `g [e_k]_x` bit
    /// for bit (a zero's sign aside); `None` otherwise.
    fn form(src: &[[usize; 9]], values: &super::RhsValues) -> Option<usize> {
        let super::RhsValues { m, c, g, .. } = *values;
        let scalar = |v: &[f64], s: &[usize; 9]| {
            (0..9).all(|l| {
                let x = v[s[l]];
                if l % 4 == 0 {
                    x.to_bits() == v[s[0]].to_bits()
                } else {
                    x == 0.0
                }
            })
        };
        if !src.iter().all(|s| scalar(m, s) && scalar(c, s)) {
            return None;
        }
        if g.is_empty() {
            return Some(2);
        }
        // The axis of the first block with a non-zero `G`.
        let axis = src
            .iter()
            .find_map(|s| (0..9).find(|&l| g[s[l]] != 0.0))
            .map_or(2, |l| {
                let (a, b) = (l / 3, l % 3);
                3 - a - b
            });
        let (p, q) = skew_slots(axis);
        let holds = src.iter().all(|s| {
            let gv = g[s[3 * p + q]];
            (0..9).all(|l| match (l / 3, l % 3) {
                (a, b) if (a, b) == (p, q) => true,
                (a, b) if (a, b) == (q, p) => g[s[l]] == -gv,
                _ => g[s[l]] == 0.0,
            })
        });
        holds.then_some(axis)
    }

    /// Fills the blocks' values for `values`' step.
    pub(super) fn refill(&mut self, values: &super::RhsValues) {
        let super::RhsValues {
            m, c, k, g, parts, ..
        } = *values;
        let (p, q) = skew_slots(self.axis);
        for (v, s) in self.val.iter_mut().zip(&self.src) {
            for l in 0..9 {
                v[l] = k[s[l]];
            }
            v[9] = parts.d(m[s[0]], c[s[0]]);
            v[10] = if g.is_empty() { 0.0 } else { g[s[3 * p + q]] };
        }
        self.c2 = parts.c2;
    }

    /// Bytes of the arrays a right-hand side reads.
    pub(super) fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.ptr[..]) + b(&self.idx[..]) + b(&self.val[..])
    }

    /// `b = h f + D v0 - K (c2 v0 + h u0)`, and with `skew` `- h G (v0 + c a0)` (module
    /// docs): on two threads the two halves of the triples side by side, on more as many
    /// parts of about equal blocks as `team` has threads to give; a row is formed whole by
    /// one thread, so the bits are those of one.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn apply(
        &self,
        team: &Team,
        h: f64,
        c: f64,
        skew: bool,
        uva: [&[f64]; 3],
        f: &[f64],
        b: &mut [f64],
    ) {
        let triples = self.ptr.len() - 1;
        let part = |range: std::ops::Range<usize>, b: &mut [f64]| {
            if skew {
                self.rows_into::<true>(range, h, c, uva, f, b);
            } else {
                self.rows_into::<false>(range, h, c, uva, f, b);
            }
        };
        let width = team.width();
        if width < 2 || self.mid == 0 || self.mid >= triples {
            part(0..triples, b);
        } else if width == 2 {
            let (lo, hi) = b.split_at_mut(3 * self.mid);
            team.join(|| part(0..self.mid, lo), || part(self.mid..triples, hi));
        } else {
            // One part a thread, up to `MAX_PARTS`, held on the stack (no allocation a step).
            let width = width.min(MAX_PARTS);
            let blocks = self.idx.len();
            let mut parts: [(std::ops::Range<usize>, &mut [f64]); MAX_PARTS] =
                std::array::from_fn(|_| (0..0, &mut [][..]));
            let (mut rest, mut t0) = (b, 0);
            for (w, slot) in parts.iter_mut().enumerate().take(width) {
                let t1 = if w + 1 == width {
                    triples
                } else {
                    let want = (w + 1) * blocks / width;
                    self.ptr.partition_point(|&p| p < want).clamp(t0, triples)
                };
                let (mine, tail) = std::mem::take(&mut rest).split_at_mut(3 * (t1 - t0));
                *slot = (t0..t1, mine);
                (rest, t0) = (tail, t1);
            }
            team.for_each(&mut parts[..width], |(range, b)| part(range.clone(), b));
        }
    }

    /// The rows of `triples` into `b`, whose first row is the first triple's.
    #[inline]
    fn rows_into<const G: bool>(
        &self,
        triples: std::ops::Range<usize>,
        h: f64,
        c: f64,
        [u0, v0, a0]: [&[f64]; 3],
        f: &[f64],
        b: &mut [f64],
    ) {
        crate::linalg::with_avx2!(
            self.rows_here::<G>(triples, h, c, [u0, v0, a0], f, b),
            self.rows_avx2::<G>(triples, h, c, [u0, v0, a0], f, b)
        );
    }

    /// [`Nodes3::rows_here`] compiled for AVX2.
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn rows_avx2<const G: bool>(
        &self,
        triples: std::ops::Range<usize>,
        h: f64,
        c: f64,
        uva: [&[f64]; 3],
        f: &[f64],
        b: &mut [f64],
    ) {
        self.rows_here::<G>(triples, h, c, uva, f, b);
    }

    /// The rows of `triples` into `b` (as [`Nodes3::rows_into`]): per block, `d v0`, `K z`
    /// and with `G` `g [e_k]_x w` summed by rows, `z` and `w` formed from the block's
    /// columns of the state.
    #[inline(always)]
    fn rows_here<const G: bool>(
        &self,
        triples: std::ops::Range<usize>,
        h: f64,
        c: f64,
        [u0, v0, a0]: [&[f64]; 3],
        f: &[f64],
        b: &mut [f64],
    ) {
        let n = v0.len();
        assert!(u0.len() == n && f.len() == n && (!G || a0.len() == n));
        assert!(b.len() >= 3 * triples.len());
        let c2 = self.c2;
        let (p, q) = skew_slots(self.axis);
        let first = triples.start;
        let ahead = |e: usize| {
            use crate::linalg::prefetch_span as span;
            span(&self.val, e + AHEAD..e + AHEAD + 1);
        };
        for t in triples {
            let range = self.ptr[t]..self.ptr[t + 1];
            let (idx, val) = (&self.idx[range.clone()], &self.val[range.clone()]);
            // [D v0, K z, G w] by rows.
            let (mut sd, mut sk, mut sg) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            for (e, (&j, v)) in idx.iter().zip(val).enumerate() {
                ahead(range.start + e);
                let j = j as usize;
                assert!(j + 2 < n);
                let vj = [v0[j], v0[j + 1], v0[j + 2]];
                let uj = [u0[j], u0[j + 1], u0[j + 2]];
                let z: [f64; 3] = std::array::from_fn(|l| c2 * vj[l] + h * uj[l]);
                for a in 0..3 {
                    sd[a] += v[9] * vj[a];
                    sk[a] += v[3 * a] * z[0] + v[3 * a + 1] * z[1] + v[3 * a + 2] * z[2];
                }
                if G {
                    let w = [
                        vj[0] + c * a0[j],
                        vj[1] + c * a0[j + 1],
                        vj[2] + c * a0[j + 2],
                    ];
                    sg[p] += v[10] * w[q];
                    sg[q] -= v[10] * w[p];
                }
            }
            let r = 3 * (t - first);
            for a in 0..3 {
                let i = 3 * t + a;
                b[r + a] = h * f[i] + (sd[a] - sk[a] - h * sg[a]);
            }
        }
    }
}

/// The most parts the rows are formed in side by side (a team wider than this gives each of
/// these parts a thread and leaves the rest idle for the right-hand side).
const MAX_PARTS: usize = 8;

/// How many blocks ahead of the one being formed the values are asked for (about 22 KiB).
const AHEAD: usize = 256;
