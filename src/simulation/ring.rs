//! A ring rail's seam kept ahead of the patch ([`RingShift`]).

use crate::contact::Interface;
use crate::model::{PairMode, PairState, Snapshot};

/// A body closed on itself along `x` (a ring of equal stations: the rail closed on itself,
/// [`crate::bodies::rolling3d::RailBlock::periodic`]) whose frame translates under the
/// contact, met through an interface as its master. Its seam (a station without top
/// facets) must stay off the patch however far the run rolls: each time the patch has
/// come within `limit` of it, the ring's nodes are relabelled one station back (each node
/// takes the state of its [`RingShift::sources`] node, the one a station ahead along the
/// patch's travel) and its frame moves on by one `pitch`. The same material is then in the
/// same place with the seam one station further ahead; the contact rows' terms on the ring
/// move with their nodes, and the interface's targets are found again. The ring's step
/// matrix does not change under the shift, so neither do the factor nor the cached columns.
#[derive(Debug, Clone)]
pub struct RingShift {
    /// Per model node, the node whose state it takes at a shift (itself off the ring).
    pub sources: Vec<usize>,
    /// One station, m.
    pub pitch: f64,
    /// The frame's move along `x` per shift, m (`+pitch` when the patch travels toward `+x`
    /// in the ring's coordinates).
    pub step: f64,
    /// The patch's place along the ring at `t = 0`, m.
    pub start: f64,
    /// The patch's speed along the ring, m/s (> 0).
    pub speed: f64,
    /// The place along the ring past which a shift is due, m.
    pub limit: f64,
}

/// The shift's work, built once ([`super::Simulation::set_ring_shift`]).
#[derive(Debug)]
pub(super) struct Shifting {
    pub(super) spec: RingShift,
    /// The new label of each old node.
    node_map: Vec<usize>,
    /// Shifts done.
    pub(super) done: usize,
    dim: usize,
    scratch: Vec<f64>,
}

impl Shifting {
    /// The shift of `spec` on a model of `dim` unknowns per node; `None` unless the sources
    /// are a permutation of the nodes.
    pub(super) fn new(spec: RingShift, dim: usize) -> Option<Self> {
        let n = spec.sources.len();
        let mut node_map = vec![usize::MAX; n];
        for (new, &old) in spec.sources.iter().enumerate() {
            if old >= n || node_map[old] != usize::MAX {
                return None;
            }
            node_map[old] = new;
        }
        let ok = spec.pitch > 0.0 && spec.speed > 0.0 && spec.limit > spec.start + spec.pitch;
        ok.then(|| Self {
            node_map,
            done: 0,
            dim,
            scratch: vec![0.0; dim * n],
            spec,
        })
    }

    /// Shifts the ring while the patch at the newest state (`snaps[2]`) is past the limit
    /// (once a step unless a step rolls more than a station): the snapshots' states and
    /// pairs relabelled, the interfaces' master frames moved. Returns the shifts done.
    pub(super) fn shift_if_due(
        &mut self,
        snaps: &mut [Snapshot; 3],
        interfaces: &mut [Interface],
    ) -> usize {
        let mut shifts = 0;
        while self.due(snaps[2].t) {
            self.shift(snaps, interfaces);
            shifts += 1;
        }
        shifts
    }

    /// Whether the patch at `t` is past the limit.
    fn due(&self, t: f64) -> bool {
        let s = &self.spec;
        s.start + s.speed * t - self.done as f64 * s.pitch >= s.limit
    }

    /// One shift (type docs).
    fn shift(&mut self, snaps: &mut [Snapshot; 3], interfaces: &mut [Interface]) {
        for snap in snaps.iter_mut() {
            for x in [&mut snap.state.u, &mut snap.state.v, &mut snap.state.a] {
                self.vector(x);
            }
            self.pairs(&mut snap.pairs);
        }
        let d = [self.spec.step, 0.0, 0.0];
        for i in interfaces.iter_mut() {
            i.shift_master_frame(d);
        }
        self.done += 1;
    }

    /// Node `n` takes the values of its source.
    fn vector(&mut self, x: &mut [f64]) {
        let d = self.dim;
        for (n, &m) in self.spec.sources.iter().enumerate() {
            self.scratch[d * n..d * n + d].copy_from_slice(&x[d * m..d * m + d]);
        }
        x.copy_from_slice(&self.scratch);
    }

    /// The pairs' rows on the ring's nodes move with them (their coefficients as they are).
    fn pairs(&self, states: &mut [PairState]) {
        let map = |m: usize| self.node_map.get(m).copied();
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for st in states.iter_mut() {
            st.brake_row = st
                .brake_row
                .relabel(self.dim, map, id, 0)
                .unwrap_or_default();
            if let PairMode::Brake { q, terms, w } = st.mode {
                st.mode = match terms.relabel(self.dim, map, id, 0) {
                    Some(terms) => PairMode::Brake { q, terms, w },
                    None => PairMode::Free,
                };
            }
        }
    }
}
