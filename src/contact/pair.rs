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
//! **Segment (mortar-weighted) pairs.** [`Pair::Weighted`] poses the weighted gap of a
//! surface node `j` against an obstacle, `g~_j = sum_k w_jk g_k`, with the weights of the
//! standard mortar (Wohlmuth; Popp et al.) on the linear segments on either side of `j`:
//! `w_jk = int N_j N_k ds / int N_j ds`, that is `2/3` for `j` and `l_k / (3 (l_prev +
//! l_next))` for its neighbours (`1/6, 2/3, 1/6` on a uniform surface). The pair's
//! multiplier is the nodal value of a pressure field `p = sum_j lambda_j N_j` integrated:
//! its force reaches the three nodes in the proportions `w_jk`, and a pressure need not drop
//! to zero at the node where the gap of the next one opens. `c` is `w_jk n` on the three
//! nodes, `o` the obstacle's offset (the weights sum to 1) and `w` the weighted surface
//! velocity.
//!
//! **Tangents.** [`Pair::tangent`] presents a tangential direction as a [`Geometry`] of
//! its own, `dim - 1` of them ([`tangent_basis`]): in the plane `c_t` is the normal turned
//! by +90 degrees, `t = (-n_y, n_x)` ([`super::obstacle::tangent_2d`]); in 3D the two unit
//! tangents `t_1` (the frame's `x` on the tangent plane) and `t_2 = n x t_1`. Each sits on
//! the node's dofs (`-t` on `a`, `+t` on `b` for two nodes), with `offset = 0` and `w` the
//! surface's velocity along it ([`Obstacle::surface_tangential_velocity`]: 0 for fixed
//! planes, the rolling speed for the rotating base; 0 between two nodes). The slip velocity
//! is `c_t . v - w`. A 1D model has no tangent (`None`). The friction treatments use the
//! plane's one tangent in 2D and both in 3D, bounded together by Coulomb's isotropic cone
//! ([`super::rows`]). Between two 3D bodies (a searched pair) the two tangents are the facet
//! search's at the node's target, on the slave node and the facet's corners
//! ([`super::facets`], The rows).
//!
//! **Split pairs (the uncoupled rolling check).** [`Pair::Split`] is a node against an
//! obstacle whose normal row sits on one node and whose tangential row on another: the
//! node's twin in a second copy of the body that carries only the tangential tractions (the
//! wheel's `rolling.coupling = "uncoupled"`, [`crate::bodies::wheel`]). The gap then sees only the
//! response to the normal and body loads, the slip only the response to the tangential
//! tractions: Carter's elastically similar bodies, for which the two problems decouple.
//! The tangent and the surface's tangential velocity are taken at the normal row's node (the
//! contact point), so the slip is `c_t . v_shadow - w_t` with `w_t` the rail's velocity where
//! the node touches it: at zero creepage and no tangential traction, no slip.

use super::interface::Interface;
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
    /// The mortar-weighted gap of a surface node (`nodes[0]`) and its two neighbours on
    /// the surface against an obstacle (module docs, Segment).
    Weighted {
        /// The node and its neighbours.
        nodes: [usize; 3],
        /// Their weights (summing to 1).
        weights: [f64; 3],
        /// The obstacle.
        obstacle: usize,
    },
    /// A node against an obstacle with its normal row on `node` and its tangential row on
    /// `shadow` (module docs, Split).
    Split {
        /// The node of the normal row (gap, normal reaction).
        node: usize,
        /// The node of the tangential row (slip, tangential reaction).
        shadow: usize,
        /// The obstacle.
        obstacle: usize,
    },
    /// A body's contact node against another body's surface, through a contact search:
    /// the row of the segment found under it at the start of each step
    /// ([`super::interface`]).
    Searched {
        /// The node (the model's index).
        node: usize,
        /// The interface (index into the problem's interfaces).
        interface: usize,
        /// The node's index among the interface's slave nodes.
        slot: usize,
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
    pub fn nodes(&self) -> ([usize; 3], usize) {
        match *self {
            Pair::Obstacle { node, .. } | Pair::Searched { node, .. } => ([node, node, node], 1),
            Pair::Split { node, shadow, .. } => ([node, shadow, shadow], 2),
            Pair::Weighted { nodes, .. } => (nodes, 3),
            Pair::Nodes { a, b, .. } => ([a, b, b], 2),
        }
    }

    /// One [`Pair::Searched`] per slave node of `iface` (index `interface` in the
    /// problem), in its order; the slave body's node `i` is the model's `first_node + i`.
    pub fn searched(interface: usize, iface: &Interface, first_node: usize) -> Vec<Pair> {
        iface
            .nodes()
            .iter()
            .enumerate()
            .map(|(slot, &node)| Pair::Searched {
                node: first_node + node,
                interface,
                slot,
            })
            .collect()
    }

    /// Mortar weights of a surface node between neighbours at distances `l_prev` and
    /// `l_next` (module docs, Segment): `[w_node, w_prev, w_next]`.
    pub fn mortar_weights(l_prev: f64, l_next: f64) -> [f64; 3] {
        let s = 3.0 * (l_prev + l_next);
        [2.0 / 3.0, l_prev / s, l_next / s]
    }

    /// The geometry at time `t` (s) in the configuration `u` of a model of dimension `dim`
    /// with reference positions `reference` (flat, `dim` per node).
    pub fn geometry(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        interfaces: &[Interface],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
    ) -> Geometry {
        self.row(obstacles, interfaces, dim, reference, u, t, true)
    }

    /// The gap `c . (X + u) - o` at time `t` in the configuration `u`, m (the row without the
    /// boundary velocity, which a gap does not need).
    pub fn gap(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        interfaces: &[Interface],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
    ) -> f64 {
        self.row(obstacles, interfaces, dim, reference, u, t, false)
            .gap(reference, u)
    }

    /// The geometry, with the boundary velocity `w` when `velocity` (else `w = 0`).
    #[allow(clippy::too_many_arguments)]
    fn row(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        interfaces: &[Interface],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
        velocity: bool,
    ) -> Geometry {
        let mut terms = Terms::default();
        match *self {
            Pair::Searched {
                interface, slot, ..
            } => {
                let r = interfaces[interface].row(slot, t, u, false);
                Geometry {
                    terms: r.terms,
                    offset: r.offset,
                    w: if velocity { r.w } else { 0.0 },
                }
            }
            Pair::Obstacle { node, obstacle } | Pair::Split { node, obstacle, .. } => {
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
            Pair::Weighted {
                nodes,
                weights,
                obstacle,
            } => {
                let obst = &obstacles[obstacle];
                let hs = obst.half_space(t, position(dim, reference, u, nodes[0]));
                let mut w = 0.0;
                for (&node, &wk) in nodes.iter().zip(&weights) {
                    for c in 0..dim {
                        terms.push(dim * node + c, wk * hs.normal[c]);
                    }
                    if velocity {
                        w +=
                            wk * obst.surface_normal_velocity(t, position(dim, reference, u, node));
                    }
                }
                Geometry {
                    terms,
                    offset: hs.offset,
                    w,
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

    /// The tangential row along the pair's tangent `k` at time `t` in the configuration `u`
    /// (module docs, Tangent): `c_t` the tangent `t_k` of [`tangent_basis`] on the pair's
    /// dofs, `offset = 0`, `w` the surface's velocity along `t_k`. A model of dimension
    /// `dim` has `dim - 1` tangents: `None` for `k >= dim - 1` (and for every `k` in 1D).
    #[allow(clippy::too_many_arguments)]
    pub fn tangent(
        &self,
        obstacles: &[Box<dyn Obstacle>],
        interfaces: &[Interface],
        dim: usize,
        reference: &[f64],
        u: &[f64],
        t: f64,
        k: usize,
    ) -> Option<Geometry> {
        if k + 1 >= dim.max(1) {
            return None;
        }
        let mut terms = Terms::default();
        let push = |terms: &mut Terms, node: usize, scale: f64, tg: Vector| {
            for c in 0..dim {
                terms.push(dim * node + c, scale * tg[c]);
            }
        };
        match *self {
            Pair::Searched {
                interface, slot, ..
            } => {
                // The search's tangent `k` (the planar segment search has one; a 3D facet
                // search two).
                let r = match k {
                    0 => interfaces[interface].row(slot, t, u, true),
                    _ => interfaces[interface].tangent(slot, k, t, u)?,
                };
                Some(Geometry {
                    terms: r.terms,
                    offset: r.offset,
                    w: r.w,
                })
            }
            Pair::Obstacle { node, obstacle } | Pair::Split { node, obstacle, .. } => {
                // A split pair's row acts on its shadow; its direction and the surface's
                // velocity are those at the contact point, the node of the normal row.
                let on = match *self {
                    Pair::Split { shadow, .. } => shadow,
                    _ => node,
                };
                let x = position(dim, reference, u, node);
                let obst = &obstacles[obstacle];
                let tg = tangent_basis(dim, obst.half_space(t, x).normal)[k];
                push(&mut terms, on, 1.0, tg);
                Some(Geometry {
                    terms,
                    offset: 0.0,
                    w: surface_velocity_along(obst.as_ref(), dim, t, x, tg),
                })
            }
            Pair::Weighted {
                nodes,
                weights,
                obstacle,
            } => {
                let obst = &obstacles[obstacle];
                let n = obst
                    .half_space(t, position(dim, reference, u, nodes[0]))
                    .normal;
                let tg = tangent_basis(dim, n)[k];
                let mut w = 0.0;
                for (&node, &wk) in nodes.iter().zip(&weights) {
                    push(&mut terms, node, wk, tg);
                    let x = position(dim, reference, u, node);
                    w += wk * surface_velocity_along(obst.as_ref(), dim, t, x, tg);
                }
                Some(Geometry {
                    terms,
                    offset: 0.0,
                    w,
                })
            }
            Pair::Nodes { a, b, normal } => {
                let tg = tangent_basis(dim, normal)[k];
                push(&mut terms, a, -1.0, tg);
                push(&mut terms, b, 1.0, tg);
                Some(Geometry {
                    terms,
                    offset: 0.0,
                    w: 0.0,
                })
            }
        }
    }
}

/// The tangents of a unit normal `n` in dimension `dim` (the first `dim - 1` are used):
/// in the plane the normal turned by +90 degrees, [`tangent_2d`]; in 3D `t_1` the frame's
/// `x` axis projected on the tangent plane (the rolling direction of a wheel on a rail along
/// `x`; the `y` axis where `n` is within 45 degrees of `x`) and `t_2 = n x t_1`, a
/// right-handed orthonormal `(t_1, t_2, n)`.
pub fn tangent_basis(dim: usize, n: Vector) -> [Vector; 2] {
    if dim < 3 {
        return [tangent_2d(n), [0.0; 3]];
    }
    let axis = if n[0].abs() < std::f64::consts::FRAC_1_SQRT_2 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let a_n = super::obstacle::dot(axis, n);
    let mut t1 = [
        axis[0] - a_n * n[0],
        axis[1] - a_n * n[1],
        axis[2] - a_n * n[2],
    ];
    let l = super::obstacle::dot(t1, t1).sqrt();
    t1.iter_mut().for_each(|c| *c /= l);
    let t2 = [
        n[1] * t1[2] - n[2] * t1[1],
        n[2] * t1[0] - n[0] * t1[2],
        n[0] * t1[1] - n[1] * t1[0],
    ];
    [t1, t2]
}

/// The obstacle's surface velocity at `x` along the tangent `tg`: in the plane its own
/// tangential velocity ([`Obstacle::surface_tangential_velocity`], along [`tangent_2d`]);
/// in 3D the part along `tg` of [`Obstacle::surface_velocity`].
fn surface_velocity_along(obst: &dyn Obstacle, dim: usize, t: f64, x: Vector, tg: Vector) -> f64 {
    if dim < 3 {
        obst.surface_tangential_velocity(t, x)
    } else {
        super::obstacle::dot(obst.surface_velocity(t, x), tg)
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
    interfaces: &[Interface],
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
            Pair::Obstacle { node, obstacle } | Pair::Split { node, obstacle, .. } => {
                match scratch[obstacle] {
                    Some(hs) => hs.gap(position(dim, reference, u, node)),
                    None => p.gap(obstacles, interfaces, dim, reference, u, t),
                }
            }
            Pair::Weighted { .. } | Pair::Nodes { .. } | Pair::Searched { .. } => {
                p.gap(obstacles, interfaces, dim, reference, u, t)
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::obstacle::{Flattening, RotatingLine};

    /// The weighted pair's gap, row and velocities are the mortar-weighted sums of its three
    /// nodes' (each computed as a node pair), and uniform weights are 1/6, 2/3, 1/6.
    #[test]
    fn weighted_pair_is_the_weighted_sum_of_its_node_pairs() {
        assert_eq!(
            Pair::mortar_weights(2.0, 2.0),
            [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0]
        );
        let w = Pair::mortar_weights(1.0, 3.0);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let base: Vec<Box<dyn Obstacle>> = vec![Box::new(RotatingLine {
            centre: [0.0; 3],
            radius: 0.1,
            omega: 300.0,
            theta0: 0.2,
            flattening: Flattening {
                depth: 1e-3,
                settle_time: 2e-3,
            },
            creepage: 0.01,
        })];
        let reference = [0.02, -0.098, 0.0, -0.1, 0.04, -0.092];
        let u = [1e-5, 2e-5, -3e-5, 1e-5, 0.0, -2e-5];
        let v = [0.3, -0.1, 0.2, 0.5, -0.4, 0.1];
        let t = 1e-3;
        let pair = Pair::Weighted {
            nodes: [0, 1, 2],
            weights: w,
            obstacle: 0,
        };
        let g = pair.geometry(&base, &[], 2, &reference, &u, t);
        let tg = pair.tangent(&base, &[], 2, &reference, &u, t, 0).unwrap();
        let (mut gap, mut rate, mut w_n, mut slip, mut w_t) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (k, &wk) in w.iter().enumerate() {
            let node = Pair::Obstacle {
                node: k,
                obstacle: 0,
            };
            let gk = node.geometry(&base, &[], 2, &reference, &u, t);
            let tk = node.tangent(&base, &[], 2, &reference, &u, t, 0).unwrap();
            gap += wk * gk.gap(&reference, &u);
            rate += wk * gk.terms.dot(&v);
            w_n += wk * gk.w;
            slip += wk * tk.terms.dot(&v);
            w_t += wk * tk.w;
        }
        let close = |a: f64, b: f64| (a - b).abs() < 1e-14 * (1.0 + b.abs());
        assert!(close(g.gap(&reference, &u), gap));
        assert!(close(g.terms.dot(&v), rate));
        assert!(close(g.w, w_n) && close(tg.terms.dot(&v), slip) && close(tg.w, w_t));
    }

    /// In 3D a pair has two tangents: with the normal they make a right-handed orthonormal
    /// frame whose first tangent is the frame's `x` on the tangent plane; a node's rows sit
    /// on its three dofs, and there is no third tangent. A floor's tangents are `x` and `y`.
    #[test]
    fn a_pair_in_3d_has_two_orthonormal_tangents() {
        use crate::contact::obstacle::{dot, HalfSpace, Plane};
        let l = (0.2_f64 * 0.2 + 0.3 * 0.3 + 0.9 * 0.9).sqrt();
        for n in [
            [0.0, 0.0, 1.0],
            [0.2 / l, -0.3 / l, 0.9 / l],
            [0.9 / l, 0.2 / l, -0.3 / l],
        ] {
            let [t1, t2] = tangent_basis(3, n);
            for (a, b, want) in [
                (t1, t1, 1.0),
                (t2, t2, 1.0),
                (t1, t2, 0.0),
                (t1, n, 0.0),
                (t2, n, 0.0),
            ] {
                assert!((dot(a, b) - want).abs() < 1e-15, "{n:?}");
            }
            let cross = [
                t1[1] * t2[2] - t1[2] * t2[1],
                t1[2] * t2[0] - t1[0] * t2[2],
                t1[0] * t2[1] - t1[1] * t2[0],
            ];
            assert!((dot(cross, n) - 1.0).abs() < 1e-15);
        }
        assert_eq!(
            tangent_basis(3, [0.0, 0.0, 1.0]),
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        );
        let floor: Vec<Box<dyn Obstacle>> = vec![Box::new(Plane {
            half_space: HalfSpace {
                normal: [0.0, 0.0, 1.0],
                offset: 0.0,
            },
        })];
        let pair = Pair::Obstacle {
            node: 1,
            obstacle: 0,
        };
        let reference = [0.0, 0.0, 0.1, 1.0, 2.0, 0.3];
        let u = [0.0; 6];
        let g = pair.geometry(&floor, &[], 3, &reference, &u, 0.0);
        assert!((g.gap(&reference, &u) - 0.3).abs() < 1e-15);
        let rows: Vec<Vec<(usize, f64)>> = (0..3)
            .filter_map(|k| pair.tangent(&floor, &[], 3, &reference, &u, 0.0, k))
            .map(|g| g.terms.iter().filter(|&(_, c)| c != 0.0).collect())
            .collect();
        assert_eq!(rows, vec![vec![(3, 1.0)], vec![(4, 1.0)]]);
        // 1D has none, the plane one.
        assert!(pair
            .tangent(&floor, &[], 1, &reference, &u, 0.0, 0)
            .is_none());
        assert!(pair
            .tangent(&floor, &[], 2, &reference, &u, 0.0, 1)
            .is_none());
    }
}
