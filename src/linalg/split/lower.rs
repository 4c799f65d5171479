//! A lower triangular factor stored in the parts of a [`super::Split`] and solved part by
//! part: the leaves of the tree of parts side by side, then each level of separators, each
//! separator after its two children (module docs of [`super`]).

use std::ops::Range;

use super::super::supernodal::{BlockRow, BLOCK_RHS};
use super::super::team::Team;
use super::super::{Supernodal, Triangle};
use super::{level_start, Shape};

/// The order from which [`SplitLower::backward_scatter`] reads each part's solution out in
/// the thread that solved it: below, the two threads' writes share too many cache lines of
/// the solution (`scenarios/wheel.toml`, 3,430 unknowns: 59-63 -> 60-65 us a free step,
/// `softway matrix`, alternated binaries) and one thread reads it all out after the parts.
const SCATTER_IN_PARTS_MIN_ORDER: usize = 10_000;

/// Unused entries after each part's local vector in the spread vector
/// ([`SplitLower::spread_len`]): one cache line, so that two threads never write to the same
/// line.
const GAP: usize = 8;

/// How the parts of a [`SplitLower`] are stored and solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::linalg) enum Layout {
    /// Dense supernodes ([`Supernodal`]): both sweeps from one copy.
    Dense,
    /// By rows ([`Triangle`]): the rows of `Λ` for the forward sweep when `forward`, those
    /// of `Λ^T` for the backward sweep when `backward` (a copy each).
    Rows { forward: bool, backward: bool },
}

/// One part of a [`SplitLower`]. A part below the root is solved on a local vector
/// `[own | room]`, the room holding its ancestors' unknowns (its parent's, its grandparent's,
/// ... in the order of the columns), as the lower triangle `Λp = [[Λ_pp, 0], [Λ_ap, I]]`:
/// forward from `[b_p; 0]` it leaves `[Λ_pp^{-1} b_p; -Λ_ap Λ_pp^{-1} b_p]` (the part's
/// contribution to its ancestors), backward from `[b_p; x_a]` it leaves
/// `[Λ_pp^{-T} (b_p - Λ_ap^T x_a); x_a]`.
// Three or more per split factor: the variants' sizes do not matter.
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
    /// 0, then those of each range of `ancestors` in turn), or `None` when a column has a
    /// row outside the part and its ancestors. Dense parts leave the room's identity columns
    /// implicit; by rows they are stored (unit entries), so that the triangle's order is the
    /// local vector's.
    fn new(
        (col_ptr, row_idx, values): (&[usize], &[usize], &[f64]),
        unit: bool,
        (c0, c1): (usize, usize),
        ancestors: &[Range<usize>],
        layout: Layout,
    ) -> Option<(Self, usize)> {
        let w = c1 - c0;
        let local = |i: usize| {
            if (c0..c1).contains(&i) {
                return Some(i - c0);
            }
            let mut off = w;
            for r in ancestors {
                if r.contains(&i) {
                    return Some(off + (i - r.start));
                }
                off += r.len();
            }
            None
        };
        let mut cp = vec![0usize];
        let (mut rows, mut vals) = (Vec::new(), Vec::new());
        for j in c0..c1 {
            for p in col_ptr[j]..col_ptr[j + 1] {
                rows.push(local(row_idx[p])?);
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
                let room: usize = ancestors.iter().map(Range::len).sum();
                if !ancestors.is_empty() {
                    room_identity(&mut cp, &mut rows, &mut vals, w, room);
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

/// Appends the room's identity columns (rows `w..w + room`) to a part's CSC arrays of `w`
/// columns. Two consecutive room rows on the same columns of the part (most often a node's
/// two dofs) get an explicit zero coupling, `Λp[t + 1, t] = 0`, which makes them a pair of
/// the triangle (one gather for both rows, as in the whole factor) rather than two single
/// rows.
fn room_identity(
    cp: &mut Vec<usize>,
    rows: &mut Vec<usize>,
    vals: &mut Vec<f64>,
    w: usize,
    room: usize,
) {
    let mut room_cols: Vec<Vec<usize>> = vec![Vec::new(); room];
    for j in 0..w {
        for &i in &rows[cp[j]..cp[j + 1]] {
            if i >= w {
                room_cols[i - w].push(j);
            }
        }
    }
    let mut t = 0;
    while t < room {
        let paired = t + 1 < room && !room_cols[t].is_empty() && room_cols[t] == room_cols[t + 1];
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

/// One part of a [`SplitLower`] with where it lives in the spread vector.
#[derive(Debug, Clone)]
struct Node {
    part: Part,
    /// Its columns (unknowns) in the split ordering.
    cols: Range<usize>,
    /// Its local vector `[own | room]` in the spread vector.
    region: Range<usize>,
    /// The rooms of its two children in the spread vector (each as long as `region`), the
    /// first child's first; `None` for a leaf.
    kids: Option<[Range<usize>; 2]>,
    /// Its parent's region (as long as its room); `None` for the root.
    parent: Option<Range<usize>>,
}

impl Node {
    /// Gathers the part's right-hand side (`x[k] = src[idx[k]]` for its columns `k`),
    /// empties its room, adds its children's contributions (the first child's, then the
    /// second's), then the forward sweep.
    ///
    /// # Safety
    /// No other thread touches this node's region, and none writes its children's rooms,
    /// while this runs.
    unsafe fn forward(&mut self, spread: &Spread, idx: &[usize], src: &[f64]) {
        let own = self.cols.len();
        // SAFETY: this node's region is this thread's alone (the contract).
        let v = unsafe { spread.slice_mut(self.region.clone()) };
        for (xk, &i) in v[..own].iter_mut().zip(&idx[self.cols.clone()]) {
            *xk = src[i];
        }
        v[own..].fill(0.0);
        for kid in self.kids.iter().flatten() {
            // SAFETY: the children's rooms are written by no one now (the contract).
            let room = unsafe { spread.slice(kid.clone()) };
            for (xi, s) in v.iter_mut().zip(room) {
                *xi += s;
            }
        }
        self.part.forward(v);
    }

    /// Copies its ancestors' unknowns from its parent's region into its room, the backward
    /// sweep, then (with `out`) `dst[to[k]] = x[k]` for its own unknowns `k`.
    ///
    /// # Safety
    /// No other thread touches this node's region, and none writes its parent's, while this
    /// runs; `to` is a permutation (the places written are this node's alone).
    unsafe fn backward(&mut self, spread: &Spread, out: Option<(&Disjoint, &[usize])>) {
        let own = self.cols.len();
        // SAFETY: this node's region is this thread's alone (the contract).
        let v = unsafe { spread.slice_mut(self.region.clone()) };
        if let Some(p) = &self.parent {
            // SAFETY: the parent's region is written by no one now (the contract).
            v[own..].copy_from_slice(unsafe { spread.slice(p.clone()) });
        }
        self.part.backward(v);
        if let Some((out, to)) = out {
            // SAFETY: this node's places of the permutation `to` are its own.
            unsafe { out.put(&to[self.cols.clone()], &v[..own]) };
        }
    }
}

/// Runs `f` on every node of a level, side by side: one on this thread, two by
/// [`Team::join`], more by [`Team::for_each`].
fn level_side_by_side<F: Fn(&mut Node) + Sync>(team: &Team, nodes: &mut [Node], f: F) {
    match nodes {
        [one] => f(one),
        [a, b] => team.join(|| f(a), || f(b)),
        _ => team.for_each(nodes, f),
    }
}

/// A lower triangular factor `Λ` of order `n` in the parts of a [`super::Split`] (module
/// docs), in dense supernodes or by rows ([`Layout`]): each part on a local vector of its own
/// unknowns and its ancestors' (a slice of the spread vector, [`SplitLower::spread_len`]).
#[derive(Debug, Clone)]
pub(in crate::linalg) struct SplitLower {
    n: usize,
    /// The parts in the split's order: the leaves, then each level of separators up to the
    /// root.
    nodes: Vec<Node>,
    /// The nodes of each level, the leaves' first, the root's last.
    levels: Vec<Range<usize>>,
    /// The parts' boundaries in the split ordering.
    bounds: Vec<usize>,
    /// Stored entries of `Λ`, diagonal included.
    nnz: usize,
    /// Stored entries of each part.
    part_nnz: Vec<usize>,
    /// The flops of each part's columns in a factorization (the sum of their squared
    /// counts of entries).
    part_flops: Vec<f64>,
    /// Where [`SplitLower::backward_scatter`] writes unknown `k`'s solution: a permutation
    /// of `0..n` ([`SplitLower::set_scatter`]; empty until set).
    scatter: Vec<usize>,
    spread_len: usize,
}

impl SplitLower {
    /// From the CSC arrays of `Λ` (as [`Supernodal::from_lower_csc`]) and the parts'
    /// boundaries ([`super::Split::bounds`]), or `None` when a column of one part has a row
    /// outside it and its ancestors (a pivot off the diagonal moved it).
    pub(in crate::linalg) fn from_lower_csc(
        csc: (&[usize], &[usize], &[f64]),
        unit: bool,
        bounds: &[usize],
        layout: Layout,
    ) -> Option<Self> {
        let n = csc.0.len() - 1;
        let shape = Shape::of(bounds.len() - 1);
        assert!(bounds[0] == 0 && bounds[bounds.len() - 1] == n);
        assert!(bounds.windows(2).all(|w| w[0] <= w[1]));
        let cols = |k: usize| bounds[k]..bounds[k + 1];
        // The regions: each node's own unknowns and its ancestors', then a gap.
        let mut regions = Vec::with_capacity(shape.count());
        let mut start = 0;
        for k in 0..shape.count() {
            let len: usize = std::iter::once(k)
                .chain(shape.ancestors(k))
                .map(|a| cols(a).len())
                .sum();
            regions.push(start..start + len);
            start += len + GAP;
        }
        let spread_len = regions[shape.count() - 1].end;
        let (mut nodes, mut part_nnz, mut part_flops) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..shape.count() {
            let ancestors: Vec<Range<usize>> = shape.ancestors(k).map(cols).collect();
            let (part, nnz) = Part::new(csc, unit, (bounds[k], bounds[k + 1]), &ancestors, layout)?;
            let room = |c: usize| regions[c].start + cols(c).len()..regions[c].end;
            nodes.push(Node {
                part,
                cols: cols(k),
                region: regions[k].clone(),
                kids: shape.children(k).map(|[c0, c1]| [room(c0), room(c1)]),
                parent: shape.parent(k).map(|p| regions[p].clone()),
            });
            part_nnz.push(nnz);
            part_flops.push(
                cols(k)
                    .map(|j| ((csc.0[j + 1] - csc.0[j]) as f64).powi(2))
                    .sum(),
            );
        }
        let levels = (0..=shape.depth)
            .rev()
            .map(|l| level_start(shape.depth, l)..level_start(shape.depth, l) + (1 << l))
            .collect();
        Some(Self {
            n,
            nodes,
            levels,
            bounds: bounds.to_vec(),
            nnz: part_nnz.iter().sum(),
            part_nnz,
            part_flops,
            scatter: Vec::new(),
            spread_len,
        })
    }

    /// Stored entries, diagonal included.
    pub(in crate::linalg) fn nnz(&self) -> usize {
        self.nnz
    }

    /// The work of each part, in the split's order.
    pub(in crate::linalg) fn part_work(&self) -> Vec<super::PartWork> {
        self.bounds
            .windows(2)
            .zip(self.part_nnz.iter().zip(&self.part_flops))
            .map(|(w, (&entries, &factor_flops))| super::PartWork {
                order: w[1] - w[0],
                entries,
                factor_flops,
            })
            .collect()
    }

    /// Bytes of the parts as stored.
    pub(in crate::linalg) fn bytes(&self) -> usize {
        self.nodes.iter().map(|n| n.part.bytes()).sum()
    }

    /// Bytes of the parts that the two sweeps of a solve read together, when this one
    /// factor serves both (Cholesky): dense parts count twice.
    pub(in crate::linalg) fn solve_bytes(&self) -> usize {
        self.nodes.iter().map(|n| n.part.solve_bytes()).sum()
    }

    /// The parts stored in dense supernodes.
    pub(in crate::linalg) fn dense_parts_mut(&mut self) -> impl Iterator<Item = &mut Supernodal> {
        self.nodes.iter_mut().filter_map(|n| n.part.dense_mut())
    }

    /// The orders of the root's two halves (each a subtree of parts, its separators
    /// included) and of the root: `(a, b - a, n - b)` for two parts.
    pub(in crate::linalg) fn sizes(&self) -> (usize, usize, usize) {
        let shape = Shape::of(self.nodes.len());
        let mut half = [0usize; 2];
        for k in 0..self.nodes.len() - 1 {
            half[shape.half(k)] += self.nodes[k].cols.len();
        }
        let root = self.nodes[self.nodes.len() - 1].cols.len();
        (half[0], half[1], root)
    }

    /// The orders of the parts in the split's order: the leaves, then each level of
    /// separators up to the root.
    pub(in crate::linalg) fn part_orders(&self) -> Vec<usize> {
        self.bounds.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The length of the vector the sweeps work on: each part's local vector (its unknowns,
    /// then room for its ancestors') and a gap, in the parts' order, the root's last. Each
    /// part's local vector is then a contiguous slice of it, solved in place (no copies in
    /// and out).
    pub(in crate::linalg) fn spread_len(&self) -> usize {
        self.spread_len
    }

    /// `x[spread(k)] = src[idx[k]]` for every `k`, `spread(k)` the place of unknown `k` in
    /// the spread vector ([`SplitLower::spread_len`]) (the gather of a permuted right-hand
    /// side into the spread vector), then `x <- Λ^{-1} x` on it: level by level from the
    /// leaves, the parts of a level side by side, each part's range gathered by the thread
    /// that solves it. Every sum is made in an order fixed by the tree of parts.
    pub(in crate::linalg) fn gather_forward(
        &mut self,
        team: &Team,
        idx: &[usize],
        src: &[f64],
        x: &mut [f64],
    ) {
        assert!(x.len() == self.spread_len && idx.len() == self.n);
        let spread = Spread::new(x);
        for l in 0..self.levels.len() {
            let nodes = &mut self.nodes[self.levels[l].clone()];
            // SAFETY: the nodes of a level have disjoint regions; their children (the level
            // below, done) are not written while this level runs.
            level_side_by_side(team, nodes, |node| unsafe {
                node.forward(&spread, idx, src)
            });
        }
    }

    /// Sets where [`SplitLower::backward_scatter`] writes each unknown's solution:
    /// `dst[to[k]]` for unknown `k`. Panics unless `to` is a permutation of `0..n`.
    pub(in crate::linalg) fn set_scatter(&mut self, to: &[usize]) {
        assert_eq!(to.len(), self.n, "a scatter of the factor's order");
        let mut seen = vec![false; self.n];
        for &i in to {
            assert!(i < self.n && !seen[i], "a scatter that is a permutation");
            seen[i] = true;
        }
        self.scatter = to.to_vec();
    }

    /// `x <- Λ^{-T} x` on the spread vector, level by level from the root, the parts of a
    /// level side by side, then `dst[to[k]] = x[spread(k)]` for every `k` (the solution read
    /// out, `to` of [`SplitLower::set_scatter`]): from `SCATTER_IN_PARTS_MIN_ORDER` unknowns on
    /// each part's unknowns by the thread that solved them, right after; below, by this
    /// thread after all the parts. Before, the first thread read the whole solution out after
    /// both parts, in order of `dst`: on the 48-ring disk (14,114 unknowns) that took
    /// 0.014-0.016 ms of a 0.46 ms step.
    pub(in crate::linalg) fn backward_scatter(
        &mut self,
        team: &Team,
        x: &mut [f64],
        dst: &mut [f64],
    ) {
        let n = self.n;
        assert!(x.len() == self.spread_len && dst.len() == n && self.scatter.len() == n);
        let in_parts = n >= SCATTER_IN_PARTS_MIN_ORDER;
        let to = &self.scatter[..];
        {
            let spread = Spread::new(x);
            let out = Disjoint::new(dst);
            let out = in_parts.then_some((&out, to));
            for l in (0..self.levels.len()).rev() {
                let nodes = &mut self.nodes[self.levels[l].clone()];
                // SAFETY: the nodes of a level have disjoint regions; their parents (the
                // level above, done) are not written while this level runs; `to` is a
                // permutation (`set_scatter`), each node's range of it its own.
                level_side_by_side(team, nodes, |node| unsafe { node.backward(&spread, out) });
            }
        }
        if !in_parts {
            for node in &self.nodes {
                let own = &x[node.region.start..node.region.start + node.cols.len()];
                for (&i, &xk) in to[node.cols.clone()].iter().zip(own) {
                    dst[i] = xk;
                }
            }
        }
    }
}

impl SplitLower {
    /// Whether every part is in dense supernodes, the layout of [`SplitLower::solve_block`].
    pub(in crate::linalg) fn is_dense(&self) -> bool {
        self.nodes.iter().all(|n| matches!(n.part, Part::Dense(_)))
    }

    /// `B <- P^T Λ^{-T} Λ^{-1} P B` for a block of right-hand sides `b` (row `i` of every
    /// column in `b[i]`; `idx` the gather of the forward sweep, the scatter that of
    /// [`SplitLower::set_scatter`]) on the spread block `x` ([`SplitLower::spread_len`] rows):
    /// the parts one after the other on this thread, each read once for the block
    /// ([`Supernodal::forward_block`]). Every part must be dense ([`SplitLower::is_dense`]).
    pub(in crate::linalg) fn solve_block(
        &self,
        idx: &[usize],
        x: &mut [BlockRow],
        b: &mut [BlockRow],
    ) {
        assert!(x.len() == self.spread_len && idx.len() == self.n && b.len() == self.n);
        assert_eq!(self.scatter.len(), self.n, "the scatter is set");
        for level in &self.levels {
            for node in &self.nodes[level.clone()] {
                let Part::Dense(sn) = &node.part else {
                    unreachable!("dense parts only (is_dense)")
                };
                let own = node.cols.len();
                // The children's rooms lie before the node's region (the regions follow the
                // nodes' order, the leaves first).
                let (before, rest) = x.split_at_mut(node.region.start);
                let v = &mut rest[..node.region.len()];
                for (xk, &i) in v[..own].iter_mut().zip(&idx[node.cols.clone()]) {
                    *xk = b[i];
                }
                v[own..].fill([0.0; BLOCK_RHS]);
                for kid in node.kids.iter().flatten() {
                    for (xi, s) in v.iter_mut().zip(&before[kid.clone()]) {
                        for c in 0..BLOCK_RHS {
                            xi[c] += s[c];
                        }
                    }
                }
                sn.forward_block(v);
            }
        }
        for level in self.levels.iter().rev() {
            for node in &self.nodes[level.clone()] {
                let Part::Dense(sn) = &node.part else {
                    unreachable!("dense parts only (is_dense)")
                };
                let own = node.cols.len();
                // The parent's region lies after the node's.
                let (lo, hi) = x.split_at_mut(node.region.end);
                let v = &mut lo[node.region.clone()];
                if let Some(p) = &node.parent {
                    let at = p.start - node.region.end;
                    v[own..].copy_from_slice(&hi[at..at + p.len()]);
                }
                sn.backward_block(v);
                for (&i, xk) in self.scatter[node.cols.clone()].iter().zip(&v[..own]) {
                    b[i] = *xk;
                }
            }
        }
    }
}

/// The spread vector shared by the threads of one level: each writes its node's region
/// and reads regions that no one writes during that level.
struct Spread<'a> {
    ptr: *mut f64,
    len: usize,
    _slice: std::marker::PhantomData<&'a mut [f64]>,
}

// SAFETY: the accesses go through `slice_mut` and `slice`, whose callers promise that no
// place is written by one thread while another reads or writes it (their contract).
unsafe impl Sync for Spread<'_> {}

impl<'a> Spread<'a> {
    fn new(slice: &'a mut [f64]) -> Self {
        Self {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _slice: std::marker::PhantomData,
        }
    }

    /// The places `r`, to write.
    ///
    /// # Safety
    /// No other reference to these places lives while the one returned does.
    #[allow(clippy::mut_from_ref)]
    unsafe fn slice_mut(&self, r: Range<usize>) -> &mut [f64] {
        assert!(r.start <= r.end && r.end <= self.len);
        // SAFETY: in bounds (checked), and this caller's alone (the contract).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(r.start), r.len()) }
    }

    /// The places `r`, to read.
    ///
    /// # Safety
    /// No one writes these places while the reference returned lives.
    unsafe fn slice(&self, r: Range<usize>) -> &[f64] {
        assert!(r.start <= r.end && r.end <= self.len);
        // SAFETY: in bounds (checked), and written by no one (the contract).
        unsafe { std::slice::from_raw_parts(self.ptr.add(r.start), r.len()) }
    }
}

/// A slice that the closures of a [`Team::join`] or [`Team::for_each`] write at places of
/// their own: each place written by one of them only, none read by another.
struct Disjoint<'a> {
    ptr: *mut f64,
    len: usize,
    _slice: std::marker::PhantomData<&'a mut [f64]>,
}

// SAFETY: the writes go through `put`, whose callers promise that no place is
// written by two threads (their contract).
unsafe impl Sync for Disjoint<'_> {}

impl<'a> Disjoint<'a> {
    fn new(slice: &'a mut [f64]) -> Self {
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
    unsafe fn put(&self, to: &[usize], src: &[f64]) {
        for (&i, &v) in to.iter().zip(src) {
            assert!(i < self.len);
            // SAFETY: in bounds (checked), and this thread's alone (the contract).
            unsafe { *self.ptr.add(i) = v };
        }
    }
}
