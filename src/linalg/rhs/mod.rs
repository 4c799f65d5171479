//! The right-hand side of the space-time step as an operator (paper Eqs. 18-19;
//! [`crate::time::step`]):
//! `b = B v0 - h K u0 + h f`, with `B = M - (1 - alpha) h C - (alpha - alpha^2/2) h^2 K`,
//! and with the Coriolis term on the right-hand side `- h G (v0 + alpha h a0)`
//! ([`RhsOperator`]), formed by the tuned kernels (module `kernels`: rows by pairs, blocks
//! of two columns, compact blocks, AVX2, prefetch); [`rhs_plain_into`] forms the same by
//! plain sparse products, the reference the kernels are tested against. `Operators`
//! forms the step's matrices `A` and `B` from `M`, `C` and `K`.

use super::{spmv_add, HugeBuf, Pattern};

mod kernels;
mod nodes3;
use kernels::ScalarSkew;
use nodes3::Nodes3;

/// Bytes of the right-hand side's blocks from which its products prefetch them
/// ([`RhsOperator::blocks_ahead`]): below, they stay in the second-level caches (2 MiB a core
/// on the development host). Within a step the sweeps' factors push the blocks out of the
/// caches, and the products waited on them: on the 192-ring disk (40 MB of blocks) the
/// right-hand side took 2.4-3.1 ms of a step without the prefetch, 1.8-2.2 ms with it, the
/// Coriolis term on either side (an in-process probe, alternated binaries, twice). On the
/// 48-ring disk (2.5 MB of blocks, in the last-level cache) it cost: 0.065 -> 0.080 ms with
/// a threshold of 1 MiB.
const RHS_PREFETCH_MIN_BYTES: usize = 4 << 20;

/// How many blocks ahead of the pair being formed the right-hand side prefetches them (24
/// KiB of six-value blocks).
const RHS_AHEAD: usize = 512;

/// The right-hand side's operators `B` and `K` stored by rows (32-bit column indices, the
/// two values of an entry side by side), so that `B v0 - h K u0` is one pass of dot
/// products without stores in the inner loop; refilled when `B` changes with `h`.
///
/// Two consecutive rows with the same columns (a node's two dofs, always on the wheel) are
/// a pair: their columns are stored once, the four values of an entry side by side, and one
/// gather of `v0` and `u0` serves both rows. Other rows are stored alone. A pair's columns
/// that come two by two (`j, j + 1`: a neighbouring node's two dofs) are a block: one
/// index, eight values, `v0[j..j + 2]` and `u0[j..j + 2]` read in one load each, and on AVX2
/// two 256-bit products (`rhs_blocks_avx2`). Measured on the paper's wheel: the right-hand
/// side 5.4 -> 4.1 us per step (see `Stepper::rhs_into`).
#[derive(Debug, Clone)]
pub struct RhsOperator {
    /// Rows stored alone: `single[k]` is row `i`, its entries `ptr[k]..ptr[k + 1]`.
    single: Vec<usize>,
    ptr: Vec<usize>,
    idx: Vec<u32>,
    /// `[B_ij, K_ij]` per entry.
    bk: Vec<[f64; 2]>,
    /// For each entry, its position in the pattern (by columns).
    src: Vec<usize>,
    /// Pairs: `pair[k]` is the first row `i` (the second is `i + 1`), its entries
    /// `pair_ptr[k]..pair_ptr[k + 1]`.
    pair: Vec<usize>,
    pair_ptr: Vec<usize>,
    pair_idx: Vec<u32>,
    /// `[B_ij, K_ij, B_(i+1)j, K_(i+1)j]` per entry.
    pair_bk: Vec<[f64; 4]>,
    pair_src: Vec<[usize; 2]>,
    /// The pairs' blocks: pair `k`'s are `blk_ptr[k]..blk_ptr[k + 1]`, block `e` the columns
    /// `j = blk_idx[e]` and `j + 1`, `blk_src[e]` its four positions in the pattern, lanes
    /// `[i j, i j+1, i+1 j, i+1 j+1]`. Its values are held in the form `blk_form`
    /// ([`BlockForm`]): `blk_bk[e]`, `B`'s four values then `K`'s, or `blk_kd[e]`, `K`'s four
    /// and two more from which `B` is formed in the products.
    blk_ptr: Vec<usize>,
    blk_idx: HugeBuf<u32>,
    blk_form: BlockForm,
    blk_bk: HugeBuf<[f64; 8]>,
    blk_kd: HugeBuf<[f64; 6]>,
    blk_src: Vec<[usize; 4]>,
    /// `(alpha - alpha^2/2) h^2`: `B = D - c2 K` with `D = M - (1 - alpha) h C`.
    c2: f64,
    /// `G`'s four values of each block (with the Coriolis term on the right-hand side),
    /// unless every block is `[[0, -g], [g, 0]]` (the wheel's Coriolis term, `2 Omega J
    /// m_ab`): then `blk_gs` holds each block's `g` and `blk_g` is empty ([`ScalarSkew`]).
    /// Both empty in [`BlockForm::Diagonal`], where `g` is in `blk_kd`.
    blk_g: Vec<[f64; 4]>,
    blk_gs: Vec<f64>,
    /// The processor has AVX2: the blocks run on [`rhs_blocks_avx2`] (the bits of
    /// [`rhs_blocks`]).
    avx2: bool,
    /// The products prefetch the blocks ahead of them ([`RhsOperator::blocks_ahead`]): set
    /// when they are `RHS_PREFETCH_MIN_BYTES` or more.
    prefetch: bool,
    /// With the Coriolis term on the right-hand side, the skew part `G` by the same rows:
    /// `g[e]` beside `bk[e]`, `pair_g[e] = [G_ij, G_(i+1)j]` beside `pair_bk[e]` (empty
    /// otherwise).
    g: Vec<f64>,
    pair_g: Vec<[f64; 2]>,
    /// From `RHS_SPLIT_MIN_ORDER` on (and two pairs), the pairs are formed in parts of
    /// about equal entries side by side, one a thread of the team's
    /// ([`RhsOperator::pair_parts`]); on two threads at most, in two halves, the second's
    /// first pair this one (a join, without the parts' lists).
    pair_mid: Option<usize>,
    /// `G` is on the right-hand side (`RhsValues::g` not empty): [`RhsOperator::apply`]
    /// forms `- h G (v0 + c a0)`.
    skew: bool,
    /// The pattern's order.
    n: usize,
    /// A 3D solid's rows by node blocks ([`Nodes3`]), where they have the form: then the
    /// singles and pairs above are empty.
    nodes3: Option<Nodes3>,
}

/// The order from which the right-hand side's pairs of rows are formed in parts side by
/// side, one a thread of the run's (`Team::for_each`; one thread runs them all with
/// `Par::Seq`): the orders
/// whose factor is split for two threads (`linalg::Factor::parts`).
const RHS_SPLIT_MIN_ORDER: usize = crate::linalg::SPLIT_MIN_ORDER;

/// How the right-hand side's blocks hold their values ([`RhsOperator`]). In the wheel, `M` and
/// the mass-proportional damping are `m_ab I` per pair of nodes and the Coriolis term `2
/// Omega m_ab J`, so that `D = M - (1 - alpha) h C` has two values per block, or one, and
/// `B = D - c2 K` need not be stored: a block is read as six values instead of eight
/// (nine with the Coriolis term on the right-hand side, seven when `G` is by one value).
/// `B`'s four values are formed lane by lane by the operations `Operators::fill` forms
/// them with ([`BParts`]), from `D`'s values checked equal to `D`'s
/// ([`RhsOperator::compact_form`]), so every form gives the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BlockForm {
    /// `blk_bk`: `B`'s four values, then `K`'s.
    General,
    /// `blk_kd = [K's four, d, s]`, `D = [[d, s], [-s, d]]`.
    Skew,
    /// `blk_kd = [K's four, d, g]`, `D = [[d, 0], [0, d]]` and `G = [[0, -g], [g, 0]]`
    /// (`g` zero without the Coriolis term on the right-hand side).
    Diagonal,
}

/// The size of the blocks' eight values from which they are held in a compact form
/// ([`BlockForm`]): below, they stay in the second-level cache between steps, where forming
/// `B` costs more than reading it (the paper's wheel, 0.2 MB: 18.8 -> 21.1 us a free step;
/// `wheel.toml`'s, 0.8 MB: 49.9 and 50.2 us; graded 576 rim nodes, 1.7 MB: 154 -> 150 us;
/// 48 rings, 3.2 MB: 400-417 -> 380-394 us with the Coriolis term on the right-hand side;
/// `softway matrix`, alternated binaries).
const COMPACT_MIN_BYTES: usize = 1 << 20;

/// `B = D - c2 K` with `D = M - k1 C`, `k1 = (1 - alpha) h`, `c2 = (alpha - alpha^2/2) h^2`:
/// the one place `B`'s values are formed (`Operators::fill`), and `D`'s of the right-hand
/// side's compact blocks, which form `B` from `D` and `K` with these very operations
/// (`BlockForm`), so that both round alike.
#[derive(Debug, Clone, Copy)]
pub struct BParts {
    k1: f64,
    c2: f64,
}

impl BParts {
    /// The parts for the scheme's `alpha` and the step `h`.
    pub fn new(alpha: f64, h: f64) -> Self {
        Self {
            k1: (1.0 - alpha) * h,
            c2: (alpha - 0.5 * alpha * alpha) * h * h,
        }
    }

    /// `D`'s value of an entry from `M`'s and `C`'s.
    #[inline(always)]
    pub fn d(&self, m: f64, c: f64) -> f64 {
        m - self.k1 * c
    }

    /// `B`'s value of an entry from `M`'s, `C`'s and `K`'s.
    #[inline(always)]
    pub fn b(&self, m: f64, c: f64, k: f64) -> f64 {
        self.d(m, c) - self.c2 * k
    }
}

/// The values the right-hand side's rows are filled from, for one step: `B`
/// ([`BParts::b`]) and its parts `M`, `C` (the symmetric part with the Coriolis term on the
/// right-hand side) and `K`, and `G` (empty unless on the right-hand side).
#[derive(Debug, Clone, Copy)]
pub struct RhsValues<'a> {
    /// `M`'s values on the pattern.
    pub m: &'a [f64],
    /// `C`'s (its symmetric part `C_s` with `G` on the right-hand side).
    pub c: &'a [f64],
    /// `K`'s.
    pub k: &'a [f64],
    /// `G`'s, the skew part of `C` on the right-hand side (empty: none).
    pub g: &'a [f64],
    /// `B`'s, formed by [`BParts::b`] from `m`, `c` and `k` (`Operators::fill`).
    pub bv: &'a [f64],
    /// The step's coefficients of `B`.
    pub parts: BParts,
}

impl RhsOperator {
    /// The operator on `pattern` (structurally symmetric or not) for `values`' step: by
    /// node blocks where a 3D solid's rows allow them (`K`'s nine values, `d` and `g` a 3 x 3
    /// block: module `nodes3`), else by pairs.
    pub fn new(pattern: &Pattern, values: &RhsValues) -> Self {
        Self::build(pattern, values, true)
    }

    /// The same by pairs of rows even where node blocks would do: the reference
    /// `benches/solver3d.rs` times the node blocks against.
    #[doc(hidden)]
    pub fn by_pairs(pattern: &Pattern, values: &RhsValues) -> Self {
        Self::build(pattern, values, false)
    }

    /// True when the rows are formed by 3D node blocks (module `nodes3`).
    pub fn by_node_blocks(&self) -> bool {
        self.nodes3.is_some()
    }

    fn build(pattern: &Pattern, values: &RhsValues, nodes: bool) -> Self {
        let g = values.g;
        let n = pattern.nrows();
        assert!(n <= u32::MAX as usize, "too many dofs for 32-bit indices");
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        let nnz = cp[pattern.ncols()];
        // The pattern by rows: (column, position by columns).
        let mut ptr = vec![0usize; n + 1];
        for &i in &ri[..nnz] {
            ptr[i + 1] += 1;
        }
        for i in 0..n {
            ptr[i + 1] += ptr[i];
        }
        let mut next = ptr[..n].to_vec();
        let mut by_rows = vec![(0u32, 0usize); nnz];
        for j in 0..pattern.ncols() {
            for p in cp[j]..cp[j + 1] {
                by_rows[next[ri[p]]] = (j as u32, p);
                next[ri[p]] += 1;
            }
        }
        let row = |i: usize| &by_rows[ptr[i]..ptr[i + 1]];
        let mut rows = Self {
            single: Vec::new(),
            ptr: vec![0],
            idx: Vec::new(),
            bk: Vec::new(),
            src: Vec::new(),
            pair: Vec::new(),
            pair_ptr: vec![0],
            pair_idx: Vec::new(),
            pair_bk: Vec::new(),
            pair_src: Vec::new(),
            blk_ptr: vec![0],
            blk_idx: HugeBuf::default(),
            blk_form: BlockForm::General,
            blk_bk: HugeBuf::default(),
            blk_kd: HugeBuf::default(),
            blk_src: Vec::new(),
            c2: 0.0,
            blk_g: Vec::new(),
            blk_gs: Vec::new(),
            avx2: crate::linalg::has_avx2(),
            skew: !values.g.is_empty(),
            n: pattern.nrows(),
            prefetch: false,
            g: Vec::new(),
            pair_g: Vec::new(),
            pair_mid: None,
            nodes3: None,
        };
        if let Some(nodes) = nodes.then(|| Nodes3::new(n, row, values)).flatten() {
            rows.nodes3 = Some(nodes);
            return rows;
        }
        let (mut i, mut blk_idx) = (0, Vec::new());
        while i < n {
            let same = i + 1 < n
                && row(i).len() == row(i + 1).len()
                && row(i).iter().zip(row(i + 1)).all(|(a, b)| a.0 == b.0);
            if same {
                rows.pair.push(i);
                let (a, b) = (row(i), row(i + 1));
                let mut e = 0;
                while e < a.len() {
                    if e + 1 < a.len() && a[e + 1].0 == a[e].0 + 1 {
                        blk_idx.push(a[e].0);
                        rows.blk_src.push([a[e].1, a[e + 1].1, b[e].1, b[e + 1].1]);
                        e += 2;
                    } else {
                        rows.pair_idx.push(a[e].0);
                        rows.pair_src.push([a[e].1, b[e].1]);
                        e += 1;
                    }
                }
                rows.pair_ptr.push(rows.pair_idx.len());
                rows.blk_ptr.push(blk_idx.len());
                i += 2;
            } else {
                rows.single.push(i);
                for a in row(i) {
                    rows.idx.push(a.0);
                    rows.src.push(a.1);
                }
                rows.ptr.push(rows.idx.len());
                i += 1;
            }
        }
        rows.blk_idx = blk_idx.into();
        if n >= RHS_SPLIT_MIN_ORDER && rows.pair.len() >= 2 {
            let pairs = rows.pair.len();
            let half = rows.entries_before(pairs) / 2;
            rows.pair_mid = Some(rows.first_pair_with(half).clamp(1, pairs - 1));
        }
        rows.bk = vec![[0.0; 2]; rows.idx.len()];
        rows.pair_bk = vec![[0.0; 4]; rows.pair_idx.len()];
        if !g.is_empty() {
            rows.g = rows.src.iter().map(|&p| g[p]).collect();
            rows.pair_g = rows.pair_src.iter().map(|&[p, q]| [g[p], g[q]]).collect();
        }
        rows.refill(values);
        rows
    }

    /// The form the blocks' values are held in for `values`: [`BlockForm::General`] below
    /// `COMPACT_MIN_BYTES`, else the most compact one they allow
    /// ([`RhsOperator::compact_form`]).
    fn block_form(&self, values: &RhsValues) -> BlockForm {
        if std::mem::size_of::<[f64; 8]>() * self.blk_src.len() < COMPACT_MIN_BYTES {
            BlockForm::General
        } else {
            self.compact_form(values)
        }
    }

    /// The most compact form the blocks' values allow for `values` ([`BlockForm`]): each of
    /// `D`'s values it holds equal to `D`'s (`==`: a zero's sign aside, which no sum that
    /// starts at `+0` can tell), so that `B`'s formed from them are `B`'s ([`BParts`]).
    fn compact_form(&self, values: &RhsValues) -> BlockForm {
        let RhsValues { m, c, g, parts, .. } = *values;
        let d = |p: usize| parts.d(m[p], c[p]);
        let same = |p: usize, q: usize| d(p).to_bits() == d(q).to_bits();
        let diagonal = (g.is_empty()
            || self
                .blk_src
                .iter()
                .all(|s| ScalarSkew::holds(&s.map(|p| g[p]))))
            && self
                .blk_src
                .iter()
                .all(|s| same(s[0], s[3]) && d(s[1]) == 0.0 && d(s[2]) == 0.0);
        if diagonal {
            return BlockForm::Diagonal;
        }
        let skew = self
            .blk_src
            .iter()
            .all(|s| same(s[0], s[3]) && d(s[2]) == -d(s[1]));
        if skew {
            BlockForm::Skew
        } else {
            BlockForm::General
        }
    }

    /// `b = h f + B v0 - h K u0`, where `f` is the external force at `t0 + alpha h` (N per
    /// dof), and with `G` on the right-hand side `- h G (v0 + c a0)` as well (`a0` is read
    /// only then; `c = alpha h`): the space-time step's right-hand side (paper Eqs. 18-19,
    /// module docs of [`crate::time::step`]), formed by the tuned kernels one row, or pair of
    /// rows, at a time, `h f` with the rest on the thread that forms the row; from
    /// `RHS_SPLIT_MIN_ORDER` on the pairs in parts side by side, as many as `team` has
    /// threads to give ([`Team::width`](crate::linalg::team::Team::width)), with the same
    /// bits on any number of threads (a row is formed whole by one thread). [`rhs_plain_into`] is its reference.
    ///
    /// # Panics
    /// When a vector's length is not the pattern's order.
    pub fn apply(
        &self,
        team: &crate::linalg::team::Team,
        h: f64,
        c: f64,
        [u0, v0, a0]: [&[f64]; 3],
        f: &[f64],
        b: &mut [f64],
    ) {
        let r = self;
        let n = self.n;
        assert!(b.len() == n && v0.len() == n && u0.len() == n && f.len() == n);
        let pairs = r.pair.len();
        let skew = self.skew;
        assert!(!skew || a0.len() == n);
        if let Some(nodes) = &self.nodes3 {
            nodes.apply(team, h, c, skew, [u0, v0, a0], f, b);
            return;
        }
        let part = |range: std::ops::Range<usize>, offset: usize, b: &mut [f64]| {
            if skew {
                r.pairs_g_into(range, offset, h, c, [f, u0, v0, a0], b);
            } else {
                r.pairs_into(range, offset, h, [f, u0, v0], b);
            }
        };
        // Each part's rows start at its first pair's row; a row is formed whole by one
        // thread, so the parts' count changes no bit.
        match r.pair_mid {
            Some(mid) if team.width() <= 2 => {
                let cut = r.pair[mid];
                let (lo, hi) = b.split_at_mut(cut);
                team.join(|| part(0..mid, 0, lo), || part(mid..pairs, cut, hi));
            }
            Some(_) => {
                let mut parts = r.pair_parts(team.width(), b);
                team.for_each(&mut parts, |(range, offset, b)| {
                    part(range.clone(), *offset, b)
                });
            }
            None => part(0..pairs, 0, b),
        }
        r.singles_into(h, f, u0, v0, b);
        if skew {
            r.singles_g_into(h, c, v0, a0, b);
        }
    }

    /// Entries before pair `k` (a block is two columns).
    fn entries_before(&self, k: usize) -> usize {
        self.pair_ptr[k] + 2 * self.blk_ptr[k]
    }

    /// The first pair with `want` entries or more before it (the count of pairs if none).
    fn first_pair_with(&self, want: usize) -> usize {
        let (mut lo, mut hi) = (0, self.pair.len());
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.entries_before(mid) >= want {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        lo
    }

    /// The pairs in `parts` contiguous runs of about equal entries (at most one a pair),
    /// each with its first row and the rows of `b` from it to the next run's first (the
    /// rows of the singles between are written after, by the caller).
    fn pair_parts<'b>(
        &self,
        parts: usize,
        b: &'b mut [f64],
    ) -> Vec<(std::ops::Range<usize>, usize, &'b mut [f64])> {
        let pairs = self.pair.len();
        let parts = parts.clamp(1, pairs.max(1));
        let total = self.entries_before(pairs);
        let mut cuts = vec![0];
        for j in 1..parts {
            let k = self.first_pair_with(j * total / parts);
            let last = *cuts.last().expect("a first cut");
            cuts.push(k.clamp(last + 1, pairs - (parts - j)));
        }
        cuts.push(pairs);
        let mut out = Vec::with_capacity(parts);
        let mut rest = b;
        let mut row = 0;
        for w in cuts.windows(2) {
            let next = if w[1] < pairs {
                self.pair[w[1]]
            } else {
                self.n
            };
            let (mine, tail) = std::mem::take(&mut rest).split_at_mut(next - row);
            out.push((w[0]..w[1], row, mine));
            rest = tail;
            row = next;
        }
        out
    }

    /// Bytes of the arrays a right-hand side reads (the positions in the pattern, read only
    /// when the values change, left out).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.single[..])
            + b(&self.ptr[..])
            + b(&self.idx[..])
            + b(&self.bk[..])
            + b(&self.g[..])
            + b(&self.pair[..])
            + b(&self.pair_ptr[..])
            + b(&self.pair_idx[..])
            + b(&self.pair_bk[..])
            + b(&self.pair_g[..])
            + b(&self.blk_ptr[..])
            + self.blk_bytes()
            + self.nodes3.as_ref().map_or(0, Nodes3::bytes)
    }

    /// Fills the values for `values`' step (the blocks' arrays are allocated again only
    /// when their form changes).
    pub fn refill(&mut self, values: &RhsValues) {
        self.skew = !values.g.is_empty();
        if let Some(nodes) = &mut self.nodes3 {
            nodes.refill(values);
            return;
        }
        let (k, bv) = (values.k, values.bv);
        for (e, &p) in self.bk.iter_mut().zip(&self.src) {
            *e = [bv[p], k[p]];
        }
        for (e, &[p, q]) in self.pair_bk.iter_mut().zip(&self.pair_src) {
            *e = [bv[p], k[p], bv[q], k[q]];
        }
        self.fill_blocks(self.block_form(values), values);
    }

    /// Fills the blocks' values in the form `form` (which must hold for `values`:
    /// [`RhsOperator::block_form`]), allocating their arrays when the form changes.
    fn fill_blocks(&mut self, form: BlockForm, values: &RhsValues) {
        let RhsValues {
            m,
            c,
            k,
            g,
            bv,
            parts,
        } = *values;
        let nb = self.blk_src.len();
        let allocated = match form {
            BlockForm::General => self.blk_bk.len() == nb,
            BlockForm::Skew | BlockForm::Diagonal => self.blk_kd.len() == nb,
        };
        if form != self.blk_form || !allocated {
            self.blk_form = form;
            (self.blk_bk, self.blk_kd, self.blk_g, self.blk_gs) = Default::default();
            match form {
                BlockForm::General => self.blk_bk = vec![[0.0; 8]; nb].into(),
                BlockForm::Skew | BlockForm::Diagonal => {
                    self.blk_kd = vec![[0.0; 6]; nb].into();
                }
            }
            if !g.is_empty() && form != BlockForm::Diagonal {
                let four: Vec<[f64; 4]> = self.blk_src.iter().map(|s| s.map(|p| g[p])).collect();
                if four.iter().all(ScalarSkew::holds) {
                    // A quarter of the bytes, the same values (and bits) in the products.
                    self.blk_gs = four.iter().map(|g| g[2]).collect();
                } else {
                    self.blk_g = four;
                }
            }
        }
        self.c2 = parts.c2;
        let d = |p: usize| parts.d(m[p], c[p]);
        let ks = |s: &[usize; 4]| s.map(|p| k[p]);
        match form {
            BlockForm::General => {
                for (e, s) in self.blk_bk.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    *e = [
                        bv[s[0]], bv[s[1]], bv[s[2]], bv[s[3]], kk[0], kk[1], kk[2], kk[3],
                    ];
                }
            }
            BlockForm::Skew => {
                for (e, s) in self.blk_kd.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    *e = [kk[0], kk[1], kk[2], kk[3], d(s[0]), d(s[1])];
                }
            }
            BlockForm::Diagonal => {
                for (e, s) in self.blk_kd.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    let gs = if g.is_empty() { 0.0 } else { g[s[2]] };
                    *e = [kk[0], kk[1], kk[2], kk[3], d(s[0]), gs];
                }
            }
        }
        self.prefetch = self.blk_bytes() >= RHS_PREFETCH_MIN_BYTES;
    }
}

/// The matrices the step's operators are made of.
pub(crate) struct Operators<'a> {
    pub(crate) m: &'a [f64],
    pub(crate) c: &'a [f64],
    pub(crate) k: &'a [f64],
    pub(crate) pattern: &'a Pattern,
    pub(crate) is_bc: &'a [bool],
}

impl Operators<'_> {
    /// `A = M + alpha h C + alpha^2 h^2/2 K`, `B = M - (1-alpha) h C - (alpha - alpha^2/2)
    /// h^2 K` and `A` with the Dirichlet identity rows, for the step `h`.
    pub(crate) fn fill(
        &self,
        a: f64,
        h: f64,
        a_orig: &mut [f64],
        bv: &mut [f64],
        a_work: &mut [f64],
    ) {
        let (m, c, k) = (self.m, self.c, self.k);
        let parts = BParts::new(a, h);
        for p in 0..m.len() {
            a_orig[p] = m[p] + a * h * c[p] + 0.5 * a * a * h * h * k[p];
            bv[p] = parts.b(m[p], c[p], k[p]);
        }
        a_work.copy_from_slice(a_orig);
        crate::linalg::set_identity_rows(self.pattern, a_work, self.is_bc);
    }
}

/// The plain reference of [`RhsOperator::apply`]: `b = h f + B v0 - h K u0 - h G (v0 + c
/// a0)` (the last term when `values.g` is not empty) by sparse products by columns on
/// `pattern` ([`crate::linalg::spmv_add`]), in another order of the sums: the same to
/// round-off. It allocates (`v0 + c a0`); the time loop uses the operator.
///
/// # Panics
/// When a vector's length is not the pattern's order.
pub fn rhs_plain_into(
    pattern: &Pattern,
    values: &RhsValues,
    h: f64,
    c: f64,
    [u0, v0, a0]: [&[f64]; 3],
    f: &[f64],
    b: &mut [f64],
) {
    for (bi, fi) in b.iter_mut().zip(f) {
        *bi = h * fi;
    }
    spmv_add(pattern, values.bv, 1.0, v0, b);
    spmv_add(pattern, values.k, -h, u0, b);
    if !values.g.is_empty() {
        let w: Vec<f64> = v0.iter().zip(a0).map(|(v, a)| v + c * a).collect();
        spmv_add(pattern, values.g, -h, &w, b);
    }
}

#[cfg(test)]
mod tests;
