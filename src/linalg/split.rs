//! Two independent parts of a factor for two threads.
//!
//! In the elimination tree of a structurally symmetric matrix, two disjoint sets of subtrees
//! do not touch each other: the columns of `L` in one set have their rows in that set or in
//! the remaining columns (their ancestors, the "top"), never in the other set. Numbered as
//! `[part 0 | part 1 | top]` (a reordering that keeps every column after its descendants,
//! so the fill is that of the ordering it came from), the factors are
//!
//! ```text
//! L = [L00  0    0  ]      U = [U00  0    U02]
//!     [0    L11  0  ]          [0    U11  U12]
//!     [L20  L21  L22]          [0    0    U22]
//! ```
//!
//! and the two sweeps of a solve each run their two parts side by side: forward, part 0 and
//! part 1 on two threads (each keeping its contributions to the top in room of its own
//! after its unknowns, added after, part 0's first), then the top; backward, the top, then
//! parts 0 and 1 on two threads. The solve's vector is spread for this
//! ([`SplitLower::spread_len`]): each part's unknowns and room are one contiguous slice, solved
//! in place. Every sum is made in the same order whatever the number of threads, so the
//! result does not depend on it (`Team::join` runs both halves on one thread with
//! `Par::Seq`).
//!
//! [`two_subtrees`] finds the parts (the pair of subtree sets with the least critical path,
//! the top plus the heavier part, weighing each column by its count of entries in `L`), and
//! [`best_split`] the better of AMD's split and that of AMD's order cut in two by a separator
//! of the graph (module `bisect`);
//! [`SplitLower`] holds a lower factor in the three parts, by rows ([`Triangle`], below
//! 10,000 unknowns) or in dense supernodes ([`Supernodal`]).

use std::collections::BTreeSet;

use super::team::Team;
use super::{Pattern, Supernodal, Triangle};

/// Most subtrees expanded into the top while looking for the best split.
const MAX_EXPANSIONS: usize = 4096;

/// A split is kept when its critical path (top plus the heavier part) is at most this
/// fraction of the whole factor's work; otherwise two threads would gain too little.
const MAX_CRITICAL_FRACTION: f64 = 0.8;

const NONE: usize = usize::MAX;

/// An ordering numbered `[part 0 | part 1 | top]`: part 0 the positions `0..a`, part 1
/// `a..b` and the top `b..n`.
#[derive(Debug, Clone)]
pub(super) struct Split {
    /// `fwd[p]` is the original index at position `p`; `inv` its inverse.
    pub fwd: Vec<usize>,
    pub inv: Vec<usize>,
    pub a: usize,
    pub b: usize,
    /// Entries of `L` on the critical path: the top's and the heavier part's.
    pub critical: u64,
    /// Entries of `L`.
    pub entries: u64,
}

/// The better of two splits of the ordering `fwd` (`inv` its inverse): [`two_subtrees`] of
/// `fwd` itself, and of its bisection by a separator of the graph
/// ([`super::bisect::bisected`], the same relative order on each side), taken when it
/// shortens the critical path ([`Split::critical`]) by more than it adds to the fill.
///
/// On a 2D mesh AMD leaves at the top of its elimination tree a chain about twice a
/// separator. On the 48-ring disk (14,114 unknowns) that is a top of 456 unknowns and a
/// critical path of 444,419 entries of `L` (fill 791,987), against 250 and 420,574 (fill
/// 805,173) for the bisection, which is taken. At 192 rings the bisection shortens the
/// critical path by 20,000 entries and adds 400,000 to the fill; on the graded disks, an
/// annulus, the level separator is long (`wheel.toml`: critical path 77,179 against
/// 56,678). There AMD's split stays. `None` when neither splits.
pub(super) fn best_split(pattern: &Pattern, fwd: &[usize], inv: &[usize]) -> Option<Split> {
    let own = two_subtrees(pattern, fwd, inv);
    let bisected = super::bisect::bisected(pattern, inv)
        .and_then(|(f, _, _)| two_subtrees(pattern, &f, &inverse(&f)));
    match (own, bisected) {
        // Each entry the bisection adds is read too, by threads that share the memory's
        // bandwidth: it must shorten the critical path by more than it adds.
        (Some(o), Some(b)) => Some(
            if b.critical + b.entries.saturating_sub(o.entries) < o.critical {
                b
            } else {
                o
            },
        ),
        (o, b) => o.or(b),
    }
}

/// The inverse of the permutation `fwd`: `inv[fwd[p]] = p`.
fn inverse(fwd: &[usize]) -> Vec<usize> {
    let mut inv = vec![0usize; fwd.len()];
    for (p, &i) in fwd.iter().enumerate() {
        inv[i] = p;
    }
    inv
}

/// The ordering `fwd` (`fwd[p]` is the original index of position `p`; `inv` its inverse)
/// renumbered as `[part 0 | part 1 | top]` ([`Split`]), or `None` when no split pays off.
pub(super) fn two_subtrees(pattern: &Pattern, fwd: &[usize], inv: &[usize]) -> Option<Split> {
    let n = fwd.len();
    if n < 4 {
        return None;
    }
    let tree = Tree::of(pattern, inv);
    let (frontier, top, zero, best_cost) = tree.best_split()?;
    if best_cost as f64 > MAX_CRITICAL_FRACTION * tree.total as f64 {
        return None;
    }
    // Label every position: the top 2, a subtree its bin, the rest as its parent (parents
    // come after their children, so a backward pass labels the subtrees whole).
    let mut label = vec![NONE; n];
    for &t in &top {
        label[t] = 2;
    }
    for &(_, r) in &frontier {
        label[r] = 1;
    }
    for &r in &zero {
        label[r] = 0;
    }
    for j in (0..n).rev() {
        if label[j] == NONE {
            label[j] = label[tree.parent[j]];
        }
    }
    let mut new_fwd = Vec::with_capacity(n);
    let mut sizes = [0usize; 3];
    for part in 0..3 {
        for p in 0..n {
            if label[p] == part {
                new_fwd.push(fwd[p]);
                sizes[part] += 1;
            }
        }
    }
    Some(Split {
        inv: inverse(&new_fwd),
        fwd: new_fwd,
        a: sizes[0],
        b: sizes[0] + sizes[1],
        critical: best_cost,
        entries: tree.total,
    })
}

/// Entries of the Cholesky factor `L` (the diagonal included) of `pattern` in the ordering
/// whose inverse permutation is `inv`, from the elimination tree's row subtrees (no factor
/// is formed: `O(n)` memory beyond the pattern's graph).
pub(super) fn factor_entries(pattern: &Pattern, inv: &[usize]) -> u64 {
    Tree::of(pattern, inv).total
}

/// A frontier of subtrees, heaviest first, then by position.
type Frontier = BTreeSet<(std::cmp::Reverse<u64>, usize)>;

/// The elimination tree of `A + A^T` in an ordering, with its columns' entry counts and
/// subtree weights.
struct Tree {
    /// Parent of each position (`NONE` for a root).
    parent: Vec<usize>,
    /// Entries of each column of `L`, the diagonal included.
    count: Vec<u64>,
    /// Entries of each subtree.
    weight: Vec<u64>,
    /// Children of position `k`: `children[children_ptr[k]..children_ptr[k + 1]]`.
    children_ptr: Vec<usize>,
    children: Vec<usize>,
    /// Entries of `L`.
    total: u64,
}

impl Tree {
    /// The tree of `pattern` in the ordering whose inverse permutation is `inv`.
    fn of(pattern: &Pattern, inv: &[usize]) -> Self {
        let n = inv.len();
        let (deg, adj) = lower_graph(pattern, inv);
        let lower = |k: usize| &adj[deg[k]..deg[k + 1]];
        // Elimination tree (Liu's algorithm, with path compression).
        let mut parent = vec![NONE; n];
        let mut ancestor = vec![NONE; n];
        for k in 0..n {
            for &i in lower(k) {
                let mut r = i;
                while ancestor[r] != NONE && ancestor[r] != k {
                    let up = ancestor[r];
                    ancestor[r] = k;
                    r = up;
                }
                if ancestor[r] == NONE {
                    ancestor[r] = k;
                    parent[r] = k;
                }
            }
        }
        // Entries of each column of L (its row subtrees), the diagonal included.
        let mut count = vec![1u64; n];
        let mut mark = vec![NONE; n];
        for k in 0..n {
            mark[k] = k;
            for &i in lower(k) {
                let mut j = i;
                while mark[j] != k {
                    count[j] += 1;
                    mark[j] = k;
                    j = parent[j];
                }
            }
        }
        // Subtree weights (children come before their parents).
        let mut weight: Vec<u64> = count.clone();
        for j in 0..n {
            if parent[j] != NONE {
                weight[parent[j]] += weight[j];
            }
        }
        let total: u64 = (0..n)
            .filter(|&j| parent[j] == NONE)
            .map(|j| weight[j])
            .sum();
        let mut children_ptr = vec![0usize; n + 1];
        for j in 0..n {
            if parent[j] != NONE {
                children_ptr[parent[j] + 1] += 1;
            }
        }
        for k in 0..n {
            children_ptr[k + 1] += children_ptr[k];
        }
        let mut children = vec![0usize; children_ptr[n]];
        let mut fill = children_ptr[..n].to_vec();
        for j in 0..n {
            if parent[j] != NONE {
                children[fill[parent[j]]] = j;
                fill[parent[j]] += 1;
            }
        }
        Tree {
            parent,
            count,
            weight,
            children_ptr,
            children,
            total,
        }
    }

    fn key(&self, r: usize) -> (std::cmp::Reverse<u64>, usize) {
        (std::cmp::Reverse(self.weight[r]), r)
    }

    /// The frontier's two bins (heaviest first into the lighter): their weights and the
    /// subtrees of bin 0.
    fn bins(frontier: &Frontier) -> (u64, u64, Vec<usize>) {
        let (mut w0, mut w1) = (0, 0);
        let mut zero = Vec::new();
        for &(std::cmp::Reverse(w), r) in frontier {
            if w0 <= w1 {
                w0 += w;
                zero.push(r);
            } else {
                w1 += w;
            }
        }
        (w0, w1, zero)
    }

    /// Moves the frontier's heaviest subtree into the top (a chain of single children at
    /// once).
    fn expand(&self, frontier: &mut Frontier, top: &mut Vec<usize>, top_w: &mut u64) {
        let (_, mut r) = frontier.pop_first().expect("a non-empty frontier");
        loop {
            top.push(r);
            *top_w += self.count[r];
            let kids = &self.children[self.children_ptr[r]..self.children_ptr[r + 1]];
            if kids.len() == 1 {
                r = kids[0];
            } else {
                frontier.extend(kids.iter().map(|&k| self.key(k)));
                break;
            }
        }
    }

    /// Expands the heaviest subtree of the frontier into the top, one at a time, and keeps
    /// the expansion whose two-bin split has the least critical path: its frontier, top,
    /// bin 0 and critical path. The frontier is kept sorted (heaviest first, then by
    /// position): each expansion takes its first and each split is one pass, where sorting
    /// it anew at every expansion took seconds on a 14,000-dof wheel.
    fn best_split(&self) -> Option<(Frontier, Vec<usize>, Vec<usize>, u64)> {
        let n = self.parent.len();
        let start: Frontier = (0..n)
            .filter(|&j| self.parent[j] == NONE)
            .map(|r| self.key(r))
            .collect();
        let (mut frontier, mut top, mut top_w) = (start.clone(), Vec::new(), 0);
        let (mut best, mut best_cost) = (None, u64::MAX);
        for step in 0..=MAX_EXPANSIONS {
            if frontier.is_empty() {
                break;
            }
            let (w0, w1, _) = Self::bins(&frontier);
            let cost = top_w + w0.max(w1);
            if w0 > 0 && w1 > 0 && cost < best_cost {
                best = Some(step);
                best_cost = cost;
            }
            self.expand(&mut frontier, &mut top, &mut top_w);
        }
        let best = best?;
        let (mut frontier, mut top, mut top_w) = (start, Vec::new(), 0);
        for _ in 0..best {
            self.expand(&mut frontier, &mut top, &mut top_w);
        }
        let (_, _, zero) = Self::bins(&frontier);
        Some((frontier, top, zero, best_cost))
    }
}

/// The graph of `A + A^T` in the ordering `inv`: for each position `k`, the positions
/// `i < k` it touches, `adj[deg[k]..deg[k + 1]]`.
fn lower_graph(pattern: &Pattern, inv: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = inv.len();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut deg = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &ri[cp[j]..cp[j + 1]] {
            let (pi, pj) = (inv[i], inv[j]);
            if pi != pj {
                deg[pi.max(pj) + 1] += 1;
            }
        }
    }
    for k in 0..n {
        deg[k + 1] += deg[k];
    }
    let mut adj = vec![0usize; deg[n]];
    let mut next = deg[..n].to_vec();
    for j in 0..n {
        for &i in &ri[cp[j]..cp[j + 1]] {
            let (pi, pj) = (inv[i], inv[j]);
            if pi != pj {
                let (lo, hi) = (pi.min(pj), pi.max(pj));
                adj[next[hi]] = lo;
                next[hi] += 1;
            }
        }
    }
    (deg, adj)
}

/// The order from which [`SplitLower::backward_scatter`] reads each part's solution out in
/// the thread that solved it: below, the two threads' writes share too many cache lines of
/// the solution (`scenarios/wheel.toml`, 3,430 unknowns: 59-63 -> 60-65 us a free step,
/// `softway matrix`, alternated binaries) and one thread reads it all out after the parts.
const SCATTER_IN_PARTS_MIN_ORDER: usize = 10_000;

/// Unused entries after each part's local vector in the spread vector
/// ([`SplitLower::spread_len`]): one cache line, so that the two threads never write to the same
/// line.
const GAP: usize = 8;

/// How the parts of a [`SplitLower`] are stored and solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Layout {
    /// Dense supernodes ([`Supernodal`]): both sweeps from one copy.
    Dense,
    /// By rows ([`Triangle`]): the rows of `Λ` for the forward sweep when `forward`, those
    /// of `Λ^T` for the backward sweep when `backward` (a copy each).
    Rows { forward: bool, backward: bool },
}

/// One part of a [`SplitLower`]. Parts 0 and 1 are solved on a local vector `[own | top]`
/// as the lower triangle `Λp = [[Λ_pp, 0], [Λ_tp, I]]`: forward from `[b_p; 0]` it leaves
/// `[Λ_pp^{-1} b_p; -Λ_tp Λ_pp^{-1} b_p]` (the part's contribution to the top), backward
/// from `[b_p; x_t]` it leaves `[Λ_pp^{-T} (b_p - Λ_tp^T x_t); x_t]`.
// Three per split factor: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum Part {
    Dense(Supernodal),
    /// The triangles of the forward and backward sweeps (an empty one where the layout did
    /// not ask for that sweep).
    Rows {
        fwd: Triangle,
        bwd: Triangle,
    },
}

impl Part {
    /// The part of columns `c0..c1` of `Λ` (CSC), its rows numbered locally (its own from
    /// 0, the top's `b..n` after), or `None` when a column has a row outside the part and
    /// the top. Dense parts leave the top's identity columns implicit; by rows they are
    /// stored (unit entries), so that the triangle's order is the local vector's.
    #[allow(clippy::too_many_arguments)]
    fn new(
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &[f64],
        unit: bool,
        (c0, c1): (usize, usize),
        (b, n): (usize, usize),
        layout: Layout,
    ) -> Option<(Self, usize)> {
        let mut cp = vec![0usize];
        let (mut rows, mut vals) = (Vec::new(), Vec::new());
        for j in c0..c1 {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let i = row_idx[p];
                let local = if (c0..c1).contains(&i) {
                    i - c0
                } else if i >= b {
                    (c1 - c0) + (i - b)
                } else {
                    return None;
                };
                rows.push(local);
                vals.push(values[p]);
            }
            cp.push(rows.len());
        }
        let mut nnz = rows.len();
        if unit {
            // The unit diagonal counts as stored, whether or not faer stored it.
            nnz += (c0..c1)
                .filter(|&j| !row_idx[col_ptr[j]..col_ptr[j + 1]].contains(&j))
                .count();
        }
        let part = match layout {
            Layout::Dense => Part::Dense(Supernodal::from_lower_csc(&cp, &rows, &vals, unit)),
            Layout::Rows { forward, backward } => {
                if c0 < b || c1 < n {
                    // A part, not the top: the top's identity columns. Two consecutive top
                    // rows on the same columns of the part (most often a node's two dofs)
                    // get an explicit zero coupling, `Λp[t + 1, t] = 0`, which makes them a
                    // pair of the triangle (one gather for both rows, as in the whole
                    // factor) rather than two single rows.
                    let w = c1 - c0;
                    let mut top_cols: Vec<Vec<usize>> = vec![Vec::new(); n - b];
                    for j in 0..w {
                        for &i in &rows[cp[j]..cp[j + 1]] {
                            if i >= w {
                                top_cols[i - w].push(j);
                            }
                        }
                    }
                    let mut t = 0;
                    while t < n - b {
                        let paired = t + 1 < n - b
                            && !top_cols[t].is_empty()
                            && top_cols[t] == top_cols[t + 1];
                        for k in 0..1 + paired as usize {
                            rows.push(w + t + k);
                            vals.push(1.0);
                            if paired && k == 0 {
                                rows.push(w + t + 1);
                                vals.push(0.0);
                            }
                            cp.push(rows.len());
                        }
                        t += 1 + paired as usize;
                    }
                }
                let tri = |wanted: bool, transpose: bool| {
                    if wanted {
                        Triangle::from_csc(&cp, &rows, &vals, unit, transpose, !transpose)
                    } else {
                        Triangle::default()
                    }
                };
                Part::Rows {
                    fwd: tri(forward, false),
                    bwd: tri(backward, true),
                }
            }
        };
        Some((part, nnz))
    }

    /// Bytes a solve reads of the part: a dense part's one copy twice (both sweeps), by rows
    /// the two triangles once each (an empty one where that sweep is not asked for).
    fn solve_bytes(&self) -> usize {
        match self {
            Part::Dense(sn) => 2 * sn.bytes(),
            Part::Rows { fwd, bwd } => fwd.bytes() + bwd.bytes(),
        }
    }

    /// Bytes of the part as stored.
    fn bytes(&self) -> usize {
        match self {
            Part::Dense(sn) => sn.bytes(),
            Part::Rows { fwd, bwd } => fwd.bytes() + bwd.bytes(),
        }
    }

    /// The dense supernodes of a dense part.
    fn dense_mut(&mut self) -> Option<&mut Supernodal> {
        match self {
            Part::Dense(sn) => Some(sn),
            Part::Rows { .. } => None,
        }
    }

    /// The forward sweep on the part's local vector.
    fn forward(&mut self, x: &mut [f64]) {
        match self {
            Part::Dense(sn) => sn.forward(x),
            Part::Rows { fwd, .. } => fwd.solve_in_place(x),
        }
    }

    /// The backward sweep on the part's local vector.
    fn backward(&mut self, x: &mut [f64]) {
        match self {
            Part::Dense(sn) => sn.backward(x),
            Part::Rows { bwd, .. } => bwd.solve_in_place(x),
        }
    }
}

/// A lower triangular factor `Λ` of order `n` in the three parts of [`two_subtrees`]
/// (module docs), in dense supernodes or by rows ([`Layout`]): part 0 (columns `0..a`) and
/// part 1 (`a..b`) on local vectors that hold their own unknowns, then the top's (`b..n`);
/// the top on `x[b..n]`.
#[derive(Debug, Clone)]
pub(super) struct SplitLower {
    a: usize,
    b: usize,
    n: usize,
    part0: Part,
    part1: Part,
    top: Part,
    /// Stored entries of `Λ`, diagonal included.
    nnz: usize,
    /// Where [`SplitLower::backward_scatter`] writes unknown `k`'s solution: a permutation
    /// of `0..n` ([`SplitLower::set_scatter`]; empty until set).
    scatter: Vec<usize>,
}

impl SplitLower {
    /// From the CSC arrays of `Λ` (as [`Supernodal::from_lower_csc`]), or `None` when a
    /// column of one part has a row in the other (a pivot off the diagonal moved it).
    pub(super) fn from_lower_csc(
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &[f64],
        unit: bool,
        (a, b): (usize, usize),
        layout: Layout,
    ) -> Option<Self> {
        let n = col_ptr.len() - 1;
        assert!(a <= b && b <= n);
        let part = |c0, c1| Part::new(col_ptr, row_idx, values, unit, (c0, c1), (b, n), layout);
        let (part0, n0) = part(0, a)?;
        let (part1, n1) = part(a, b)?;
        let (top, nt) = part(b, n)?;
        Some(Self {
            a,
            b,
            n,
            part0,
            part1,
            top,
            nnz: n0 + n1 + nt,
            scatter: Vec::new(),
        })
    }

    /// Stored entries, diagonal included.
    pub(super) fn nnz(&self) -> usize {
        self.nnz
    }

    /// Bytes of the three parts as stored.
    pub(super) fn bytes(&self) -> usize {
        self.part0.bytes() + self.part1.bytes() + self.top.bytes()
    }

    /// Bytes of the three parts that the two sweeps of a solve read together, when this one
    /// factor serves both (Cholesky): dense parts count twice.
    pub(super) fn solve_bytes(&self) -> usize {
        self.part0.solve_bytes() + self.part1.solve_bytes() + self.top.solve_bytes()
    }

    /// The parts stored in dense supernodes.
    pub(super) fn dense_parts_mut(&mut self) -> impl Iterator<Item = &mut Supernodal> {
        [&mut self.part0, &mut self.part1, &mut self.top]
            .into_iter()
            .filter_map(Part::dense_mut)
    }

    /// The parts' orders: `(a, b - a, n - b)`.
    pub(super) fn sizes(&self) -> (usize, usize, usize) {
        (self.a, self.b - self.a, self.n - self.b)
    }

    /// The length of the vector the sweeps work on: `[x0 | s0 | x1 | s1 | xt]`, the two
    /// parts' unknowns each followed by room for their contributions to the top (`n - b`
    /// each), then the top's unknowns. Each part's local vector is then a contiguous slice
    /// of it, solved in place (no copies in and out).
    pub(super) fn spread_len(&self) -> usize {
        self.n + 2 * (self.n - self.b + GAP)
    }

    /// `x[spread(k)] = src[idx[k]]` for every `k`, `spread(k)` the place of unknown `k` in
    /// the spread vector ([`SplitLower::spread_len`]) (the gather of a permuted right-hand side
    /// into the spread vector), then `x <- Λ^{-1} x` on it: each part's range gathered by the
    /// thread that solves it, the top's by the first.
    pub(super) fn gather_forward(
        &mut self,
        team: &Team,
        idx: &[usize],
        src: &[f64],
        x: &mut [f64],
    ) {
        let (a, b, n, t) = (self.a, self.b, self.n, self.n - self.b);
        assert!(x.len() == self.spread_len() && idx.len() == n);
        let (v0, rest) = x.split_at_mut(a + t);
        let (v1, xt) = rest[GAP..].split_at_mut(b - a + t);
        let xt = &mut xt[GAP..];
        let fill = |dst: &mut [f64], range: std::ops::Range<usize>| {
            for (xk, &i) in dst.iter_mut().zip(&idx[range]) {
                *xk = src[i];
            }
        };
        let (p0, p1) = (&mut self.part0, &mut self.part1);
        team.join(
            || {
                fill(&mut v0[..a], 0..a);
                v0[a..].fill(0.0);
                p0.forward(v0);
                fill(xt, b..n);
            },
            || {
                fill(&mut v1[..b - a], a..b);
                v1[b - a..].fill(0.0);
                p1.forward(v1);
            },
        );
        for ((xi, s0), s1) in xt.iter_mut().zip(&v0[a..]).zip(&v1[b - a..]) {
            *xi = (*xi + s0) + s1;
        }
        self.top.forward(xt);
    }

    /// Sets where [`SplitLower::backward_scatter`] writes each unknown's solution:
    /// `dst[to[k]]` for unknown `k`. Panics unless `to` is a permutation of `0..n`.
    pub(super) fn set_scatter(&mut self, to: &[usize]) {
        assert_eq!(to.len(), self.n, "a scatter of the factor's order");
        let mut seen = vec![false; self.n];
        for &i in to {
            assert!(i < self.n && !seen[i], "a scatter that is a permutation");
            seen[i] = true;
        }
        self.scatter = to.to_vec();
    }

    /// `x <- Λ^{-T} x` on the spread vector, then `dst[to[k]] = x[spread(k)]` for every `k`
    /// (the solution read out, `to` of [`SplitLower::set_scatter`]): each part's unknowns by
    /// the thread that solved them, right after, the top's by the first. Before, the first
    /// thread read the whole solution out after both parts, in order of `dst`: on the
    /// 48-ring disk (14,114 unknowns) that took 0.014-0.016 ms of a 0.46 ms step.
    pub(super) fn backward_scatter(&mut self, team: &Team, x: &mut [f64], dst: &mut [f64]) {
        let (a, b, n, t) = (self.a, self.b, self.n, self.n - self.b);
        assert!(x.len() == self.spread_len() && dst.len() == n && self.scatter.len() == n);
        let (v0, rest) = x.split_at_mut(a + t);
        let (v1, xt) = rest[GAP..].split_at_mut(b - a + t);
        let xt = &mut xt[GAP..];
        self.top.backward(xt);
        v0[a..].copy_from_slice(xt);
        v1[b - a..].copy_from_slice(xt);
        let (p0, p1, to) = (&mut self.part0, &mut self.part1, &self.scatter[..]);
        if n < SCATTER_IN_PARTS_MIN_ORDER {
            team.join(|| p0.backward(v0), || p1.backward(v1));
            for (range, x) in [(0..a, &v0[..a]), (a..b, &v1[..b - a]), (b..n, &v0[a..])] {
                for (&i, &xk) in to[range].iter().zip(x) {
                    dst[i] = xk;
                }
            }
            return;
        }
        let out = Disjoint::new(dst);
        // SAFETY: `to` is a permutation (`set_scatter`), its three ranges disjoint.
        team.join(
            || {
                p0.backward(v0);
                unsafe { out.put(&to[..a], &v0[..a]) };
                unsafe { out.put(&to[b..], &v0[a..]) };
            },
            || {
                p1.backward(v1);
                unsafe { out.put(&to[a..b], &v1[..b - a]) };
            },
        );
    }
}

/// A slice that the two closures of a [`Team::join`] write at places of their own: each place
/// written by one of them only, none read by the other.
pub(crate) struct Disjoint<'a> {
    ptr: *mut f64,
    len: usize,
    _slice: std::marker::PhantomData<&'a mut [f64]>,
}

// SAFETY: the writes go through `put`, whose callers promise that no place is
// written by two threads (their contract).
unsafe impl Sync for Disjoint<'_> {}

impl<'a> Disjoint<'a> {
    pub(crate) fn new(slice: &'a mut [f64]) -> Self {
        Self {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _slice: std::marker::PhantomData,
        }
    }

    /// `slice[to[k]] = src[k]` for every `k`.
    ///
    /// # Safety
    /// No other thread writes or reads the places `to` while this one does.
    #[inline(always)]
    pub(crate) unsafe fn put(&self, to: &[usize], src: &[f64]) {
        for (&i, &v) in to.iter().zip(src) {
            assert!(i < self.len);
            // SAFETY: in bounds (checked), and this thread's alone (the contract).
            unsafe { *self.ptr.add(i) = v };
        }
    }
}
