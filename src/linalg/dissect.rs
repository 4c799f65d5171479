//! Nested dissection: a fill-reducing ordering for 3D meshes ([`nested_dissection`]).
//!
//! AMD orders by local degrees; on a 3D mesh its factor grows faster than nested
//! dissection's, which numbers a small vertex separator of the graph last, the two sides it
//! separates before it, each side dissected the same way down to small leaves ordered by AMD
//! (George 1973; George and Liu 1981, ch. 8). On an `m x m x m` grid nested dissection's
//! factor has `O(n^{4/3})` entries and costs `O(n^2)` operations, the least any ordering can
//! reach (Lipton, Rose and Tarjan 1979).
//!
//! The separators come from a multilevel bisection, as in METIS (Karypis and Kumar 1998):
//!
//! 1. the unknowns of one node (identical rows: the same closed adjacency) are one vertex of
//!    a compressed graph, weighted by their count ([`Graph::compressed`]);
//! 2. the graph is coarsened by heavy-edge matchings down to about a hundred vertices;
//! 3. the coarsest graph is cut in two by greedy growing from a few seeds, the least cut kept;
//! 4. the cut is carried back level by level, refined at each by Fiduccia-Mattheyses passes
//!    (moves of boundary vertices by gain under a balance bound, the best state kept);
//! 5. the edge cut becomes a vertex separator: a minimum vertex cover of the cut edges
//!    (a maximum matching of the bipartite graph they form and König's theorem).
//!
//! Everything is deterministic (a fixed-seed generator): the same pattern gives the same
//! ordering, hence the same factor bit for bit.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;

use super::{LinalgError, Pattern};

/// Compressed vertices at most in a leaf of the dissection, ordered by AMD.
const LEAF: usize = 120;

/// Coarsening stops at this many vertices (or when a level shrinks by less than 10 %).
const COARSEST: usize = 100;

/// A side may hold at most this fraction of the vertex weight (plus one vertex).
const BALANCE: f64 = 0.53;

/// Greedy growings tried on the coarsest graph.
const SEEDS: usize = 6;

/// Moves without a better cut after which a refinement pass stops.
const FM_PATIENCE: usize = 64;

/// Refinement passes at most per level.
const FM_PASSES: usize = 6;

/// An undirected graph with vertex and edge weights: the neighbours of `i` are
/// `adj[ptr[i]..ptr[i + 1]]` (sorted, no repeats, no loops), with weights `ewt`.
#[derive(Debug, Clone, Default)]
pub(super) struct Graph {
    pub(super) ptr: Vec<usize>,
    pub(super) adj: Vec<usize>,
    pub(super) ewt: Vec<u64>,
    pub(super) vwt: Vec<u64>,
}

impl Graph {
    /// Vertices.
    pub(super) fn n(&self) -> usize {
        self.vwt.len()
    }

    fn nbrs(&self, i: usize) -> std::ops::Range<usize> {
        self.ptr[i]..self.ptr[i + 1]
    }

    fn total(&self) -> u64 {
        self.vwt.iter().sum()
    }

    /// The graph of `pattern` (`A + A^T` without its diagonal) with the unknowns of equal
    /// columns (with the diagonal: a node's unknowns, on a structurally symmetric pattern)
    /// merged into one vertex, and `members`: the unknowns of each vertex,
    /// `members[mptr[v]..mptr[v + 1]]`.
    pub(super) fn compressed(pattern: &Pattern) -> (Graph, Vec<usize>, Vec<usize>) {
        let n = pattern.ncols();
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        // Column j with its diagonal, in increasing order (faer's columns are sorted).
        let closed = |j: usize| {
            let col = &ri[cp[j]..cp[j + 1]];
            let at = col.partition_point(|&i| i < j);
            let has = col.get(at) == Some(&j);
            col[..at]
                .iter()
                .copied()
                .chain(std::iter::once(j))
                .chain(col[at + usize::from(has)..].iter().copied())
        };
        // Candidates by (length, hash of the column), then compared exactly.
        let keys: Vec<(usize, u64)> = (0..n)
            .map(|j| {
                let (len, h) = closed(j).fold((0usize, 0u64), |(l, h), i| {
                    (
                        l + 1,
                        h.wrapping_add((i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)),
                    )
                });
                (len, h)
            })
            .collect();
        let mut by_key: Vec<usize> = (0..n).collect();
        by_key.sort_unstable_by_key(|&i| (keys[i], i));
        const NONE: usize = usize::MAX;
        let mut rep = vec![NONE; n];
        let mut start = 0;
        while start < n {
            let mut end = start + 1;
            while end < n && keys[by_key[end]] == keys[by_key[start]] {
                end += 1;
            }
            for a in start..end {
                let i = by_key[a];
                if rep[i] != NONE {
                    continue;
                }
                rep[i] = i;
                for &j in &by_key[a + 1..end] {
                    if rep[j] == NONE && closed(i).eq(closed(j)) {
                        rep[j] = i;
                    }
                }
            }
            start = end;
        }
        // Vertices numbered by their first unknown.
        let mut id = vec![NONE; n];
        let mut count = 0;
        for i in 0..n {
            if rep[i] == i {
                id[i] = count;
                count += 1;
            }
        }
        let mut mptr = vec![0usize; count + 1];
        for i in 0..n {
            mptr[id[rep[i]] + 1] += 1;
        }
        for v in 0..count {
            mptr[v + 1] += mptr[v];
        }
        let mut next = mptr.clone();
        let mut members = vec![0usize; n];
        for i in 0..n {
            let v = id[rep[i]];
            members[next[v]] = i;
            next[v] += 1;
        }
        // The compressed edges of each vertex's column both ways (A + A^T), then sorted
        // and without repeats.
        let mut edges: Vec<(usize, usize)> = Vec::new();
        for v in 0..count {
            let j = members[mptr[v]];
            for &i in &ri[cp[j]..cp[j + 1]] {
                let u = id[rep[i]];
                if u != v {
                    edges.push((v, u));
                    edges.push((u, v));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let mut g = Graph {
            ptr: vec![0usize; count + 1],
            adj: edges.iter().map(|&(_, u)| u).collect(),
            ewt: vec![1; edges.len()],
            vwt: (0..count).map(|v| (mptr[v + 1] - mptr[v]) as u64).collect(),
        };
        for &(v, _) in &edges {
            g.ptr[v + 1] += 1;
        }
        for v in 0..count {
            g.ptr[v + 1] += g.ptr[v];
        }
        (g, mptr, members)
    }

    /// The mean number of unknowns a vertex of the compressed graph holds ([`Graph::compressed`]):
    /// about 2 on a 2D mesh of two unknowns a node, 3 in 3D.
    pub(super) fn unknowns_per_vertex(pattern: &Pattern) -> f64 {
        let (g, _, _) = Graph::compressed(pattern);
        pattern.ncols() as f64 / g.n().max(1) as f64
    }

    /// The subgraph on the vertices `ids` (increasing), whose positions in `ids` are
    /// `local[v]` (set by the caller; other vertices of `ids`' part any value), with the
    /// edges between them: those to vertices of the same `label`.
    fn subgraph(&self, ids: &[usize], local: &[usize], label: &[u32]) -> Graph {
        let mut g = Graph {
            ptr: Vec::with_capacity(ids.len() + 1),
            vwt: Vec::with_capacity(ids.len()),
            ..Graph::default()
        };
        g.ptr.push(0);
        for &v in ids {
            for e in self.nbrs(v) {
                let u = self.adj[e];
                if label[u] == label[v] {
                    g.adj.push(local[u]);
                    g.ewt.push(self.ewt[e]);
                }
            }
            g.ptr.push(g.adj.len());
            g.vwt.push(self.vwt[v]);
        }
        g
    }

    /// The subgraphs of the vertices of each label `0..count`, with their vertices' indices
    /// here.
    fn parts(&self, label: &[u32], count: usize) -> Vec<(Graph, Vec<usize>)> {
        let mut ids: Vec<Vec<usize>> = vec![Vec::new(); count];
        let mut local = vec![0usize; self.n()];
        for v in 0..self.n() {
            let l = label[v] as usize;
            if l < count {
                local[v] = ids[l].len();
                ids[l].push(v);
            }
        }
        ids.into_iter()
            .map(|i| (self.subgraph(&i, &local, label), i))
            .collect()
    }

    /// The connected component of each vertex, and their count.
    fn components(&self) -> (Vec<u32>, usize) {
        let n = self.n();
        let mut comp = vec![u32::MAX; n];
        let mut count = 0u32;
        let mut stack = Vec::new();
        for s in 0..n {
            if comp[s] != u32::MAX {
                continue;
            }
            comp[s] = count;
            stack.push(s);
            while let Some(v) = stack.pop() {
                for e in self.nbrs(v) {
                    let u = self.adj[e];
                    if comp[u] == u32::MAX {
                        comp[u] = count;
                        stack.push(u);
                    }
                }
            }
            count += 1;
        }
        (comp, count as usize)
    }
}

/// A small deterministic generator (xorshift64*).
pub(super) struct Rng(pub(super) u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn shuffled(&mut self, n: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            p.swap(i, self.below(i + 1));
        }
        p
    }
}

/// The nested dissection ordering of `pattern` (structurally symmetric, or read as
/// `A + A^T`): `(fwd, inv)`, `fwd[p]` the unknown at position `p` (module docs).
///
/// # Errors
/// [`LinalgError::Symbolic`] when AMD fails on a leaf.
pub(super) fn nested_dissection(
    pattern: &Pattern,
) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    let (g, mptr, members) = Graph::compressed(pattern);
    let mut order = Vec::with_capacity(g.n());
    let ids: Vec<usize> = (0..g.n()).collect();
    let mut rng = Rng(0x0005_EED0_FD15_5EC7);
    dissect(&g, &ids, &mut order, &mut rng)?;
    let n = pattern.ncols();
    let mut fwd = Vec::with_capacity(n);
    for &v in &order {
        fwd.extend_from_slice(&members[mptr[v]..mptr[v + 1]]);
    }
    let mut inv = vec![0usize; n];
    for (p, &i) in fwd.iter().enumerate() {
        inv[i] = p;
    }
    Ok((fwd, inv))
}

/// Appends to `order` the vertices of `g` (named `ids[v]` outside) in nested dissection
/// order.
fn dissect(
    g: &Graph,
    ids: &[usize],
    order: &mut Vec<usize>,
    rng: &mut Rng,
) -> Result<(), LinalgError> {
    if g.n() <= LEAF {
        return leaf(g, ids, order);
    }
    let (comp, count) = g.components();
    if count > 1 {
        for (sub, local) in g.parts(&comp, count) {
            let sub_ids: Vec<usize> = local.iter().map(|&v| ids[v]).collect();
            dissect(&sub, &sub_ids, order, rng)?;
        }
        return Ok(());
    }
    let side = separator(g, rng);
    let sizes = [0u8, 1].map(|s| side.iter().filter(|&&x| x == s).count());
    if sizes[0] == 0 || sizes[1] == 0 {
        return leaf(g, ids, order);
    }
    let label: Vec<u32> = side.iter().map(|&s| u32::from(s)).collect();
    for (sub, local) in g.parts(&label, 2) {
        let sub_ids: Vec<usize> = local.iter().map(|&v| ids[v]).collect();
        dissect(&sub, &sub_ids, order, rng)?;
    }
    order.extend((0..g.n()).filter(|&v| side[v] == 2).map(|v| ids[v]));
    Ok(())
}

/// Appends the vertices of the leaf `g` in AMD's order.
fn leaf(g: &Graph, ids: &[usize], order: &mut Vec<usize>) -> Result<(), LinalgError> {
    let n = g.n();
    if n <= 2 {
        order.extend_from_slice(ids);
        return Ok(());
    }
    let pattern = Pattern::new_checked(n, n, g.ptr.clone(), None, g.adj.clone());
    let nnz = g.adj.len();
    let (mut fwd, mut inv) = (vec![0usize; n], vec![0usize; n]);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, nnz));
    amd::order(
        &mut fwd,
        &mut inv,
        pattern.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| LinalgError::Symbolic(format!("{e:?}")))?;
    order.extend(fwd.iter().map(|&v| ids[v]));
    Ok(())
}

/// A vertex separator of the connected graph `g`: each vertex labelled 0 or 1 (its side) or 2
/// (the separator), no edge joining 0 and 1.
pub(super) fn separator(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let mut side = bisection(g, rng);
    let cover = cut_cover(g, &side);
    for v in cover {
        side[v] = 2;
    }
    side
}

/// A two-way partition of `g` (labels 0 and 1) with a small weight of cut edges, balanced
/// within [`BALANCE`]: multilevel (module docs, steps 2 to 4).
fn bisection(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let mut levels: Vec<(Graph, Vec<usize>)> = Vec::new();
    loop {
        let fine = levels.last().map_or(g, |(c, _)| c);
        if fine.n() <= COARSEST {
            break;
        }
        let (coarse, cmap) = coarsen(fine, rng);
        if coarse.n() * 10 > fine.n() * 9 {
            break;
        }
        levels.push((coarse, cmap));
    }
    let coarsest = levels.last().map_or(g, |(c, _)| c);
    let mut side = initial(coarsest, rng);
    for k in (0..levels.len()).rev() {
        let fine = if k == 0 { g } else { &levels[k - 1].0 };
        let cmap = &levels[k].1;
        side = cmap.iter().map(|&c| side[c]).collect();
        refine(fine, &mut side);
    }
    side
}

/// A coarser graph by a heavy-edge matching of `g`, and the coarse vertex of each vertex.
fn coarsen(g: &Graph, rng: &mut Rng) -> (Graph, Vec<usize>) {
    let n = g.n();
    const NONE: usize = usize::MAX;
    let max_w = (3 * g.total() / COARSEST as u64).max(1);
    let mut mate = vec![NONE; n];
    for v in rng.shuffled(n) {
        if mate[v] != NONE {
            continue;
        }
        let mut best = (0u64, v);
        for e in g.nbrs(v) {
            let u = g.adj[e];
            if mate[u] == NONE && g.vwt[v] + g.vwt[u] <= max_w && g.ewt[e] > best.0 {
                best = (g.ewt[e], u);
            }
        }
        mate[v] = best.1;
        mate[best.1] = v;
    }
    let mut cmap = vec![NONE; n];
    let mut count = 0;
    for v in 0..n {
        if cmap[v] == NONE {
            cmap[v] = count;
            cmap[mate[v]] = count;
            count += 1;
        }
    }
    let mut c = Graph {
        ptr: Vec::with_capacity(count + 1),
        vwt: vec![0; count],
        ..Graph::default()
    };
    c.ptr.push(0);
    let mut at = vec![NONE; count];
    let mut next = 0;
    for v in 0..n {
        if cmap[v] != next {
            continue;
        }
        let start = c.adj.len();
        let pair = if mate[v] == v { [v, v] } else { [v, mate[v]] };
        for (k, &w) in pair.iter().enumerate() {
            if k == 1 && w == v {
                break;
            }
            c.vwt[next] += g.vwt[w];
            for e in g.nbrs(w) {
                let cu = cmap[g.adj[e]];
                if cu == next {
                    continue;
                }
                if at[cu] == NONE || at[cu] < start {
                    at[cu] = c.adj.len();
                    c.adj.push(cu);
                    c.ewt.push(g.ewt[e]);
                } else {
                    c.ewt[at[cu]] += g.ewt[e];
                }
            }
        }
        c.ptr.push(c.adj.len());
        next += 1;
    }
    (c, cmap)
}

/// The weight of the cut edges of `side`.
fn cut(g: &Graph, side: &[u8]) -> u64 {
    let mut c = 0;
    for v in 0..g.n() {
        for e in g.nbrs(v) {
            if side[g.adj[e]] != side[v] {
                c += g.ewt[e];
            }
        }
    }
    c / 2
}

/// The least cut of [`SEEDS`] greedy growings (breadth first from a random vertex until half
/// the weight), each refined.
fn initial(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let n = g.n();
    let half = g.total() / 2;
    let mut best: Option<(u64, Vec<u8>)> = None;
    for _ in 0..SEEDS {
        let mut side = vec![1u8; n];
        let mut queued = vec![false; n];
        let mut queue = vec![rng.below(n)];
        queued[queue[0]] = true;
        let (mut head, mut w) = (0, 0u64);
        while w < half {
            if head == queue.len() {
                // Another component: start again anywhere not reached.
                match (0..n).find(|&v| !queued[v]) {
                    Some(v) => {
                        queued[v] = true;
                        queue.push(v);
                    }
                    None => break,
                }
            }
            let v = queue[head];
            head += 1;
            side[v] = 0;
            w += g.vwt[v];
            for e in g.nbrs(v) {
                let u = g.adj[e];
                if !queued[u] {
                    queued[u] = true;
                    queue.push(u);
                }
            }
        }
        refine(g, &mut side);
        let c = cut(g, &side);
        if best.as_ref().is_none_or(|(b, _)| c < *b) {
            best = Some((c, side));
        }
    }
    best.map(|(_, s)| s).unwrap_or_default()
}

/// Fiduccia-Mattheyses refinement of the two-way partition `side` of `g`: passes of single
/// moves by largest gain (each vertex once a pass), a side kept within [`BALANCE`] of the
/// weight, each pass rolled back to its best state (least cut, then least imbalance).
fn refine(g: &Graph, side: &mut [u8]) {
    use std::collections::BinaryHeap;
    let n = g.n();
    let total = g.total();
    let max_vwt = g.vwt.iter().copied().max().unwrap_or(0);
    let bound = (BALANCE * total as f64) as u64 + max_vwt;
    let mut w = [0u64; 2];
    for v in 0..n {
        w[side[v] as usize] += g.vwt[v];
    }
    // gain[v] = (edges to the other side) - (edges to its own).
    let mut gain = vec![0i64; n];
    let mut version = vec![0u32; n];
    let mut locked = vec![false; n];
    let mut moves: Vec<usize> = Vec::new();
    for _ in 0..FM_PASSES {
        let mut heap = BinaryHeap::new();
        for v in 0..n {
            let mut gv = 0i64;
            let mut boundary = false;
            for e in g.nbrs(v) {
                let same = side[g.adj[e]] == side[v];
                gv += if same {
                    -(g.ewt[e] as i64)
                } else {
                    g.ewt[e] as i64
                };
                boundary |= !same;
            }
            gain[v] = gv;
            locked[v] = false;
            if boundary {
                heap.push((gv, version[v], v));
            }
        }
        // A state's score: within the bound, then the cut's decrease, then the balance.
        let score = |w: &[u64; 2], cur: i64| {
            (
                w[0].max(w[1]) <= bound,
                cur,
                std::cmp::Reverse(w[0].abs_diff(w[1])),
            )
        };
        let mut cur = 0i64;
        let mut best = score(&w, 0);
        let mut best_at = 0;
        moves.clear();
        while let Some((gv, ver, v)) = heap.pop() {
            if locked[v] || ver != version[v] {
                continue;
            }
            let (from, to) = (side[v] as usize, 1 - side[v] as usize);
            // The heavier side may always give; the lighter only within the bound.
            if w[to] + g.vwt[v] > bound && w[to] + g.vwt[v] > w[from] {
                continue;
            }
            locked[v] = true;
            side[v] = to as u8;
            w[from] -= g.vwt[v];
            w[to] += g.vwt[v];
            cur += gv;
            moves.push(v);
            for e in g.nbrs(v) {
                let u = g.adj[e];
                let d = 2 * g.ewt[e] as i64;
                gain[u] += if side[u] as usize == to { -d } else { d };
                if !locked[u] {
                    version[u] = version[u].wrapping_add(1);
                    heap.push((gain[u], version[u], u));
                }
            }
            let state = score(&w, cur);
            if state > best {
                best = state;
                best_at = moves.len();
            } else if moves.len() - best_at > FM_PATIENCE {
                break;
            }
        }
        for &v in moves[best_at..].iter().rev() {
            let to = 1 - side[v] as usize;
            w[side[v] as usize] -= g.vwt[v];
            w[to] += g.vwt[v];
            side[v] = to as u8;
        }
        if best_at == 0 {
            break;
        }
    }
}

/// A minimum vertex cover of the edges cut by `side` (König: from a maximum matching of the
/// bipartite graph of the cut edges, the side-0 vertices not reached by alternating paths
/// from the unmatched side-0 vertices, and the side-1 vertices reached).
fn cut_cover(g: &Graph, side: &[u8]) -> Vec<usize> {
    const NONE: usize = usize::MAX;
    let n = g.n();
    let crosses = |v: usize| g.nbrs(v).filter(move |&e| side[g.adj[e]] != side[v]);
    let left: Vec<usize> = (0..n)
        .filter(|&v| side[v] == 0 && crosses(v).next().is_some())
        .collect();
    let mut mate = vec![NONE; n];
    // Greedy matching, then augmenting paths (Kuhn), each by an explicit depth-first search.
    for &v in &left {
        if let Some(e) = crosses(v).find(|&e| mate[g.adj[e]] == NONE) {
            mate[v] = g.adj[e];
            mate[g.adj[e]] = v;
        }
    }
    let mut seen = vec![0usize; n];
    let mut stamp = 0;
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let mut path: Vec<usize> = Vec::new();
    for &root in &left {
        if mate[root] != NONE {
            continue;
        }
        stamp += 1;
        stack.clear();
        path.clear();
        stack.push((root, g.ptr[root]));
        let mut found = NONE;
        while let Some(&mut (v, ref mut e)) = stack.last_mut() {
            let end = g.ptr[v + 1];
            while *e < end && (side[g.adj[*e]] == 0 || seen[g.adj[*e]] == stamp) {
                *e += 1;
            }
            if *e == end {
                stack.pop();
                path.pop();
                continue;
            }
            let u = g.adj[*e];
            *e += 1;
            seen[u] = stamp;
            if mate[u] == NONE {
                found = u;
                path.push(u);
                break;
            }
            path.push(u);
            let w = mate[u];
            stack.push((w, g.ptr[w]));
        }
        if found != NONE {
            // stack[k].0 is the left vertex before path[k] (the right vertex taken from it).
            for (k, &(l, _)) in stack.iter().enumerate() {
                let r = path[k];
                mate[l] = r;
                mate[r] = l;
            }
        }
    }
    // Alternating reach from the unmatched left vertices.
    let mut reached = vec![false; n];
    let mut queue: Vec<usize> = left.iter().copied().filter(|&v| mate[v] == NONE).collect();
    for &v in &queue {
        reached[v] = true;
    }
    while let Some(v) = queue.pop() {
        for e in crosses(v) {
            let u = g.adj[e];
            if !reached[u] {
                reached[u] = true;
                let w = mate[u];
                if w != NONE && !reached[w] {
                    reached[w] = true;
                    queue.push(w);
                }
            }
        }
    }
    let mut cover: Vec<usize> = left.iter().copied().filter(|&v| !reached[v]).collect();
    cover.extend((0..n).filter(|&v| side[v] == 1 && reached[v]));
    cover
}

#[cfg(test)]
#[path = "dissect_tests.rs"]
mod tests;
