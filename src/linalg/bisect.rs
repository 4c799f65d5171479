//! A bisection of the matrix graph by a vertex separator, for the split ordering.
//!
//! The split ordering (module `split`) solves two independent sets of subtrees of the
//! elimination tree side by side and their ancestors, the top, on one thread after them. On
//! AMD's ordering of a 2D mesh the top is the chain of AMD's last eliminations: on the
//! 48-ring disk 456 unknowns, twice a diameter of the disk. [`bisected`] orders the graph as
//! `[A | B | S]` instead, with `S` a separator of the graph found by a level structure (the
//! nodes at one distance from a far node, as in George and Liu's automatic nested
//! dissection) and `A`, `B` in AMD's relative order: the top is then the separator, about one
//! diameter of the disk.

use super::Pattern;

/// The graph of `A + A^T` without its diagonal: the neighbours of `i` are
/// `adj[ptr[i]..ptr[i + 1]]`, sorted and without repeats.
fn graph(pattern: &Pattern) -> (Vec<usize>, Vec<usize>) {
    let n = pattern.ncols();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut lists: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in 0..n {
        for &i in &ri[cp[j]..cp[j + 1]] {
            if i != j {
                lists[i].push(j);
                lists[j].push(i);
            }
        }
    }
    let mut ptr = Vec::with_capacity(n + 1);
    let mut adj = Vec::new();
    ptr.push(0);
    for l in &mut lists {
        l.sort_unstable();
        l.dedup();
        adj.extend_from_slice(l);
        ptr.push(adj.len());
    }
    (ptr, adj)
}

const UNSEEN: usize = usize::MAX;

/// Breadth-first levels from `start`: `level[i]` (`UNSEEN` where not reached) and the count of
/// vertices on each level.
fn levels(ptr: &[usize], adj: &[usize], start: usize, level: &mut [usize]) -> Vec<usize> {
    level.fill(UNSEEN);
    level[start] = 0;
    let mut queue = vec![start];
    let mut counts = vec![1usize];
    let mut head = 0;
    while head < queue.len() {
        let i = queue[head];
        head += 1;
        for &j in &adj[ptr[i]..ptr[i + 1]] {
            if level[j] == UNSEEN {
                level[j] = level[i] + 1;
                if counts.len() <= level[j] {
                    counts.push(0);
                }
                counts[level[j]] += 1;
                queue.push(j);
            }
        }
    }
    counts
}

/// The ordering `[A | B | S]` (`fwd[p]` the original index at position `p`; `A` the
/// positions `0..a`, `B` `a..b`) with `S` a vertex separator of the graph of `pattern` (no
/// edge joins `A` and `B`), each set in the relative order of `inv` (an ordering's inverse:
/// the position of each index), or `None` when the graph has no balanced level separator.
pub(super) fn bisected(pattern: &Pattern, inv: &[usize]) -> Option<(Vec<usize>, usize, usize)> {
    let n = pattern.ncols();
    if n < 4 {
        return None;
    }
    let (ptr, adj) = graph(pattern);
    let degree = |i: usize| ptr[i + 1] - ptr[i];
    // A pseudo-peripheral start: from the vertex of least degree (an isolated one aside),
    // again from the least degree vertex of the last level while the depth grows.
    let first = (0..n)
        .filter(|&i| degree(i) > 0)
        .min_by_key(|&i| (degree(i), i))?;
    let mut level = vec![UNSEEN; n];
    let mut counts = levels(&ptr, &adj, first, &mut level);
    for _ in 0..16 {
        let last = counts.len() - 1;
        let far = (0..n)
            .filter(|&i| level[i] == last)
            .min_by_key(|&i| (degree(i), i))?;
        let mut other = vec![UNSEEN; n];
        let c = levels(&ptr, &adj, far, &mut other);
        if c.len() <= counts.len() {
            break;
        }
        (counts, level) = (c, other);
    }
    // The smallest level whose two sides are balanced within 40/60 of the vertices reached,
    // the best balanced of those.
    let reached: usize = counts.iter().sum();
    let mut below = 0usize;
    let mut best: Option<(usize, (usize, usize))> = None;
    for (m, &s) in counts.iter().enumerate() {
        let above = reached - below - s;
        let (lo, hi) = (below.min(above), below.max(above));
        let key = (s, hi - lo);
        if m > 0 && above > 0 && 10 * lo >= 4 * (lo + hi) && best.is_none_or(|(_, k)| key < k) {
            best = Some((m, key));
        }
        below += s;
    }
    let (m, _) = best?;
    // 0: A, 1: B, 2: S; the vertices not reached join A (another component: no edges).
    let mut side: Vec<u8> = level
        .iter()
        .map(|&l| match l {
            UNSEEN => 0,
            l if l < m => 0,
            l if l > m => 1,
            _ => 2,
        })
        .collect();
    // Thinning: a separator vertex with no neighbour in B moves to A, and one with none in
    // A to B (S stays a separator: the vertex then touches only its new side and S).
    for i in 0..n {
        if side[i] == 2 {
            let nb = &adj[ptr[i]..ptr[i + 1]];
            if !nb.iter().any(|&j| side[j] == 1) {
                side[i] = 0;
            } else if !nb.iter().any(|&j| side[j] == 0) {
                side[i] = 1;
            }
        }
    }
    let mut by_pos: Vec<usize> = (0..n).collect();
    by_pos.sort_unstable_by_key(|&i| inv[i]);
    let mut fwd = Vec::with_capacity(n);
    let mut ends = [0usize; 3];
    for s in 0..3u8 {
        fwd.extend(by_pos.iter().copied().filter(|&i| side[i] == s));
        ends[s as usize] = fwd.len();
    }
    Some((fwd, ends[0], ends[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pattern of an `nx` by `ny` grid of nodes with two unknowns each, joined to their
    /// right, upper and upper-right neighbours (a triangulated rectangle).
    fn grid(nx: usize, ny: usize) -> Pattern {
        let node = |x: usize, y: usize| x + nx * y;
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); 2 * nx * ny];
        for y in 0..ny {
            for x in 0..nx {
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    if x + dx < nx && y + dy < ny {
                        let (a, b) = (node(x, y), node(x + dx, y + dy));
                        for (da, db) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                            cols[2 * b + db].push(2 * a + da);
                            cols[2 * a + da].push(2 * b + db);
                        }
                    }
                }
            }
        }
        let (mut cp, mut ri) = (vec![0usize], Vec::new());
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            ri.extend_from_slice(c);
            cp.push(ri.len());
        }
        let n = cols.len();
        Pattern::new_checked(n, n, cp, None, ri)
    }

    /// On grids of either shape the bisection is a permutation whose two sides no edge joins,
    /// balanced within 40/60, and whose separator is at most a straight cut across the grid's
    /// longer side (two unknowns a node).
    #[test]
    fn a_grid_is_cut_into_two_balanced_sides_by_a_short_separator() {
        for (nx, ny) in [(40, 30), (30, 40), (61, 17)] {
            let pattern = grid(nx, ny);
            let n = pattern.ncols();
            let inv: Vec<usize> = (0..n).collect();
            let (fwd, a, b) = bisected(&pattern, &inv).expect("a separator");
            let mut seen = vec![false; n];
            for &i in &fwd {
                assert!(!seen[i], "{nx}x{ny}: a permutation");
                seen[i] = true;
            }
            let mut side = vec![2u8; n];
            for (p, &i) in fwd.iter().enumerate() {
                side[i] = u8::from(p >= a) + u8::from(p >= b);
            }
            let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
            for j in 0..n {
                for &i in &ri[cp[j]..cp[j + 1]] {
                    assert!(side[i] + side[j] != 1, "{nx}x{ny}: an edge from A to B");
                }
            }
            let (sa, sb, sep) = (a, b - a, n - b);
            assert!(
                10 * sa.min(sb) >= 4 * (sa + sb),
                "{nx}x{ny}: sides {sa} and {sb}"
            );
            assert!(sep <= 2 * nx.max(ny), "{nx}x{ny}: a separator of {sep}");
        }
    }

    /// A graph with an isolated vertex (as a Dirichlet unknown's row and column can be) is
    /// still bisected: the level structure starts elsewhere and the vertex joins a side.
    #[test]
    fn isolated_vertices_do_not_stop_the_bisection() {
        let base = grid(20, 20);
        let m = base.ncols();
        let (mut cp, mut ri) = (base.col_ptr().to_vec(), base.row_idx().to_vec());
        ri.push(m);
        cp.push(ri.len());
        let pattern = Pattern::new_checked(m + 1, m + 1, cp, None, ri);
        let inv: Vec<usize> = (0..=m).collect();
        let (fwd, a, _) = bisected(&pattern, &inv).expect("a separator");
        assert!(fwd[..a].contains(&m));
    }
}
