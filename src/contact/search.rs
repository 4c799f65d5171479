//! Contact search between bodies: a body's contact nodes against another body's surface
//! segments, each body in a frame of its own ([`crate::bodies`]).
//!
//! # Frames
//!
//! A body's dofs are displacements in its own frame. The frame moves rigidly against the
//! ground ([`Motion`]): fixed, translating at a constant velocity `V` (a rail or block that
//! passes under the wheel), or turning about a centre `c` at `omega` (the wheel, seen in the
//! frame that turns with it, as the paper does). A material point with reference position
//! `X` and displacement `u` is in the ground at
//! $$x = c + R(\theta(t))\\,(X + u),\qquad \theta(t) = \theta_0 + \omega t$$
//! (`R` the rotation about z; a translating frame: `x = x_0 + V t + X + u`). Its velocity
//! is `R v` plus the drift of the frame at that point, `omega e_z x R(X + u)` or `V`.
//!
//! # The pair's row
//!
//! A contact node `a` (slave) faces the master segment `s = [p, q]` at the parameter `xi`
//! of its closest point, `x_s = (1 - xi) x_p + xi x_q`, with the segment's outward unit
//! normal `n` (the master body lies on the left of `p -> q`: `n = (dy, -dx) / l`). The gap
//! $$g = n \cdot (x_a - x_s)$$
//! is linear in the displacements once `(s, xi, n)` are frozen, which the search does once
//! per step: it is `g = c \cdot (X + u) - o` with the row `c` equal to `R_a^T n` on `a`'s
//! dofs and `-(1 - xi) R_s^T n`, `-xi R_s^T n` on `p`'s and `q`'s, and the offset `o`
//! holding the frames' origins. The rows impose the relative normal velocity through
//! `c \cdot v = w`: with `(s, xi, n)` frozen,
//! $$\dot g = c \cdot v - w,\qquad w = -n \cdot \big(d_a - (1-\xi) d_p - \xi d_q\big)$$
//! where `d` is a point's frame drift. Against a rigid line turning about the wheel this is
//! the rotating base's normal velocity ([`super::RotatingLine`]); the tests check the two
//! agree. The tangent is the normal turned by +90 degrees ([`super::obstacle::tangent_2d`])
//! with the same construction, so that the slip is `c_t \cdot v - w_t`.
//!
//! # The search
//!
//! Each step the master surface's segments are placed in the ground and binned on a uniform
//! grid of cells of the longest segment's size ([`Search::update`]); a node's closest
//! segment is then found among the cells within the search reach ([`Search::find`]). The
//! bins are sorted arrays reused from step to step: no allocation once they have grown to
//! the surface's size. Pairs come and go as the bodies move: a node is paired with the
//! segment under it, or with none when no segment is within reach.
//!
//! # Beams
//!
//! A rail of [`crate::element::beam::Beam2`] elements along its frame's `x` is a master
//! surface too ([`Search::on_beams`]): its nodes carry the deflection `w` and the rotation
//! `theta`, and between two nodes its top is the element's own deflected line,
//! $$x_s(\xi) = \big(X(\xi),\ Y + N_w(\xi_e) \cdot (w_1, \theta_1, w_2, \theta_2)\big),
//!   \qquad \xi_e = 1 - \xi$$
//! (the segment runs from the element's right node to its left one, so that the rail lies
//! below its top; `N_w` the Hermite cubics, or the Timoshenko element's with its `Phi`). The
//! row then carries `-N_w (R_s^T n)_y` on the element's four dofs, and the abscissa
//! `X(xi)`, which no dof moves, goes into the offset. The binning and the closest point's
//! parameter `xi` are the chords' between the deflected nodes; the point, the gap and the
//! normal are the beam's own line's there (`n` normal to its tangent `(1, w'(X))`), so the
//! normal turns continuously along the rail (an Euler-Bernoulli rail's line is C1; a
//! Timoshenko rail's slope steps at a node by the shear strain's jump, the support's force
//! over `kappa G A`) and a node sliding along it at `V` sees the normal velocity `V w'`
//! through the row's drift term, not the chord's stepwise slope.
//!
//! # Irregularity
//!
//! A rail's top may carry a roughness or corrugation `r(X)` ([`super::profile`],
//! [`Search::with_profile`]): the surface point under a node is `(X, Y + w + r(X))` and the
//! chord's direction `e` becomes `(e_x, e_y + r'(X) e_x)` before the normal is taken. The
//! row's offset holds `n_y r(X)`; the tilted normal puts `V r'(X)` into its drift term `w`.
//!
//! Two dimensions: the segments are a 2D body's boundary edges; [`Search::new`] refuses any
//! other dimension. A 3D body's surface facets are [`super::facets`]'s search, which
//! fills the same [`Target`] (with its second parameter `eta`) and [`SearchedRow`].

use super::obstacle::{dot, tangent_2d, Flattening, Vector};
use super::profile::Profile;
use super::rows::Terms;
use crate::element::beam::shape_functions;

/// The rigid motion of a body's frame against the ground (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// The frame is the ground: `x = X + u`.
    Fixed,
    /// The frame translates: `x = origin + velocity t + X + u`.
    Translating {
        /// Position of the frame's origin at `t = 0`, m.
        origin: Vector,
        /// The frame's velocity, m/s.
        velocity: Vector,
    },
    /// The frame translates and is pressed along `direction` (unit) by a flattening program
    /// (the kinematic load of the paper's wheel, put on the base body):
    /// `x = origin + velocity t + d(t) direction + X + u`. The frame accelerates at
    /// `d''(t) direction` ([`Motion::acceleration`]): the body's equations carry the
    /// inertial load `-M 1 d''(t)` along `direction`.
    Pressed {
        /// Position of the frame's origin at `t = 0`, m.
        origin: Vector,
        /// The frame's velocity, m/s.
        velocity: Vector,
        /// The direction of the pressing, unit.
        direction: Vector,
        /// The program `d(t)`.
        program: Flattening,
    },
    /// The frame turns about z: `x = centre + R(angle0 + omega t) (X + u)`.
    Rotating {
        /// The centre of rotation in the ground, m.
        centre: Vector,
        /// Angular velocity, rad/s (counter-clockwise positive).
        omega: f64,
        /// Angle at `t = 0`, rad.
        angle0: f64,
    },
}

impl Motion {
    fn angle(&self, t: f64) -> Option<(f64, f64)> {
        match *self {
            Motion::Rotating { omega, angle0, .. } => {
                let th = angle0 + omega * t;
                Some((th.cos(), th.sin()))
            }
            _ => None,
        }
    }

    /// `R(t) d`: a direction of the frame in the ground.
    pub fn rotate(&self, t: f64, d: Vector) -> Vector {
        match self.angle(t) {
            Some((c, s)) => [c * d[0] - s * d[1], s * d[0] + c * d[1], d[2]],
            None => d,
        }
    }

    /// `R(t)^T d`: a ground direction in the frame.
    pub fn rotate_back(&self, t: f64, d: Vector) -> Vector {
        match self.angle(t) {
            Some((c, s)) => [c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]],
            None => d,
        }
    }

    /// The ground position at time `t` of the frame's point `local` (`X + u`), m.
    pub fn place(&self, t: f64, local: Vector) -> Vector {
        match *self {
            Motion::Fixed => local,
            Motion::Translating { .. } | Motion::Pressed { .. } => {
                let o = self.origin(t);
                std::array::from_fn(|i| o[i] + local[i])
            }
            Motion::Rotating { centre, .. } => {
                let r = self.rotate(t, local);
                std::array::from_fn(|i| centre[i] + r[i])
            }
        }
    }

    /// The acceleration of a translating frame at time `t`, m/s^2 (zero but for
    /// [`Motion::Pressed`]; a rotating frame's terms are [`crate::frame`]'s).
    pub fn acceleration(&self, t: f64) -> Vector {
        match *self {
            Motion::Pressed {
                direction, program, ..
            } => direction.map(|c| c * program.accel(t)),
            _ => [0.0; 3],
        }
    }

    /// The frame's offset in the ground: `place(t, local) - R(t) local`, m.
    fn origin(&self, t: f64) -> Vector {
        match *self {
            Motion::Fixed => [0.0; 3],
            Motion::Translating { origin, velocity } => {
                std::array::from_fn(|i| origin[i] + velocity[i] * t)
            }
            Motion::Pressed {
                origin,
                velocity,
                direction,
                program,
            } => {
                let d = program.at(t);
                std::array::from_fn(|i| origin[i] + velocity[i] * t + d * direction[i])
            }
            Motion::Rotating { centre, .. } => centre,
        }
    }

    /// The ground velocity at time `t` of the point fixed in the frame at `local`, m/s.
    pub fn drift(&self, t: f64, local: Vector) -> Vector {
        match *self {
            Motion::Fixed => [0.0; 3],
            Motion::Translating { velocity, .. } => velocity,
            Motion::Pressed {
                velocity,
                direction,
                program,
                ..
            } => {
                let r = program.rate(t);
                std::array::from_fn(|i| velocity[i] + r * direction[i])
            }
            Motion::Rotating { omega, .. } => {
                let r = self.rotate(t, local);
                [-omega * r[1], omega * r[0], 0.0]
            }
        }
    }
}

/// A body in the search: its frame and where its nodes' dofs are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// The body's frame.
    pub motion: Motion,
    /// The body's first dof in the model (its node `i` has dofs `first_dof + dim i ..`,
    /// `dim` the surface's dimension).
    pub first_dof: usize,
}

impl Placed {
    /// The frame position `X + u` of node `i` of a body of dimension `dim` (2 or 3) whose
    /// reference positions are `reference` (`dim` per node, the body's own) and
    /// displacements `u` (the model's); the components past `dim` are zero.
    pub(crate) fn local(&self, dim: usize, reference: &[f64], u: &[f64], i: usize) -> Vector {
        let d = self.first_dof + dim * i;
        let mut x = [0.0; 3];
        for (c, xc) in x.iter_mut().enumerate().take(dim) {
            *xc = reference[dim * i + c] + u[d + c];
        }
        x
    }
}

/// Where a contact node meets a master segment, frozen for a step (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// The segment's index in the surface (a 3D facet's, [`super::facets`]).
    pub segment: usize,
    /// The closest point's parameter on the segment, in `[0, 1]` (on a 3D facet its first
    /// parameter, [`super::facets`]).
    pub xi: f64,
    /// The closest point's second parameter on a 3D facet ([`super::facets`]); 0 on a
    /// segment.
    pub eta: f64,
    /// The segment's outward unit normal in the ground.
    pub normal: Vector,
    /// The gap at the search, m (negative: penetration).
    pub gap: f64,
}

/// A row of a searched pair at one instant: `g = c . (X + u) - offset`, `g' = c . v - w`
/// (the default: an empty row).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SearchedRow {
    /// `c` on the model's dofs.
    pub terms: Terms,
    /// `o`, m.
    pub offset: f64,
    /// `w`, m/s.
    pub w: f64,
}

/// Errors of setting up a search.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// Not a 2D model.
    #[error("contact search between bodies needs a 2D model (segments), not {0}D")]
    Dimension(usize),
    /// A segment of zero length or naming a node the body does not have.
    #[error("master segment {segment} is {why}")]
    Segment {
        /// The segment.
        segment: usize,
        /// What is wrong.
        why: &'static str,
    },
    /// The reach is not finite and positive.
    #[error("the search reach must be finite and > 0 m, got {0}")]
    Reach(f64),
}

/// How a master surface's points move with the master body's dofs (module docs, Beams).
#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// Edges of a body of triangles: node `i`'s dofs are its displacements `(u_x, u_y)` in
    /// the frame, linear along a segment.
    Edges,
    /// The top of a rail of [`crate::element::beam::Beam2`] elements along the frame's `x`:
    /// node `i`'s dofs are `(w, theta)`, the deflection along `y` and the rotation; along a
    /// segment the deflection is the element's own (`N_w` of
    /// [`crate::element::beam::shape_functions`] with its `Phi`, one per segment).
    Beams {
        /// `Phi = 12 EI / (kappa G A l^2)` of each segment's element (0: Euler-Bernoulli).
        phi: Vec<f64>,
    },
}

/// The segments of a flat top surface `nodes` of a body below it, with node positions
/// `coords` (flat, `dim` per node, `x` first): the nodes sorted from right to left
/// (decreasing `x`) and joined in that order, so that the body lies on the left of each
/// segment (its outward normal `+y`).
pub fn top_segments(coords: &[f64], dim: usize, nodes: &[usize]) -> Vec<[usize; 2]> {
    let mut top = nodes.to_vec();
    top.sort_by(|&a, &b| coords[dim * b].total_cmp(&coords[dim * a]));
    top.windows(2).map(|w| [w[0], w[1]]).collect()
}

/// A beam element's deflection and slope at its local coordinate `xi_e` (from its left
/// node), `(w, dw/dx)`, from the dofs `(w1, theta1, w2, theta2)` and its `Phi` and length
/// `l` (the shape functions of [`shape_functions`], differentiated).
fn beam_line(phi: f64, l: f64, xi_e: f64, dofs: &[f64; 4]) -> (f64, f64) {
    let (nw, _) = shape_functions(phi, l, xi_e);
    let s = 1.0 / (1.0 + phi);
    let x = xi_e;
    let dn = [
        s * (6.0 * x * x - 6.0 * x - phi),
        s * l * (3.0 * x * x - (4.0 + phi) * x + 1.0 + 0.5 * phi),
        s * (-6.0 * x * x + 6.0 * x + phi),
        s * l * (3.0 * x * x - (2.0 - phi) * x - 0.5 * phi),
    ];
    let w = (0..4).map(|i| nw[i] * dofs[i]).sum();
    let dw = (0..4).map(|i| dn[i] * dofs[i]).sum::<f64>() / l;
    (w, dw)
}

/// The master surface and its bins (module docs).
#[derive(Debug, Clone)]
pub struct Search {
    master: Placed,
    surface: Surface,
    /// The master body's reference positions, two per node.
    reference: Vec<f64>,
    segments: Vec<[usize; 2]>,
    reach: f64,
    cell: f64,
    /// The segments' ends in the ground at the last update.
    ends: Vec<[Vector; 2]>,
    /// On beams: each segment's element dofs `(w, theta)` of its left and right nodes at the
    /// last update.
    beam_dofs: Vec<[f64; 4]>,
    /// `(cell key, segment)` sorted by key.
    bins: Vec<(i64, i64, usize)>,
    /// The surface's irregularity over the master frame's abscissa ([`Search::with_profile`]).
    profile: Option<Profile>,
}

impl Search {
    /// A search against the segments `segments` (pairs of the master body's node indices,
    /// the body on the left of each) of the master body with reference positions
    /// `reference` (two per node) placed by `master`, finding segments within `reach` (m)
    /// of a node.
    ///
    /// # Errors
    /// [`SearchError`] for a model of another dimension than 2, a degenerate segment or a
    /// bad reach.
    pub fn new(
        dim: usize,
        master: Placed,
        reference: Vec<f64>,
        segments: Vec<[usize; 2]>,
        reach: f64,
    ) -> Result<Self, SearchError> {
        if dim != 2 {
            return Err(SearchError::Dimension(dim));
        }
        if !(reach.is_finite() && reach > 0.0) {
            return Err(SearchError::Reach(reach));
        }
        let nodes = reference.len() / 2;
        let mut longest: f64 = 0.0;
        for (k, &[p, q]) in segments.iter().enumerate() {
            if p >= nodes || q >= nodes {
                return Err(SearchError::Segment {
                    segment: k,
                    why: "naming a node the master body does not have",
                });
            }
            let l = (reference[2 * q] - reference[2 * p])
                .hypot(reference[2 * q + 1] - reference[2 * p + 1]);
            if l.is_nan() || l <= 0.0 {
                return Err(SearchError::Segment {
                    segment: k,
                    why: "of zero length",
                });
            }
            longest = longest.max(l);
        }
        let cell = longest.max(reach);
        Ok(Self {
            ends: vec![[[0.0; 3]; 2]; segments.len()],
            beam_dofs: vec![[0.0; 4]; segments.len()],
            bins: Vec::with_capacity(4 * segments.len()),
            master,
            surface: Surface::Edges,
            reference,
            segments,
            reach,
            cell,
            profile: None,
        })
    }

    /// The segments.
    pub fn segments(&self) -> &[[usize; 2]] {
        &self.segments
    }

    /// The same search on a rail of beams (module docs, Beams): the segments are elements
    /// along the frame's `x` with the given `phi` each, run from right to left (the rail
    /// below its top).
    ///
    /// # Errors
    /// [`SearchError::Segment`] when `phi` does not give one value per segment, or a
    /// segment is not along `x` from right to left.
    pub fn on_beams(mut self, phi: Vec<f64>) -> Result<Self, SearchError> {
        if phi.len() != self.segments.len() {
            return Err(SearchError::Segment {
                segment: phi.len().min(self.segments.len()),
                why: "without a beam's Phi (one per segment)",
            });
        }
        for (k, &[p, q]) in self.segments.iter().enumerate() {
            let r = &self.reference;
            if r[2 * q] >= r[2 * p] || r[2 * q + 1] != r[2 * p + 1] {
                return Err(SearchError::Segment {
                    segment: k,
                    why: "not a beam along x run from right to left",
                });
            }
        }
        self.surface = Surface::Beams { phi };
        Ok(self)
    }

    /// The same search with the irregularity `profile` on the rail's top (module docs,
    /// Irregularity): the surface point under a node is raised by `r(X)` and its normal
    /// turned by `r'(X)`, `X` the abscissa in the rail's frame.
    ///
    /// # Errors
    /// [`SearchError::Segment`] when the surface is not a rail of beams ([`Search::on_beams`]
    /// first).
    pub fn with_profile(mut self, profile: Profile) -> Result<Self, SearchError> {
        if !matches!(self.surface, Surface::Beams { .. }) {
            return Err(SearchError::Segment {
                segment: 0,
                why: "not a rail of beams: an irregularity needs Search::on_beams first",
            });
        }
        self.profile = Some(profile);
        Ok(self)
    }

    /// The irregularity on the surface, if any.
    pub fn profile(&self) -> Option<&Profile> {
        self.profile.as_ref()
    }

    /// `(r, r')` of the irregularity at the point `xi` of segment `[p, q]` (zero without one).
    fn irregularity(&self, p: usize, q: usize, xi: f64) -> (f64, f64) {
        match &self.profile {
            None => (0.0, 0.0),
            Some(pr) => pr.at((1.0 - xi) * self.reference[2 * p] + xi * self.reference[2 * q]),
        }
    }

    /// The reach, m.
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// The master body's placement.
    pub fn master(&self) -> Placed {
        self.master
    }

    /// The frame position of master node `i` with the model's displacements `u`: `X + u`
    /// on edges, `(X, Y + w)` on beams.
    fn local(&self, u: &[f64], i: usize) -> Vector {
        match self.surface {
            Surface::Edges => self.master.local(2, &self.reference, u, i),
            Surface::Beams { .. } => {
                let d = self.master.first_dof + 2 * i;
                [self.reference[2 * i], self.reference[2 * i + 1] + u[d], 0.0]
            }
        }
    }

    fn key(&self, x: f64) -> i64 {
        (x / self.cell).floor() as i64
    }

    /// Places the segments in the ground at time `t` with the displacements `u` and bins
    /// them. Allocates nothing once the bins have reached their size.
    pub fn update(&mut self, t: f64, u: &[f64]) {
        self.bins.clear();
        for k in 0..self.segments.len() {
            let [p, q] = self.segments[k];
            let a = self.master.motion.place(t, self.local(u, p));
            let b = self.master.motion.place(t, self.local(u, q));
            self.ends[k] = [a, b];
            if let Surface::Beams { .. } = self.surface {
                let (dq, dp) = (self.master.first_dof + 2 * q, self.master.first_dof + 2 * p);
                self.beam_dofs[k] = [u[dq], u[dq + 1], u[dp], u[dp + 1]];
            }
            let (x0, x1) = (self.key(a[0].min(b[0])), self.key(a[0].max(b[0])));
            let (y0, y1) = (self.key(a[1].min(b[1])), self.key(a[1].max(b[1])));
            for i in x0..=x1 {
                for j in y0..=y1 {
                    self.bins.push((i, j, k));
                }
            }
        }
        self.bins.sort_unstable();
    }

    /// The closest segment to the ground point `x` within the reach, with its parameter,
    /// normal and the gap (module docs); `None` when none is within reach. Among segments
    /// at the same distance (a node over a vertex) the one with the larger gap is taken,
    /// then the lower index.
    pub fn find(&self, x: Vector) -> Option<Target> {
        let (i0, i1) = (self.key(x[0] - self.reach), self.key(x[0] + self.reach));
        let (j0, j1) = (self.key(x[1] - self.reach), self.key(x[1] + self.reach));
        let mut best: Option<(f64, Target)> = None;
        for i in i0..=i1 {
            for j in j0..=j1 {
                let start = self.bins.partition_point(|&(a, b, _)| (a, b) < (i, j));
                for &(_, _, k) in self.bins[start..]
                    .iter()
                    .take_while(|&&(a, b, _)| (a, b) == (i, j))
                {
                    let t = self.project(k, x);
                    let [a, b] = self.ends[k];
                    let c: Vector = std::array::from_fn(|d| (1.0 - t.xi) * a[d] + t.xi * b[d]);
                    let dist = (x[0] - c[0]).hypot(x[1] - c[1]);
                    if dist > self.reach {
                        continue;
                    }
                    let better = match &best {
                        None => true,
                        Some((bd, bt)) => {
                            let tol = 1e-12 * self.cell;
                            dist < bd - tol
                                || (dist <= bd + tol
                                    && (t.gap > bt.gap || (t.gap == bt.gap && k < bt.segment)))
                        }
                    };
                    if better {
                        best = Some((dist, t));
                    }
                }
            }
        }
        best.map(|(_, t)| t)
    }

    /// The projection of `x` on segment `k` as placed at the last update.
    fn project(&self, k: usize, x: Vector) -> Target {
        let [a, b] = self.ends[k];
        let e = [b[0] - a[0], b[1] - a[1], 0.0];
        let l2 = dot(e, e);
        let xi = (((x[0] - a[0]) * e[0] + (x[1] - a[1]) * e[1]) / l2).clamp(0.0, 1.0);
        let mut c: Vector = std::array::from_fn(|d| (1.0 - xi) * a[d] + xi * b[d]);
        let [p, q] = self.segments[k];
        let (r, slope) = self.irregularity(p, q, xi);
        let e = match &self.surface {
            Surface::Edges => e,
            Surface::Beams { phi } => {
                // The beam's own deflected line at the point and its slope (module docs,
                // Beams): the element runs from q (left) to p (right), xi_e = 1 - xi.
                let l = self.reference[2 * p] - self.reference[2 * q];
                let (w, dw) = beam_line(phi[k], l, 1.0 - xi, &self.beam_dofs[k]);
                let chord_w = (1.0 - xi) * self.beam_dofs[k][2] + xi * self.beam_dofs[k][0];
                c[1] += w - chord_w;
                // Run from right to left: along -x, down the slope.
                [-l, -dw * l, 0.0]
            }
        };
        // The irregularity raises the point and turns the line by its slope (module docs).
        c[1] += r;
        let e = [e[0], e[1] + slope * e[0], 0.0];
        let l = dot(e, e).sqrt();
        let normal = [e[1] / l, -e[0] / l, 0.0];
        let gap = (x[0] - c[0]) * normal[0] + (x[1] - c[1]) * normal[1];
        Target {
            segment: k,
            xi,
            eta: 0.0,
            normal,
            gap,
        }
    }

    /// The normal row of slave node `node` (its dofs `slave.first_dof + 2 node ..`,
    /// reference position `x_ref`, its `x` and `y`) against `target` at time `t` in the configuration `u`
    /// (module docs).
    pub fn normal_row(
        &self,
        target: &Target,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        self.row(target, target.normal, slave, node, x_ref, t, u)
    }

    /// The tangential row (the normal turned by +90 degrees), as [`Search::normal_row`].
    pub fn tangent_row(
        &self,
        target: &Target,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        self.row(target, tangent_2d(target.normal), slave, node, x_ref, t, u)
    }

    #[allow(clippy::too_many_arguments)]
    fn row(
        &self,
        target: &Target,
        n: Vector,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        let [p, q] = self.segments[target.segment];
        let xi = target.xi;
        let mut terms = Terms::default();
        let ca = slave.motion.rotate_back(t, n);
        let da = slave.first_dof + 2 * node;
        terms.push(da, ca[0]);
        terms.push(da + 1, ca[1]);
        let cm = self.master.motion.rotate_back(t, n);
        match &self.surface {
            Surface::Edges => {
                for (m, wgt) in [(p, 1.0 - xi), (q, xi)] {
                    let d = self.master.first_dof + 2 * m;
                    terms.push(d, -wgt * cm[0]);
                    terms.push(d + 1, -wgt * cm[1]);
                }
            }
            Surface::Beams { phi } => {
                // The element runs from q (left, its node 1) to p (right, its node 2).
                let l = self.reference[2 * p] - self.reference[2 * q];
                let (nw, _) = shape_functions(phi[target.segment], l, 1.0 - xi);
                let (dq, dp) = (self.master.first_dof + 2 * q, self.master.first_dof + 2 * p);
                for (d, c) in [(dq, nw[0]), (dq + 1, nw[1]), (dp, nw[2]), (dp + 1, nw[3])] {
                    terms.push(d, -c * cm[1]);
                }
            }
        }
        // g = n.(x_a - x_s) = c.(X + u) + n.(origin_a - origin_s): o = -n.(o_a - o_s).
        let (oa, om) = (slave.motion.origin(t), self.master.motion.origin(t));
        let mut offset = -(n[0] * (oa[0] - om[0]) + n[1] * (oa[1] - om[1]));
        if let Surface::Beams { .. } = self.surface {
            // A beam's point has no dof along x: its abscissa is the offset's.
            let xs = (1.0 - xi) * self.reference[2 * p] + xi * self.reference[2 * q];
            offset += cm[0] * xs;
            // The irregularity's height is the surface's, moved by no dof.
            offset += cm[1] * self.irregularity(p, q, xi).0;
        }
        let la = [x_ref[0] + u[da], x_ref[1] + u[da + 1], 0.0];
        let drift_a = slave.motion.drift(t, la);
        let lp = self.local(u, p);
        let lq = self.local(u, q);
        let (dp, dq) = (
            self.master.motion.drift(t, lp),
            self.master.motion.drift(t, lq),
        );
        let rel: Vector = std::array::from_fn(|i| drift_a[i] - (1.0 - xi) * dp[i] - xi * dq[i]);
        SearchedRow {
            terms,
            offset,
            w: -dot(n, rel),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::obstacle::{Flattening, Obstacle, RotatingLine};

    /// A flat master surface along `y = 0` from `x = -L` to `L` in `n` segments, the body
    /// below it (so the segments run from right to left: the body on their left).
    fn floor(n: usize, l: f64) -> (Vec<f64>, Vec<[usize; 2]>) {
        let mut reference = Vec::new();
        for i in 0..=n {
            reference.push(l - 2.0 * l * i as f64 / n as f64);
            reference.push(0.0);
        }
        let segments = (0..n).map(|i| [i, i + 1]).collect();
        (reference, segments)
    }

    #[test]
    fn the_closest_segment_and_the_gap_of_a_point_above_a_floor() {
        let (reference, segments) = floor(10, 1.0);
        let master = Placed {
            motion: Motion::Fixed,
            first_dof: 0,
        };
        let mut s = Search::new(2, master, reference, segments, 0.5).unwrap();
        s.update(0.0, &[0.0; 22]);
        // Segment k spans x in [1 - 0.2 (k + 1), 1 - 0.2 k].
        let t = s.find([0.31, 0.05, 0.0]).unwrap();
        assert_eq!(t.segment, 3);
        assert!((t.xi - (0.4 - 0.31) / 0.2).abs() < 1e-12);
        assert!((t.gap - 0.05).abs() < 1e-12, "gap {}", t.gap);
        assert!((t.normal[1] - 1.0).abs() < 1e-12);
        let t = s.find([-0.55, -0.01, 0.0]).unwrap();
        assert!(
            (t.gap + 0.01).abs() < 1e-12,
            "penetration is a negative gap"
        );
        assert!(s.find([0.0, 0.6, 0.0]).is_none(), "beyond the reach");
    }

    #[test]
    fn a_translating_master_moves_its_segments_and_the_pair_follows() {
        let (reference, segments) = floor(10, 1.0);
        let master = Placed {
            motion: Motion::Translating {
                origin: [0.0; 3],
                velocity: [-2.0, 0.0, 0.0],
            },
            first_dof: 0,
        };
        let mut s = Search::new(2, master, reference, segments, 0.5).unwrap();
        let u = [0.0; 22];
        s.update(0.0, &u);
        let at0 = s.find([0.31, 0.05, 0.0]).unwrap().segment;
        s.update(0.1, &u);
        let at1 = s.find([0.31, 0.05, 0.0]).unwrap();
        // The floor moved 0.2 m to the left: the point is above the segment one to the right.
        assert_eq!(at1.segment + 1, at0);
        assert!((at1.gap - 0.05).abs() < 1e-12);
    }

    /// The searched row of a node of a wheel in its rotating frame against a rigid flat
    /// floor is the rotating base's row, seen from the ground: the gaps agree, the row is
    /// the base's normal turned into the wheel's frame, and `w` is the base's normal
    /// velocity.
    #[test]
    fn a_node_in_a_rotating_frame_against_a_fixed_floor_is_the_rotating_base() {
        let radius = 0.1;
        let omega = 300.0;
        let (mut reference, segments) = floor(40, 0.2);
        for y in reference.iter_mut().skip(1).step_by(2) {
            *y = -radius;
        }
        let master = Placed {
            motion: Motion::Fixed,
            first_dof: 2,
        };
        let mut s = Search::new(2, master, reference, segments, 0.05).unwrap();
        // The wheel turns counter-clockwise at -omega (rolls to the right); seen in its
        // frame, the base turns at +omega about the centre.
        let wheel = Placed {
            motion: Motion::Rotating {
                centre: [0.0; 3],
                omega: -omega,
                angle0: 0.0,
            },
            first_dof: 0,
        };
        let base = RotatingLine {
            centre: [0.0; 3],
            radius,
            omega,
            theta0: 0.0,
            flattening: Flattening {
                depth: 0.0,
                settle_time: 0.0,
            },
            creepage: 0.0,
        };
        let n_dofs = 2 + 2 * 41;
        let mut u = vec![0.0; n_dofs];
        for &(t, xr, ux, uy) in &[
            (0.0, [0.0, -0.0995], 1e-5, -2e-4),
            (1e-4, [0.003, -0.0999], 3e-5, 1e-4),
            (2.5e-4, [-0.01, -0.0990], -2e-5, -8e-4),
        ] {
            u[0] = ux;
            u[1] = uy;
            s.update(t, &u);
            let x = wheel.motion.place(t, [xr[0] + ux, xr[1] + uy, 0.0]);
            let target = s.find(x).expect("the node is over the floor");
            let row = s.normal_row(&target, wheel, 0, &xr, t, &u);
            let local = [xr[0] + ux, xr[1] + uy, 0.0];
            let hs = base.half_space(t, local);
            // The same gap.
            let x_all: Vec<f64> = (0..n_dofs)
                .map(|d| {
                    if d < 2 {
                        local[d]
                    } else {
                        s.reference[d - 2] + u[d]
                    }
                })
                .collect();
            let g = row.terms.dot(&x_all) - row.offset;
            assert!(
                (g - hs.gap(local)).abs() < 1e-14,
                "gap {g} against {}",
                hs.gap(local)
            );
            // The row on the wheel's node is the base's normal in the wheel's frame.
            let c: Vec<(usize, f64)> = row.terms.iter().filter(|&(d, _)| d < 2).collect();
            assert!((c[0].1 - hs.normal[0]).abs() < 1e-12 && (c[1].1 - hs.normal[1]).abs() < 1e-12);
            let w_base = base.surface_normal_velocity(t, local);
            assert!(
                (row.w - w_base).abs() < 1e-9 * omega * radius,
                "w {} against the base's {}",
                row.w,
                w_base
            );
        }
    }

    #[test]
    fn w_is_minus_the_gap_rate_at_fixed_displacements() {
        for motion in [
            Motion::Translating {
                origin: [0.01, -0.1, 0.0],
                velocity: [-30.0, 0.5, 0.0],
            },
            Motion::Pressed {
                origin: [0.01, -0.1, 0.0],
                velocity: [-30.0, 0.0, 0.0],
                direction: [0.0, 1.0, 0.0],
                program: Flattening {
                    depth: 1e-3,
                    settle_time: 3e-4,
                },
            },
        ] {
            w_is_minus_the_gap_rate(motion);
        }
    }

    fn w_is_minus_the_gap_rate(motion: Motion) {
        let (reference, segments) = floor(20, 0.3);
        let master = Placed {
            motion,
            first_dof: 2,
        };
        let mut s = Search::new(2, master, reference, segments, 0.05).unwrap();
        let wheel = Placed {
            motion: Motion::Rotating {
                centre: [0.002, 0.0, 0.0],
                omega: -300.0,
                angle0: 0.3,
            },
            first_dof: 0,
        };
        let mut u = vec![0.0; 2 + 42];
        for (i, x) in u.iter_mut().enumerate() {
            *x = 1e-5 * ((i * 7 % 5) as f64 - 2.0);
        }
        let xr = [0.02, -0.097];
        let t = 1e-4;
        s.update(t, &u);
        let x = wheel.motion.place(t, [xr[0] + u[0], xr[1] + u[1], 0.0]);
        let target = s.find(x).unwrap();
        let gap_at = |tt: f64| {
            let xa = wheel.motion.place(tt, [xr[0] + u[0], xr[1] + u[1], 0.0]);
            let [p, q] = s.segments[target.segment];
            let lp = s.local(&u, p);
            let lq = s.local(&u, q);
            let (a, b) = (s.master.motion.place(tt, lp), s.master.motion.place(tt, lq));
            let xs: Vector = std::array::from_fn(|d| (1.0 - target.xi) * a[d] + target.xi * b[d]);
            dot(target.normal, [xa[0] - xs[0], xa[1] - xs[1], 0.0])
        };
        let dt = 1e-9;
        let rate = (gap_at(t + dt) - gap_at(t - dt)) / (2.0 * dt);
        let row = s.normal_row(&target, wheel, 0, &xr, t, &u);
        assert!(
            (rate + row.w).abs() < 1e-6 * 30.0,
            "rate {rate}, w {}",
            row.w
        );
        assert!((gap_at(t) - target.gap).abs() < 1e-15);
    }

    /// On a rail of beams the row's gap is the normal distance to the beam's own deflected
    /// line (Hermite, or the Timoshenko element's `N_w`), not to the chord; its rate at
    /// fixed dofs is `-w`.
    #[test]
    fn a_node_over_a_rail_of_beams_sees_the_beams_deflection() {
        let (reference, segments) = floor(4, 0.4);
        let phi = vec![0.0, 0.0, 0.3, 0.0];
        let master = Placed {
            motion: Motion::Translating {
                origin: [0.0, -0.1, 0.0],
                velocity: [-20.0, 0.0, 0.0],
            },
            first_dof: 2,
        };
        let s0 = Search::new(2, master, reference.clone(), segments, 0.05).unwrap();
        let mut s = s0.clone().on_beams(phi.clone()).unwrap();
        assert!(s0.clone().on_beams(vec![0.0; 3]).is_err());
        // (w, theta) per rail node after the slave node's two dofs.
        let mut u = vec![0.0; 2 + 10];
        let w = [0.0, -1e-4, -3e-4, -2e-4, 0.0];
        let th = [1e-3, 2e-3, 0.0, -2e-3, -1e-3];
        for i in 0..5 {
            u[2 + 2 * i] = w[i];
            u[2 + 2 * i + 1] = th[i];
        }
        let slave = Placed {
            motion: Motion::Fixed,
            first_dof: 0,
        };
        let t = 2e-3;
        let xr = [0.13, -0.0998];
        s.update(t, &u);
        let x = [xr[0], xr[1], 0.0];
        let target = s.find(x).unwrap();
        let row = s.normal_row(&target, slave, 0, &xr, t, &u);
        // X per dof: the slave's position, then (Y, 0) per rail node.
        let mut xref = vec![xr[0], xr[1]];
        for i in 0..5 {
            xref.extend([reference[2 * i + 1], 0.0]);
        }
        let x_all: Vec<f64> = xref.iter().zip(&u).map(|(a, b)| a + b).collect();
        let g = row.terms.dot(&x_all) - row.offset;
        // Directly: the element from q (left) to p (right), its deflection at 1 - xi.
        let [p, q] = s.segments()[target.segment];
        let l = reference[2 * p] - reference[2 * q];
        let (nw, _) = shape_functions(phi[target.segment], l, 1.0 - target.xi);
        let wx = nw[0] * w[q] + nw[1] * th[q] + nw[2] * w[p] + nw[3] * th[p];
        let xs_local = [
            (1.0 - target.xi) * reference[2 * p] + target.xi * reference[2 * q],
            reference[2 * p + 1] + wx,
            0.0,
        ];
        let xs = master.motion.place(t, xs_local);
        let direct = dot(target.normal, [x[0] - xs[0], x[1] - xs[1], 0.0]);
        assert!((g - direct).abs() < 1e-15, "row {g}, direct {direct}");
        assert!(
            (g - target.gap).abs() < 1e-15,
            "the search's gap is the row's"
        );
        let chord_w = (1.0 - target.xi) * w[p] + target.xi * w[q];
        assert!(
            (wx - chord_w).abs() > 1e-7,
            "the deflection between nodes is not the chord's"
        );
        // The normal is the beam line's: normal to (1, w') with w' the element's own slope.
        let dxi = 1e-6;
        let w_at = |xe: f64| {
            let (n, _) = shape_functions(phi[target.segment], l, xe);
            n[0] * w[q] + n[1] * th[q] + n[2] * w[p] + n[3] * th[p]
        };
        let xe = 1.0 - target.xi;
        let slope = (w_at(xe + dxi) - w_at(xe - dxi)) / (2.0 * dxi * l);
        let nx = -slope / (1.0 + slope * slope).sqrt();
        assert!(
            (target.normal[0] - nx).abs() < 1e-9,
            "normal {:?}, beam slope {slope}",
            target.normal
        );
        // Rate at fixed dofs.
        let gap_at = |tt: f64| {
            let xs = master.motion.place(tt, xs_local);
            dot(target.normal, [x[0] - xs[0], x[1] - xs[1], 0.0])
        };
        let dt = 1e-9;
        let rate = (gap_at(t + dt) - gap_at(t - dt)) / (2.0 * dt);
        assert!(
            (rate + row.w).abs() < 1e-6 * 20.0,
            "rate {rate}, w {}",
            row.w
        );
    }

    /// An irregularity on the rail's top: the row's gap is the height above `r(X)`, and a
    /// node held still over the rail that runs under it sees the gap change at
    /// `-V r'(X)`, which the row's drift term `w` carries (to the slope squared).
    #[test]
    fn a_node_over_an_irregular_rail_sees_the_height_and_its_slope() {
        let (reference, segments) = floor(4, 0.4);
        let v = 20.0;
        let master = Placed {
            motion: Motion::Translating {
                origin: [0.0, -0.1, 0.0],
                velocity: [-v, 0.0, 0.0],
            },
            first_dof: 2,
        };
        let (amp, wl) = (1e-4, 0.1);
        let profile = Profile::harmonic(amp, wl, (-0.4, 0.4), 0.0).unwrap();
        let plain = Search::new(2, master, reference.clone(), segments, 0.05).unwrap();
        assert!(
            plain.clone().with_profile(profile.clone()).is_err(),
            "edges refuse it"
        );
        let mut s = plain
            .on_beams(vec![0.0; 4])
            .unwrap()
            .with_profile(profile.clone())
            .unwrap();
        let u = vec![0.0; 2 + 10];
        let slave = Placed {
            motion: Motion::Fixed,
            first_dof: 0,
        };
        let xr = [0.13, -0.0995];
        let x = [xr[0], xr[1], 0.0];
        let gap_at = |s: &mut Search, t: f64| {
            s.update(t, &u);
            s.find(x).unwrap().gap
        };
        for t in [0.0, 1e-3, 2.3e-3] {
            s.update(t, &u);
            let target = s.find(x).unwrap();
            let row = s.normal_row(&target, slave, 0, &xr, t, &u);
            let mut xref = vec![xr[0], xr[1]];
            for i in 0..5 {
                xref.extend([reference[2 * i + 1], 0.0]);
            }
            let g = row.terms.dot(&xref) - row.offset;
            let (r, slope) = profile.at(xr[0] + v * t);
            let height = xr[1] + 0.1 - r;
            assert!(
                (g - target.gap).abs() < 1e-15,
                "row {g}, search {}",
                target.gap
            );
            assert!(
                (g - height).abs() < 1e-3 * amp,
                "gap {g} against the height above the profile {height}"
            );
            let dt = 1e-7;
            let rate = (gap_at(&mut s, t + dt) - gap_at(&mut s, t - dt)) / (2.0 * dt);
            assert!(
                (rate + v * slope).abs() < 1e-3 * (v * amp * 2.0 * std::f64::consts::PI / wl),
                "rate {rate}, -V r' {}",
                -v * slope
            );
            assert!(
                (rate + row.w).abs() < 1e-3 * (v * amp * 2.0 * std::f64::consts::PI / wl),
                "rate {rate}, w {}",
                row.w
            );
        }
    }

    #[test]
    fn bad_setups_are_refused() {
        let (reference, segments) = floor(4, 1.0);
        let placed = Placed {
            motion: Motion::Fixed,
            first_dof: 0,
        };
        assert_eq!(
            Search::new(3, placed, reference.clone(), segments.clone(), 0.1).unwrap_err(),
            SearchError::Dimension(3)
        );
        assert!(Search::new(2, placed, reference.clone(), vec![[0, 0]], 0.1).is_err());
        assert!(Search::new(2, placed, reference.clone(), vec![[0, 9]], 0.1).is_err());
        assert!(Search::new(2, placed, reference, segments, f64::NAN).is_err());
    }
}
