//! A contact interface between two bodies: one body's contact nodes (slave) searched against
//! another body's surface segments (master) once per step ([`super::search`]; a 3D body's
//! facets, [`super::facets`]), each node's closest segment then frozen for the step and
//! presented to the treatments as the row of a [`Pair::Searched`](super::Pair::Searched)
//! pair.
//!
//! A pair exists for every slave node for the whole run; what comes and goes as the bodies
//! move is its target. A node with a segment within the search's reach has the row of
//! [`super::search`] (`c` on the node's and the segment's ends' dofs, the frames' offset and
//! the drift's normal velocity `w`); a node with none has an empty row whose gap is
//! [`FAR_GAP`] times the reach: open, never braked, held or reacted, whatever the treatment.
//!
//! **When the targets are frozen.** The driver refreshes every interface at the start of
//! each step, from the state the step starts from ([`Interface::refresh`]); the treatment's
//! predictions, solves and judgements of that step all see the same rows. A step back (the
//! soft way's braking, Table 1 item 4) repeats the previous interval with the targets of the
//! later state: one step's travel (`V h`, 60 um for the wheel at 30 m/s and `h` = 2 us,
//! against segments of 2 mm) off.
//!
//! **Losing a target.** A node held in contact whose target disappears (a body rolled off
//! the other's end) would leave a held row empty: [`Interface::refresh`] refuses it with
//! [`InterfaceError::LostTarget`], naming the node, rather than let the run continue on a
//! singular row.

use std::any::Any;

use super::obstacle::Vector;
use super::rows::Terms;
use super::search::{Motion, Placed, Search, SearchedRow, Target};

/// A master surface that an [`Interface`] searches: the contract of a contact search, in
/// any dimension. The planar segment search ([`Search`]: a body's boundary edges, or a rail
/// of beams) fulfils it; a 3D body's facets are another implementation of the same
/// contract, and the interface, the pairs, the treatments and the driver stay as they are.
pub trait MasterSurface: Send + Sync + std::fmt::Debug {
    /// The dimension of the bodies the surface joins (coordinates and displacement dofs
    /// per node of the slave body).
    fn dim(&self) -> usize;

    /// How far from the surface a node finds a target, m.
    fn reach(&self) -> f64;

    /// The master body's placement.
    fn master(&self) -> Placed;

    /// The master body's dofs that a row may touch, sorted, without repeats.
    fn master_dofs(&self) -> Vec<usize>;

    /// Places the surface in the ground at time `t` with the model's displacements `u`
    /// (once per step; allocates nothing once its buffers have grown).
    fn update(&mut self, t: f64, u: &[f64]);

    /// The closest point of the surface to the ground point `x` within the reach, frozen
    /// as a [`Target`]; `None` when none is within reach.
    fn find(&self, x: Vector) -> Option<Target>;

    /// The normal row of slave node `node` (the slave body's own index; reference position
    /// `x_ref`, `dim` values) against `target` at time `t` in the configuration `u`.
    fn normal_row(
        &self,
        target: &Target,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow;

    /// The tangential row along tangent `k` (`k < dim - 1`), as [`MasterSurface::normal_row`];
    /// `None` past the surface's tangents.
    #[allow(clippy::too_many_arguments)]
    fn tangent_row(
        &self,
        target: &Target,
        k: usize,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> Option<SearchedRow>;

    /// Moves the master body's translating frame by `d` (m) in the ground: a ring rail's
    /// labels shifted by a station ([`crate::simulation::RingShift`]). `false` (nothing
    /// done) for a surface whose frame does not translate.
    fn shift_frame(&mut self, _d: Vector) -> bool {
        false
    }

    /// A boxed copy (an interface is cloned with its problem).
    fn clone_box(&self) -> Box<dyn MasterSurface>;

    /// The surface as [`Any`], for a kind that knows its concrete search (the planar
    /// segment search's profile and segments).
    fn as_any(&self) -> &dyn Any;
}

impl Clone for Box<dyn MasterSurface> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// The planar segment search as a master surface (its own methods, [`Search`]).
impl MasterSurface for Search {
    fn dim(&self) -> usize {
        2
    }

    fn reach(&self) -> f64 {
        Search::reach(self)
    }

    fn master(&self) -> Placed {
        Search::master(self)
    }

    /// Both ends' dofs of every segment (two per node: a body's `(u_x, u_y)`, a beam's
    /// `(w, theta)`).
    fn master_dofs(&self) -> Vec<usize> {
        let first = Search::master(self).first_dof;
        let mut dofs: Vec<usize> = self
            .segments()
            .iter()
            .flat_map(|s| s.iter().flat_map(|&i| [first + 2 * i, first + 2 * i + 1]))
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    fn update(&mut self, t: f64, u: &[f64]) {
        Search::update(self, t, u);
    }

    fn find(&self, x: Vector) -> Option<Target> {
        Search::find(self, x)
    }

    fn normal_row(
        &self,
        target: &Target,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        Search::normal_row(self, target, slave, node, x_ref, t, u)
    }

    fn tangent_row(
        &self,
        target: &Target,
        k: usize,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> Option<SearchedRow> {
        (k == 0).then(|| Search::tangent_row(self, target, slave, node, x_ref, t, u))
    }

    fn clone_box(&self) -> Box<dyn MasterSurface> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// The gap of a node without a target, in units of the search's reach.
pub const FAR_GAP: f64 = 1.0e3;

/// Errors of an interface's refresh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InterfaceError {
    /// A node close to the master surface found no segment within reach.
    #[error(
        "contact node {node} was {gap:.3e} m from the master surface at t = {t:.6e} s and then \
         found no segment within reach (the bodies have moved apart along the surface: make \
         the master surface longer, or the run shorter)"
    )]
    LostTarget {
        /// The node (the slave body's own index).
        node: usize,
        /// Its last gap, m.
        gap: f64,
        /// The time of the refresh, s.
        t: f64,
    },
}

/// A contact interface: slave nodes against a master surface (module docs).
#[derive(Debug, Clone)]
pub struct Interface {
    search: Box<dyn MasterSurface>,
    /// Coordinates (and displacement dofs) per slave node: the surface's dimension.
    dim: usize,
    slave: Placed,
    /// The slave body's contact nodes (its own indices).
    nodes: Vec<usize>,
    /// Their reference positions, m, flat: `dim` per node, in the order of `nodes`.
    x_ref: Vec<f64>,
    /// Each node's target at the last refresh.
    targets: Vec<Option<Target>>,
    /// The reach of the search, m.
    reach: f64,
}

impl Interface {
    /// An interface between the nodes `nodes` of the slave body placed by `slave` (its own
    /// node indices, reference positions `slave_reference`, the surface's
    /// [`MasterSurface::dim`] per node) and the master surface `search`.
    ///
    /// # Panics
    /// If a node is not in `slave_reference`.
    pub fn new(
        search: impl MasterSurface + 'static,
        slave: Placed,
        nodes: Vec<usize>,
        slave_reference: &[f64],
    ) -> Self {
        let (reach, dim) = (search.reach(), search.dim());
        let x_ref = nodes
            .iter()
            .flat_map(|&i| &slave_reference[dim * i..dim * (i + 1)])
            .copied()
            .collect();
        Self {
            targets: vec![None; nodes.len()],
            search: Box::new(search),
            dim,
            slave,
            nodes,
            x_ref,
            reach,
        }
    }

    /// The reference position of slave node `slot` (its index in [`Interface::nodes`]).
    fn x_ref(&self, slot: usize) -> &[f64] {
        &self.x_ref[self.dim * slot..self.dim * (slot + 1)]
    }

    /// The slave nodes (the slave body's own indices), one pair each.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// The slave body's placement.
    pub fn slave(&self) -> Placed {
        self.slave
    }

    /// Turns the slave body's frame by `angle` (rad) about the ground's `z` through its
    /// centre, and forgets the targets: a moving refined zone's relocation, whose mesh frame
    /// turns by one sector ([`crate::simulation::Relocation`]); the next refresh finds them
    /// again. `false` (nothing done) unless the slave's frame turns about `z`.
    pub fn turn_slave_frame(&mut self, angle: f64) -> bool {
        let Motion::Rotating { angle0, .. } = &mut self.slave.motion else {
            return false;
        };
        *angle0 += angle;
        if angle != 0.0 {
            self.targets.iter_mut().for_each(|t| *t = None);
        }
        true
    }

    /// Moves the master body's translating frame by `d` (m) and forgets the targets: a ring
    /// rail whose nodes were relabelled one station on ([`crate::simulation::RingShift`]);
    /// the next refresh finds them again. `false` (nothing done) unless the master's frame
    /// translates.
    pub fn shift_master_frame(&mut self, d: Vector) -> bool {
        if !self.search.shift_frame(d) {
            return false;
        }
        self.targets.iter_mut().for_each(|t| *t = None);
        true
    }

    /// The master surface's search.
    pub fn search(&self) -> &dyn MasterSurface {
        self.search.as_ref()
    }

    /// The planar segment search, when the master surface is one (its segments, a rail's
    /// profile).
    pub fn segment_search(&self) -> Option<&Search> {
        self.search.as_any().downcast_ref::<Search>()
    }

    /// The target of slave node `slot` (its index in [`Interface::nodes`]) at the last
    /// refresh.
    pub fn target(&self, slot: usize) -> Option<&Target> {
        self.targets[slot].as_ref()
    }

    /// The master body's dofs that a row may touch, sorted ([`MasterSurface::master_dofs`]).
    pub fn master_dofs(&self) -> Vec<usize> {
        self.search.master_dofs()
    }

    /// Finds each slave node's closest master segment at time `t` in the configuration `u`
    /// (the model's displacements) and freezes it (module docs). Allocates nothing.
    ///
    /// # Errors
    /// [`InterfaceError::LostTarget`] when a node that was within half the reach of the
    /// surface finds none.
    pub fn refresh(&mut self, t: f64, u: &[f64]) -> Result<(), InterfaceError> {
        self.search.update(t, u);
        for slot in 0..self.nodes.len() {
            let d = self.slave.first_dof + self.dim * self.nodes[slot];
            let x_ref = self.x_ref(slot);
            let mut local = [0.0; 3];
            for (c, l) in local.iter_mut().enumerate().take(self.dim) {
                *l = x_ref[c] + u[d + c];
            }
            let found = self.search.find(self.slave.motion.place(t, local));
            if found.is_none() {
                if let Some(last) = self.targets[slot] {
                    if last.gap < 0.5 * self.reach {
                        return Err(InterfaceError::LostTarget {
                            node: self.nodes[slot],
                            gap: last.gap,
                            t,
                        });
                    }
                }
            }
            self.targets[slot] = found;
        }
        Ok(())
    }

    /// The tangential row along tangent `k` (`k < dim - 1`: the plane's one tangent, or
    /// the two of a 3D surface, [`super::pair::tangent_basis`]) of slave node `slot` against
    /// its frozen target at time `t` in the configuration `u`, with a zero offset; `None`
    /// past the surface's tangents, and an empty row when the node has no target.
    pub fn tangent(&self, slot: usize, k: usize, t: f64, u: &[f64]) -> Option<SearchedRow> {
        if k + 1 >= self.dim {
            return None;
        }
        Some(match &self.targets[slot] {
            Some(target) => {
                let (node, x_ref) = (self.nodes[slot], self.x_ref(slot));
                let r = self
                    .search
                    .tangent_row(target, k, self.slave, node, x_ref, t, u)
                    .unwrap_or_default();
                SearchedRow { offset: 0.0, ..r }
            }
            None => SearchedRow::default(),
        })
    }

    /// The normal row (`tangent` false) or the first tangential row (true) of slave node
    /// `slot` against its frozen target at time `t` in the configuration `u`; an empty row
    /// with the gap [`FAR_GAP`] times the reach when it has none (module docs).
    pub fn row(&self, slot: usize, t: f64, u: &[f64], tangent: bool) -> SearchedRow {
        match &self.targets[slot] {
            Some(target) => {
                let (node, x_ref) = (self.nodes[slot], self.x_ref(slot));
                let r = if tangent {
                    self.search
                        .tangent_row(target, 0, self.slave, node, x_ref, t, u)
                        .unwrap_or_default()
                } else {
                    self.search
                        .normal_row(target, self.slave, node, x_ref, t, u)
                };
                SearchedRow {
                    offset: if tangent { 0.0 } else { r.offset },
                    ..r
                }
            }
            None => SearchedRow {
                terms: Terms::default(),
                offset: if tangent { 0.0 } else { -FAR_GAP * self.reach },
                w: 0.0,
            },
        }
    }
}
