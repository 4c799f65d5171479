//! The moving refined zone's relocation of the state ([`Relocation`]).

use crate::contact::{Interface, Obstacle};
use crate::mesh::zone::Source;
use crate::model::internal::Nonlinear;
use crate::model::{PairMode, PairState, Snapshot};

/// A moving refined zone ([`crate::mesh::zone`]): each time the obstacle has turned half a
/// sector past the zone's centre, the frame of the mesh turns by one sector `step` with it,
/// and the state is relabelled: node `n` takes the state of its [`Source`] (a node, or the
/// interpolation in a triangle) with its vectors turned by `-step`, pair `p` the state of the
/// pair at that node (a fresh state if there is none), and the obstacles turn by `-step`
/// ([`crate::contact::Obstacle::turn_frame`]). The matrices and their factors do not change.
/// Models of node pairs, in 2D or in 3D (the turn about the axle `z`; the 3D wheel's
/// zone, [`crate::mesh::zone3d`]), and of a wheel met by another body through a contact
/// interface whose slave it is (the 3D wheel on its elastic rail): the interface's slave
/// frame turns with the mesh's ([`crate::contact::Interface::turn_slave_frame`]), the
/// other body's nodes (from [`Relocation::turned`] on) keep their states, and a row's
/// terms on them keep their coefficients.
///
/// **Friction.** A pair's whole state goes with its node: the normal mode and rows, and the
/// tangential ones (the friction force along the pair's tangent, a scalar that a turn of the
/// frame leaves as it is, whether it slid, its slip power and the energy it dissipated); the
/// tangential rows of the next step are posed from the relabelled state, as the normal ones
/// are. The energy dissipated at the pairs the zone leaves behind (their material leaves the
/// refined arc, where the rim has fewer nodes) is handed to the pairs that start fresh ahead
/// of it, as many as those: the total friction energy is carried through exactly.
#[derive(Debug, Clone)]
pub struct Relocation {
    /// Per node, the source of its state.
    pub sources: Vec<Source>,
    /// The angle of one relocation, rad.
    pub step: f64,
    /// The obstacle's angular speed in the frame, rad/s (> 0).
    pub omega: f64,
    /// The obstacle's angle past the zone's centre at `t = 0`, rad.
    pub angle0: f64,
    /// The nodes `0..turned` turn with the frame (the wheel's, and its twin's); the nodes
    /// after them belong to a body in a frame of its own (an elastic rail met through a
    /// contact interface) and keep their labels and states, each its own source.
    pub turned: usize,
}

impl Relocation {
    /// Whether the nodes from [`Relocation::turned`] on (another body's, an elastic rail's)
    /// are each their own source and no turned node takes its state from them, and that
    /// body is met through `interfaces` whose slave is the turning body (its nodes below
    /// `turned`, its dofs first, its frame turning about `z`).
    pub(super) fn other_body_kept(&self, interfaces: &mut [crate::contact::Interface]) -> bool {
        let (nodes, turned) = (self.sources.len(), self.turned.min(self.sources.len()));
        let own = |n: usize| matches!(self.sources[n], Source::Node(m) if m == n);
        let from_turned = |n: usize| match self.sources[n] {
            Source::Node(m) => m < turned,
            Source::Triangle { nodes, .. } => nodes.iter().all(|&m| m < turned),
        };
        let labels_kept = (turned..nodes).all(own) && (0..turned).all(from_turned);
        let slaves_turn = interfaces.iter_mut().all(|i| {
            i.slave().first_dof == 0
                && i.nodes().iter().all(|&n| n < turned)
                && i.turn_slave_frame(0.0)
        });
        labels_kept && slaves_turn && (turned == nodes || !interfaces.is_empty())
    }
}

/// The relocation's work, built once ([`super::Simulation::set_relocation`]).
#[derive(Debug)]
pub(super) struct Relocating {
    pub(super) spec: Relocation,
    /// Pair `p` takes the state of pair `pairs[p]`.
    pub(super) pairs: Vec<Option<usize>>,
    /// Pairs whose state no pair takes (left behind).
    pub(super) dropped: Vec<usize>,
    /// Pairs that start fresh (no pair at their source).
    pub(super) fresh: Vec<usize>,
    /// Relocations done.
    pub(super) done: usize,
    /// The new label of each old node (`None`: dropped).
    pub(super) node_map: Vec<Option<usize>>,
    /// Unknowns per node (2 or 3).
    pub(super) dim: usize,
    /// The turn by `-step` about `z` (its leading `dim x dim` block used).
    pub(super) rot: [[f64; 3]; 3],
    pub(super) scratch: Vec<f64>,
    pub(super) pair_scratch: Vec<PairState>,
}

impl Relocating {
    /// Relocates the zone when the obstacle at the newest state (`snaps[2]`) has turned half
    /// a sector past the zone's centre: the snapshots, a nonlinear force's nodal states and
    /// the pairs relabelled, the obstacles and the interfaces' slave frames turned. Returns
    /// whether it relocated.
    pub(super) fn relocate_if_due(
        &mut self,
        snaps: &mut [Snapshot; 3],
        nonlinear: Option<&mut Nonlinear>,
        obstacles: &mut [Box<dyn Obstacle>],
        interfaces: &mut [Interface],
    ) -> bool {
        if self.spec.angle0 + self.spec.omega * snaps[2].t < 0.5 * self.spec.step {
            return false;
        }
        for snap in snaps.iter_mut() {
            self.vector(&mut snap.state.u);
            self.vector(&mut snap.state.v);
            self.vector(&mut snap.state.a);
            self.pairs(&mut snap.pairs);
        }
        if let Some(nl) = nonlinear {
            nl.relabel(|x| self.vector(x));
        }
        for o in obstacles.iter_mut() {
            o.turn_frame(self.spec.step);
        }
        for i in interfaces.iter_mut() {
            i.turn_slave_frame(self.spec.step);
        }
        self.spec.angle0 -= self.spec.step;
        self.done += 1;
        true
    }

    /// Relabels a state vector (`dim` per node) in place.
    pub(super) fn vector(&mut self, x: &mut [f64]) {
        let (r, d) = (self.rot, self.dim);
        for (n, src) in self.spec.sources.iter().enumerate() {
            let mut a = [0.0; 3];
            match *src {
                Source::Node(m) => a[..d].copy_from_slice(&x[d * m..d * m + d]),
                Source::Triangle { nodes, weights } => {
                    for k in 0..3 {
                        for (c, v) in a.iter_mut().enumerate().take(d) {
                            *v += weights[k] * x[d * nodes[k] + c];
                        }
                    }
                }
            }
            if n >= self.spec.turned {
                self.scratch[d * n..d * n + d].copy_from_slice(&a[..d]);
                continue;
            }
            for (c, row) in r.iter().enumerate().take(d) {
                let mut v = 0.0;
                for q in 0..d {
                    v += row[q] * a[q];
                }
                self.scratch[d * n + c] = v;
            }
        }
        x.copy_from_slice(&self.scratch);
    }

    /// Relabels the pairs' states.
    pub(super) fn pairs(&mut self, states: &mut [PairState]) {
        let map = |m: usize| self.node_map.get(m).copied().flatten();
        for (p, src) in self.pairs.iter().enumerate() {
            self.pair_scratch[p] = match *src {
                None => PairState::default(),
                Some(q) => {
                    let mut st = states[q];
                    st.brake_row = st
                        .brake_row
                        .relabel(self.dim, map, self.rot, self.spec.turned)
                        .unwrap_or_default();
                    if let PairMode::Brake { q, terms, w } = st.mode {
                        st.mode = match terms.relabel(self.dim, map, self.rot, self.spec.turned) {
                            Some(terms) => PairMode::Brake { q, terms, w },
                            None => PairMode::Free,
                        };
                    }
                    st
                }
            };
        }
        // The friction energy of the pairs left behind, to the fresh ones (type docs).
        if !self.dropped.is_empty() {
            let last = self.fresh.len().saturating_sub(1);
            for (k, &q) in self.dropped.iter().enumerate() {
                let to = self.fresh.get(k.min(last)).copied().unwrap_or(0);
                self.pair_scratch[to].dissipated += states[q].dissipated;
            }
        }
        states.copy_from_slice(&self.pair_scratch);
    }
}
