//! Independent parts of a factor for threads side by side.
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
//! parts 0 and 1 on two threads.
//!
//! **More parts.** Each part is a forest of subtrees again, and splits the same way: into
//! two sets of its subtrees and a separator of its own (its top). Split to depth `d`, the
//! ordering is a complete binary tree of `2^d` leaves and `2^d - 1` separators ([`Split`]),
//! numbered level by level: `[leaves | the separators above them | ... | the root]`, each
//! level in the tree's order (still every column after its descendants, the fill
//! unchanged). A solve runs each level's parts side by side, the leaves first forward and
//! the root first backward; each part keeps room for the unknowns of all its ancestors, and
//! a separator adds its first child's contributions, then its second's. The depth is fixed
//! by the matrix ([`depth_for`]: its order), never by the threads, so every sum is made in
//! the same order whatever their number and the result does not depend on it (a level of
//! `2^l` parts goes to the team's threads in turn, [`super::team::Team::for_each`], or all on
//! one thread with `Par::Seq`).
//!
//! The solve's vector is spread for this ([`SplitLower::spread_len`]): each part's unknowns
//! and room are one contiguous slice, solved in place.
//!
//! [`two_subtrees`] finds the two parts (the pair of subtree sets with the least critical
//! path, the top plus the heavier part, weighing each column by its count of entries in
//! `L`), [`best_split`] the better of AMD's split and that of AMD's order cut in two by a
//! separator of the graph (module `bisect`), and [`deepen`] splits the parts again;
//! [`SplitLower`] holds a lower factor in the parts, by rows ([`super::Triangle`], below
//! 10,000 unknowns) or in dense supernodes ([`super::Supernodal`]).

use std::collections::BTreeSet;

use super::Pattern;

mod lower;
pub(super) use lower::{Layout, SplitLower};

/// Most subtrees expanded into the top while looking for the best split.
const MAX_EXPANSIONS: usize = 4096;

/// A split is kept when its critical path (top plus the heavier part) is at most this
/// fraction of the whole factor's work; otherwise two threads would gain too little.
const MAX_CRITICAL_FRACTION: f64 = 0.8;

const NONE: usize = usize::MAX;

/// An ordering numbered in the parts of a complete binary tree of depth `d` (module docs):
/// `[part 0 | part 1 | top]` for `d = 1` (part 0 the positions `0..a`, part 1 `a..b`, the
/// top `b..n`), `[leaf 0 | leaf 1 | leaf 2 | leaf 3 | separator 0 | separator 1 | root]`
/// for `d = 2`, leaves `2k` and `2k + 1` the children of separator `k`.
#[derive(Debug, Clone)]
pub(super) struct Split {
    /// `fwd[p]` is the original index at position `p`; `inv` its inverse.
    pub fwd: Vec<usize>,
    pub inv: Vec<usize>,
    /// The parts' boundaries: part `k` holds the positions `bounds[k]..bounds[k + 1]`
    /// (`2^(d + 1)` of them: `[0, a, b, n]` for two parts).
    pub bounds: Vec<usize>,
    /// Entries of `L` on the critical path: each separator's plus the heavier of its two
    /// children's paths, from the root (the top's and the heavier part's for two parts).
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
        bounds: vec![0, sizes[0], sizes[0] + sizes[1], n],
        critical: best_cost,
        entries: tree.total,
    })
}

/// The work of one part of a split factor ([`crate::linalg::SparseLlt::part_work`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PartWork {
    /// Its unknowns (columns).
    pub order: usize,
    /// Its stored entries of the factor (a solve's flops are twice these per sweep).
    pub entries: usize,
    /// Its columns' flops in a factorization: the sum of their squared counts of entries.
    pub factor_flops: f64,
}

/// The order from which [`depth_for`] splits the ordering into four parts (depth 2): each
/// leaf then holds some 10,000 columns, whose solve outweighs the levels' hand-offs.
///
/// Measured on cubes of steel hexahedra (`examples/split_parts.rs`, nested dissection,
/// the same entries of `L` at every depth; this 2-core machine shared with other builds,
/// so differences below ~10% are noise): at 20,577 unknowns (18^3 cells) a solve on one
/// thread takes 21.8-22.3 ms in 2 parts, 23.7-28.1 in 4, 27.7-31.0 in 8; at 46,875 (24^3)
/// 52.5 ms in 2 and 48.9-59.3 in 4; at 107,811 (32^3) 237-239 ms in 2, 227-269 in 4,
/// 229 in 8. The leaves' balance (largest over mean entries of `L`) at 107,811: 1.02,
/// 1.11, 1.16; the solve's ideal speed-up on as many cores as leaves (the entries of `L`
/// over the sum of each level's largest part's) 1.87, 2.89, 3.91.
pub(super) const SPLIT4_MIN_ORDER: usize = 50_000;

/// The order from which [`depth_for`] splits the ordering into eight parts (depth 3): at
/// 107,811 unknowns 8 parts cost a 2-core machine nothing measurable either, but each leaf
/// holds 11,000-13,000 columns there; from this order on, 25,000 or more.
pub(super) const SPLIT8_MIN_ORDER: usize = 200_000;

/// The depth of the tree of parts for a matrix of order `n` (`2^depth` leaves): 0 (whole)
/// below `SPLIT_MIN_ORDER`, 1 (two parts) from it, 2 from [`SPLIT4_MIN_ORDER`], 3 from
/// [`SPLIT8_MIN_ORDER`]. The matrix alone fixes it, never the threads: the result of a
/// solve is the same bits on any number of them.
pub(super) fn depth_for(n: usize) -> usize {
    if n >= SPLIT8_MIN_ORDER {
        3
    } else if n >= SPLIT4_MIN_ORDER {
        2
    } else if n >= super::SPLIT_MIN_ORDER {
        1
    } else {
        0
    }
}

/// The first part of level `level` (0 the root's) in the order of a tree of depth `depth`:
/// the levels are numbered from the leaves up, `2^l` parts at level `l`.
fn level_start(depth: usize, level: usize) -> usize {
    (1 << (depth + 1)) - (1 << (level + 1))
}

/// The shape of a complete binary tree of parts of depth `depth`, its parts in the split's
/// order (the leaves, then each level up to the root).
#[derive(Debug, Clone, Copy)]
struct Shape {
    depth: usize,
}

impl Shape {
    /// The tree of `count` parts; panics unless `count` is `2^(d + 1) - 1` with `d >= 1`.
    fn of(count: usize) -> Self {
        assert!(count >= 3 && (count + 1).is_power_of_two(), "{count} parts");
        Shape {
            depth: (count + 1).trailing_zeros() as usize - 1,
        }
    }

    /// The number of parts.
    fn count(self) -> usize {
        (1 << (self.depth + 1)) - 1
    }

    /// The level of part `k` (0 the root's) and its place in that level.
    fn place(self, k: usize) -> (usize, usize) {
        (0..=self.depth)
            .map(|l| (l, level_start(self.depth, l)))
            .find(|&(l, s)| (s..s + (1 << l)).contains(&k))
            .map(|(l, s)| (l, k - s))
            .expect("a part of the tree")
    }

    /// The parent of part `k`, `None` for the root.
    fn parent(self, k: usize) -> Option<usize> {
        let (l, q) = self.place(k);
        (l > 0).then(|| level_start(self.depth, l - 1) + q / 2)
    }

    /// The two children of part `k`, `None` for a leaf.
    fn children(self, k: usize) -> Option<[usize; 2]> {
        let (l, q) = self.place(k);
        (l < self.depth).then(|| {
            let c = level_start(self.depth, l + 1) + 2 * q;
            [c, c + 1]
        })
    }

    /// The ancestors of part `k`, its parent first.
    fn ancestors(self, k: usize) -> impl Iterator<Item = usize> {
        std::iter::successors(self.parent(k), move |&p| self.parent(p))
    }

    /// Which of the root's two halves part `k` (not the root) is in.
    fn half(self, k: usize) -> usize {
        let (l, q) = self.place(k);
        q >> (l - 1)
    }
}

/// `split` (two parts, [`two_subtrees`] or [`best_split`]) split again to `depth` levels
/// (module docs): each part of a level cut into two sets of its subtrees and a separator,
/// as [`two_subtrees`] cuts the whole. When a part of a level does not split (no pair of
/// non-empty sets, or a critical path above `MAX_CRITICAL_FRACTION` of the part's work)
/// the tree stops at the level above, complete. The fill is the one of `split` (every
/// column still after its descendants).
pub(super) fn deepen(pattern: &Pattern, split: Split, depth: usize) -> Split {
    if depth <= 1 || split.bounds.len() != 4 {
        return split;
    }
    let n = split.fwd.len();
    let tree = Tree::of(pattern, &split.inv);
    let (a, b) = (split.bounds[1], split.bounds[2]);
    // Each position's part as a node of a heap: the root 1, the children of `h` `2h` and
    // `2h + 1`.
    let mut id: Vec<usize> = (0..n)
        .map(|p| match p {
            p if p < a => 2,
            p if p < b => 3,
            _ => 1,
        })
        .collect();
    let mut reached = 1;
    while reached < depth {
        match tree.split_level(&id, reached) {
            Some(next) => (id, reached) = (next, reached + 1),
            None => break,
        }
    }
    if reached == 1 {
        return split;
    }
    let count = (1 << (reached + 1)) - 1;
    let index = |h: usize| {
        let l = (usize::BITS - 1 - h.leading_zeros()) as usize;
        level_start(reached, l) + (h - (1 << l))
    };
    let (mut sizes, mut weight) = (vec![0usize; count], vec![0u64; count + 1]);
    for p in 0..n {
        sizes[index(id[p])] += 1;
        weight[id[p]] += tree.count[p];
    }
    let mut bounds = vec![0usize; count + 1];
    for k in 0..count {
        bounds[k + 1] = bounds[k] + sizes[k];
    }
    let mut next = bounds[..count].to_vec();
    let mut fwd = vec![0usize; n];
    for p in 0..n {
        let k = index(id[p]);
        fwd[next[k]] = split.fwd[p];
        next[k] += 1;
    }
    let mut critical = weight.clone();
    for h in (1..1 << reached).rev() {
        critical[h] = weight[h] + critical[2 * h].max(critical[2 * h + 1]);
    }
    Split {
        inv: inverse(&fwd),
        fwd,
        bounds,
        critical: critical[1],
        entries: split.entries,
    }
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
        self.best_split_from(start)
    }

    /// [`Tree::best_split`] of the forest whose roots are the frontier `start`.
    fn best_split_from(&self, start: Frontier) -> Option<(Frontier, Vec<usize>, Vec<usize>, u64)> {
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

impl Tree {
    /// The heap labels `id` (each position's part: the root 1, the children of `h` `2h` and
    /// `2h + 1`) with every part of level `level` (labels `2^level..2^(level + 1)`) cut by
    /// [`Tree::best_split_from`] into its top (keeping its label) and two sets of subtrees,
    /// or `None` when one of them does not split (module docs of [`deepen`]).
    fn split_level(&self, id: &[usize], level: usize) -> Option<Vec<usize>> {
        let n = id.len();
        let first = 1usize << level;
        let at = |h: usize| (first..2 * first).contains(&h);
        let mut roots: Vec<Vec<usize>> = vec![Vec::new(); first];
        for p in 0..n {
            let h = id[p];
            if at(h) && (self.parent[p] == NONE || id[self.parent[p]] != h) {
                roots[h - first].push(p);
            }
        }
        let mut mark = vec![NONE; n];
        for (q, r) in roots.iter().enumerate() {
            let h = first + q;
            let whole: u64 = r.iter().map(|&p| self.weight[p]).sum();
            let start: Frontier = r.iter().map(|&p| self.key(p)).collect();
            let (frontier, top, zero, cost) = self.best_split_from(start)?;
            if cost as f64 > MAX_CRITICAL_FRACTION * whole as f64 {
                return None;
            }
            for &t in &top {
                mark[t] = h;
            }
            for &(_, r) in &frontier {
                mark[r] = 2 * h + 1;
            }
            for &r in &zero {
                mark[r] = 2 * h;
            }
        }
        // Parents come after their children: a backward pass labels the subtrees whole.
        let mut next = id.to_vec();
        for p in (0..n).rev() {
            if at(id[p]) {
                next[p] = if mark[p] != NONE {
                    mark[p]
                } else {
                    next[self.parent[p]]
                };
            }
        }
        Some(next)
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

#[cfg(test)]
mod tests;
