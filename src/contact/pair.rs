//! Contact pairs of both kinds (rapier's one-body and two-body constraints): a node against
//! a rigid obstacle, and a node against a node of another body.
//!
//! At a time `t` and a configuration, a pair presents a [`Geometry`]: the row `c` on its
//! dofs, the offset `o` and the normal velocity `w` of the admissible boundary, with the gap
//! $$g = c \cdot x - o \ge 0,\qquad x = X + u$$
//! (`X` the reference positions). For a node against an obstacle, `c` is the obstacle's
//! normal `n` on the node's dofs, `o` its offset and `w` its surface normal velocity; for
//! node `a` against node `b` along the fixed unit normal `n` (from `a` to `b`), `c` is `-n` on
//! `a` and `+n` on `b`, `o = 0` and `w = 0`. Every treatment works on `c`, `o`, `w` alone, so
//! the soft way brakes the relative normal velocity of two bodies exactly as it brakes a node
//! against a wall.
//!
//! **Tangent (friction, 2D).** [`Pair::tangent`] presents the tangential direction as a
//! [`Geometry`] of its own: `c_t` is the normal turned by +90 degrees,
//! `t = (-n_y, n_x)` ([`super::obstacle::tangent_2d`]), on the node's dofs (`-t` on `a`, `+t`
//! on `b` for two nodes), with `offset = 0` and `w` the surface's tangential velocity
//! ([`Obstacle::surface_tangential_velocity`]: 0 for fixed planes, the rolling speed for the
//! rotating base; 0 between two nodes). The slip velocity is `c_t . v - w`. A 1D model has
//! no tangent (`None`); a 3D model needs two tangents and a friction cone (future work).

use super::obstacle::{tangent_2d, Obstacle, Vector};
use super::rows::Terms;

/// A contact pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pair {
    /// A node against an obstacle (index into the problem's obstacles).
    Obstacle {
        /// The node.
        node: usize,
        /// The obstacle.
        obstacle: usize,
    },
    /// Node `a` of one body facing node `b` of another along `normal` (unit, from `a` to
    /// `b`).
    Nodes {
        /// The first node.
        a: usize,
        /// The second node.
        b: usize,
        /// The unit normal from `a` to `b`.
        normal: Vector,
    },
}

/// A pair's row, offset and boundary velocity at one instant (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// `c`.
    pub terms: Terms,
    /// `o`, m.
    pub offset: f64,
    /// `w`, m/s.
    pub w: f64,
}

impl Geometry {
    /// `c . (X + u)`, m.
    pub fn position(&self, reference: &[f64], u: &[f64]) -> f64 {
        let mut s = 0.0;
        for (d, c) in self.terms.iter() {
            s += c * (reference[d] + u[d]);
        }
        s
    }

    /// The gap `c . (X + u) - o`, m.
    pub fn gap(&self, reference: &[f64], u: &[f64]) -> f64 {
        self.position(reference, u) - self.offset
    }
}

impl Pair {
    /// The nodes of the pair.
    pub fn nodes(&self) -> ([usize; 2], usize) {
        match *self {
            Pair::Obstacle { node, .. } => ([node, node], 1),
            Pair::Nodes { a, b, .. } => ([a, b], 2),
        }
    }

    /// The geometry at time `t` (s) in the configuration `u` of a model of dimension `dim`
    /// with reference positions `reference` (flat, `dim` per node).
    pub fn geometry(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
    ) -> Geometry {
        self.row(obstacles, dim, reference, u, t, true)
    }

    /// The gap `c . (X + u) - o` at time `t` in the configuration `u`, m (the row without the
    /// boundary velocity, which a gap does not need).
    pub fn gap(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
    ) -> f64 {
        self.row(obstacles, dim, reference, u, t, false)
            .gap(reference, u)
    }

    /// The geometry, with the boundary velocity `w` when `velocity` (else `w = 0`).
    fn row(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
        velocity: bool,
    ) -> Geometry {
        let mut terms = Terms::default();
        match *self {
            Pair::Obstacle { node, obstacle } => {
                let x = position(dim, reference, u, node);
                let obst = &obstacles[obstacle];
                let hs = obst.half_space(t, x);
                for c in 0..dim {
                    terms.push(dim * node + c, hs.normal[c]);
                }
                Geometry {
                    terms,
                    offset: hs.offset,
                    w: if velocity {
                        obst.surface_normal_velocity(t, x)
                    } else {
                        0.0
                    },
                }
            }
            Pair::Nodes { a, b, normal } => {
                for c in 0..dim {
                    terms.push(dim * a + c, -normal[c]);
                }
                for c in 0..dim {
                    terms.push(dim * b + c, normal[c]);
                }
                Geometry {
                    terms,
                    offset: 0.0,
                    w: 0.0,
                }
            }
        }
    }

    /// The tangential row at time `t` in the configuration `u` (module docs, Tangent): `c_t`
    /// the normal turned by +90 degrees, `offset = 0`, `w` the surface's tangential velocity.
    /// `None` unless `dim == 2`.
    pub fn tangent(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
    ) -> Option<Geometry> {
        if dim != 2 {
            return None;
        }
        let mut terms = Terms::default();
        match *self {
            Pair::Obstacle { node, obstacle } => {
                let x = position(dim, reference, u, node);
                let obst = &obstacles[obstacle];
                let tg = tangent_2d(obst.half_space(t, x).normal);
                terms.push(2 * node, tg[0]);
                terms.push(2 * node + 1, tg[1]);
                Some(Geometry {
                    terms,
                    offset: 0.0,
                    w: obst.surface_tangential_velocity(t, x),
                })
            }
            Pair::Nodes { a, b, normal } => {
                let tg = tangent_2d(normal);
                terms.push(2 * a, -tg[0]);
                terms.push(2 * a + 1, -tg[1]);
                terms.push(2 * b, tg[0]);
                terms.push(2 * b + 1, tg[1]);
                Some(Geometry {
                    terms,
                    offset: 0.0,
                    w: 0.0,
                })
            }
        }
    }
}

/// The current position `X + u` of `node`, padded to three components.
fn position(dim: usize, reference: &[f64], u: &[f64], node: usize) -> Vector {
    let mut x = [0.0; 3];
    for c in 0..dim {
        x[c] = reference[dim * node + c] + u[dim * node + c];
    }
    x
}

/// The gaps of all `pairs` at time `t` in the configuration `u` into `out` (m), as
/// [`Pair::gap`] gives them one by one, with the half-space of each obstacle that has a
/// uniform one ([`Obstacle::uniform_half_space`]) evaluated once instead of once per pair
/// (`scratch`: one slot per obstacle).
#[allow(clippy::too_many_arguments)]
pub fn gaps_into(
    pairs: &[Pair],
    obstacles: &[Box<dyn Obstacle>],
    dim: usize,
    reference: &[f64],
    u: &[f64],
    t: f64,
    scratch: &mut Vec<Option<super::obstacle::HalfSpace>>,
    out: &mut [f64],
) {
    scratch.clear();
    scratch.extend(obstacles.iter().map(|o| o.uniform_half_space(t)));
    for (p, g) in pairs.iter().zip(out.iter_mut()) {
        *g = match *p {
            Pair::Obstacle { node, obstacle } => match scratch[obstacle] {
                Some(hs) => hs.gap(position(dim, reference, u, node)),
                None => p.gap(obstacles, dim, reference, u, t),
            },
            Pair::Nodes { .. } => p.gap(obstacles, dim, reference, u, t),
        };
    }
}
