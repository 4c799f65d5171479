//! A bounding-volume hierarchy of axis-aligned boxes, rebuilt in place once per step.
//!
//! The build splits each node's items at the median of their centres along the longest
//! side of the centres' box (`select_nth_unstable_by`: in place, `O(n)` per level), down to
//! leaves of at most [`LEAF`] items: `O(n log n)` per build, a depth of about `log2(n / LEAF)`,
//! and at most `2 n` nodes, which [`Bvh::with_capacity`] reserves so that a build allocates
//! nothing. Rebuilding rather than refitting keeps the tree tight whatever the bodies do
//! (a refit tree degrades as the surface slides or deforms); at one build per step its cost
//! is that of placing the facets.
//!
//! A query walks the tree depth first on a fixed stack, visiting the nodes whose box is
//! within a distance of the point that the caller may shrink as it finds closer items
//! ([`Bvh::visit`]).

use crate::contact::obstacle::Vector;

/// Most items per leaf.
pub const LEAF: usize = 4;

/// The deepest stack a query needs: a median split of fewer than `2^60` items.
const STACK: usize = 64;

/// A node: its box, and its children (`first`, `first + 1`) or its items
/// (`order[first..first + count]`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    lo: Vector,
    hi: Vector,
    first: usize,
    count: usize,
}

/// The hierarchy over a set of boxes (module docs).
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// The items, ordered so that each leaf holds a contiguous range.
    order: Vec<usize>,
}

impl Bvh {
    /// Room for `n` items (a build of up to `n` items allocates nothing).
    pub fn with_capacity(n: usize) -> Self {
        Self {
            nodes: Vec::with_capacity(2 * n.max(1)),
            order: Vec::with_capacity(n),
        }
    }

    /// Builds the tree over the boxes `boxes[i] = (lo, hi)` (module docs).
    pub fn build(&mut self, boxes: &[(Vector, Vector)]) {
        self.order.clear();
        self.order.extend(0..boxes.len());
        self.nodes.clear();
        if boxes.is_empty() {
            return;
        }
        let centre = |i: usize, d: usize| boxes[i].0[d] + boxes[i].1[d];
        self.nodes.push(Node {
            lo: [0.0; 3],
            hi: [0.0; 3],
            first: 0,
            count: boxes.len(),
        });
        let mut k = 0;
        while k < self.nodes.len() {
            let Node { first, count, .. } = self.nodes[k];
            let items = &mut self.order[first..first + count];
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &i in items.iter() {
                for d in 0..3 {
                    lo[d] = lo[d].min(boxes[i].0[d]);
                    hi[d] = hi[d].max(boxes[i].1[d]);
                    clo[d] = clo[d].min(centre(i, d));
                    chi[d] = chi[d].max(centre(i, d));
                }
            }
            self.nodes[k].lo = lo;
            self.nodes[k].hi = hi;
            if count > LEAF {
                let axis = (0..3)
                    .max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b])))
                    .unwrap_or(0);
                let mid = count / 2;
                items.select_nth_unstable_by(mid, |&a, &b| {
                    centre(a, axis).total_cmp(&centre(b, axis))
                });
                let child = self.nodes.len();
                for (f, c) in [(first, mid), (first + mid, count - mid)] {
                    self.nodes.push(Node {
                        lo,
                        hi,
                        first: f,
                        count: c,
                    });
                }
                // An inner node: its children, and no items of its own.
                self.nodes[k].first = child;
                self.nodes[k].count = 0;
            }
            k += 1;
        }
    }

    /// Calls `visit(item)` for every item of every leaf whose box is within `sqrt(reach2)`
    /// of `x`; `visit` returns the squared distance to search within from then on (it may
    /// shrink as closer items are found).
    pub fn visit(&self, x: Vector, mut reach2: f64, mut visit: impl FnMut(usize) -> f64) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0usize; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top]];
            let mut d2 = 0.0;
            for d in 0..3 {
                let e = (node.lo[d] - x[d]).max(x[d] - node.hi[d]).max(0.0);
                d2 += e * e;
            }
            if d2 > reach2 {
                continue;
            }
            if node.count > 0 {
                for &i in &self.order[node.first..node.first + node.count] {
                    reach2 = visit(i);
                }
            } else {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            }
        }
    }

    /// The addresses of its buffers (for the tests that a build allocates nothing).
    #[cfg(test)]
    pub(crate) fn addresses(&self) -> (*const (), *const ()) {
        (self.nodes.as_ptr().cast(), self.order.as_ptr().cast())
    }
}
