//! The "soft way" (paper §3.1, Table 1) as a per-node state machine.
//!
//! A node about to penetrate an obstacle is braked in the step *before* the one in which the
//! penetration is found, so that it arrives on the obstacle with the obstacle's normal
//! velocity; it is then held while the reaction is compressive, released on tension, and the
//! braking reaction `R` is given back as an external force in its first free step.
//!
//! **Braking value (Eq. 26, generalised).** With indices -1, 0, 1 for `t_{i-2}, t_{i-1},
//! t_i` (penetration found at `t_i`), let `n, c` be the obstacle's half-space at `t_i`
//! (`n . x = c` on the surface) and `w` its surface normal velocity there. Writing
//! `p = n . x`, `q = n . v`, Eq. (10) twice gives
//! `p_1 = p_{-1} + h (1 - beta) q_{-1} + h q_0 + h beta q_1`. Asking `p_1 = c` (on the
//! surface at `t_i`) and `q_1 = w` (no relative normal velocity) gives
//! $$q_0 = \frac{c - p_{-1}}{h} - (1-\beta)\\, q_{-1} - \beta w,$$
//! which for a fixed obstacle (`w = 0`) is Eq. (26), and the position at `t_{i-1}` is then
//! Eq. (27). Only the normal component is prescribed: the tangential motion stays free.
//!
//! **Holding.** Table 1 (item 6) holds the node with `v = 0`, i.e. `n . v_1 = w`. Asking
//! instead for a zero gap at `t_1` in one step, `n.v_1 = (c_1 - n.x_0 - h(1-beta) n.v_0) /
//! (h beta)`, is unstable: an error `e_0` in the relative normal velocity gives
//! `e_1 = -(1-beta)/beta e_0`, a factor -4 per step for `alpha = 0.8, gamma = 0` (any
//! `beta < 1/2`), so round-off grows into a spurious tension and the node chatters. The
//! holding velocity is therefore the surface velocity plus a deadbeat drift correction:
//! with `g* = n.x_0 + h[(1-beta) n.v_0 + beta w] - c_1`, the gap at `t_1` if `n.v_1 = w`,
//! $$n_1 \cdot v_1 = w - g^\*/h .$$
//! The gap and velocity errors `(g, h e)` then evolve with the matrix
//! `[[1-beta, (1-beta)^2], [-1, -(1-beta)]]`, whose eigenvalues are both 0 (nilpotent): any
//! drift is gone after two steps, for every `beta` in `[0, 1]`. After a braking step
//! `g* = 0` and this is exactly Table 1's `v = w`.
//!
//! **Release.** A held node whose multiplier turns tensile (`lambda < 0`) is released; the
//! same step is solved again with a force `R` added on the node (Table 1, item 7), which
//! gives back the momentum taken by the arrival. `R h` is the impulse that would have
//! stopped the node's relative normal motion in the braking step,
//! `lambda_s = S^{-1}(w - C A^{-1} b)` (`S = C A^{-1} C^T`), i.e. the braking multiplier
//! `lambda_b = S^{-1}(v_bar - C A^{-1} b)` completed with `S^{-1}(w - v_bar)`, the part of
//! the approach momentum that the arrival step removes. Table 1's `R` (the braking reaction
//! alone) is about the fraction `(q_{-1} - v_bar)/(q_{-1} - w)` of it, anywhere in
//! `(-beta, 1 - beta]` depending on where the node happens to be inside the step; with
//! `lambda_s` the restored momentum does not depend on that phase, and for `h -> 0` it is
//! the node's effective mass times its approach speed, so the impact gives back the energy
//! it took (an elastic impact of the node).
//! `lambda_s` also holds the impulse of the forces acting in the braking step,
//! `S^{-1} C (v_{-1} - A^{-1} b)`; a node resting under a load (a chattering corner under
//! a block's weight) gets that back as a push at each release, and the cycles can pump it
//! off. [`Restore::ApproachMomentum`] gives back the approach's momentum alone,
//! `S^{-1}(w - C v_{-1})` (the same rows solved on the velocity at the braking step's
//! start, `Context::solve_multipliers_at`), the same as `lambda_s` for a node that no force
//! acts on before it arrives.
//!
//! **Braking may only push.** Eq. (26) asks two things of the arrival, the position and the
//! velocity, of one braking velocity. When the penetration found at `t_i` is the obstacle's
//! doing more than the node's (a turning base that sweeps into a slow node, a rim node
//! that spans several steps' travel), meeting both can take a *tensile* braking impulse: the
//! obstacle would pull the node onto itself. Such a pair is not braked: the previous
//! interval is solved again without its brake, and the pair is held at once in the
//! interval where its penetration was found (as exact enforcement does), and the impulse
//! that stops its relative normal motion there is kept and given back at its release, as a
//! braked pair's is. For the same reason only a compressive impulse is given back. So every force the soft way
//! records pushes (without this, a 48-node plastic wheel at `h = 2e-5 s` recorded -9.4 kN
//! from one tensile braking).
//!
//! **Friction.** With a Coulomb coefficient `mu > 0` (2D) a held pair gets, beside its
//! equality normal row, a bounded row on its tangent: the slip velocity at `t1`,
//! `c_t . v1 - w_t`, is zero (stick) while the tangential impulse stays within `mu` times the
//! normal impulse, else that impulse bounds it against the slip. Braking is not extended to
//! the tangential direction: only the relative normal velocity jumps at an impact (the
//! tangential velocity is continuous, nothing to brake or to give back), so a braked pair
//! carries no friction row and friction starts with the first held step. A released pair
//! loses its friction row with its normal row. The dissipation recorded is the friction
//! force times the slip rate at `t1` that the row holds, `-F_t s_1 >= 0`
//! ([`super::treatment::record_friction`]).

use super::context::{ContactError, Context};
use super::friction::{push_rows as push_friction_rows, spring_energy, tangent_index, FrictionLaw};
use super::rows::{Row, RowKind, Terms};
use super::treatment::{record_friction, ContactTreatment, Restore, Treatment};
use crate::model::Snapshot;
use crate::time::integrator::Step;

pub use crate::model::{PairMode, PairState};

/// The braking normal velocity of Eq. (26), generalised to a moving obstacle (module docs):
/// `q0 = (c - n.x_{-1})/h - (1 - beta) n.v_{-1} - beta w`.
pub fn braking_velocity(c: f64, p_prev: f64, q_prev: f64, w: f64, h: f64, beta: f64) -> f64 {
    (c - p_prev) / h - (1.0 - beta) * q_prev - beta * w
}

/// The holding normal velocity (module docs): the surface velocity `w` corrected by the
/// gap `g*` the node would have at the end of the step if it moved with the surface,
/// `w - g*/h` (deadbeat, stable for every `beta`).
pub fn holding_velocity(c1: f64, p0: f64, q0: f64, w: f64, h: f64, beta: f64) -> f64 {
    let g_star = p0 + h * ((1.0 - beta) * q0 + beta * w) - c1;
    w - g_star / h
}

const MAX_RESOLVES: usize = 32;

/// The soft way's state machine (Table 1) on the engine; with `brakes = false` it is exact
/// enforcement for the space-time scheme (held at once in the step where penetration is
/// found, released on tension).
///
/// One interval `[t0, t1]` is solved as follows (Table 1):
/// 1. the pairs' modes at `t0` give the rows (brake, hold) and the forces given back;
/// 2. solve; a held pair with a tensile multiplier is released and the step solved again
///    with the momentum taken at its arrival given back as a force (item 7);
/// 3. a free pair found penetrating at `t1` is, with the soft way, braked in the previous
///    interval `[t_{-1}, t0]` (Eq. 26), which is solved again (items 4-5), and the interval
///    is solved again with the pair held (item 6). Without a previous interval (first step),
///    or for exact enforcement, the pair is held at once in the current interval.
#[derive(Debug, Clone)]
pub struct SoftWay {
    brakes: bool,
    restore_mode: Restore,
    modes: Vec<PairMode>,
    restore: Vec<Option<f64>>,
    released: Vec<bool>,
    pen: Vec<usize>,
    pen_saved: Vec<usize>,
    /// Per pair, its mode in the interval before a braking (restored when the braking comes
    /// out tensile).
    pre_brake: Vec<PairMode>,
    /// Per pair: held at once in this interval in place of a tensile braking; its stopping
    /// impulse is kept and given back at release as a braked pair's is.
    arrive: Vec<bool>,
    /// Per pair, the row of its hold in the last solve.
    hold_terms: Vec<Option<Terms>>,
    /// The pair of each row of the last solve.
    row_pair: Vec<usize>,
    lambda: Vec<f64>,
    lambda_stop: Vec<f64>,
    friction: Option<FrictionLaw>,
    /// Per pair, the friction row of the last solve: its row, surface velocity, multiplier
    /// and whether it slid.
    friction_row: Vec<[Option<(Terms, f64)>; 2]>,
    lambda_t: Vec<[f64; 2]>,
    sliding: Vec<bool>,
    /// The pairs' gaps at `t1` of the last solve.
    gaps: Vec<f64>,
}

impl SoftWay {
    /// For `pairs` contact pairs; `brakes`: the soft way (else exact enforcement).
    pub fn new(brakes: bool, restore: Restore, pairs: usize) -> Self {
        Self {
            brakes,
            restore_mode: restore,
            modes: vec![PairMode::Free; pairs],
            restore: vec![None; pairs],
            released: vec![false; pairs],
            pen: Vec::with_capacity(pairs),
            pen_saved: Vec::with_capacity(pairs),
            pre_brake: vec![PairMode::Free; pairs],
            arrive: vec![false; pairs],
            hold_terms: vec![None; pairs],
            row_pair: Vec::with_capacity(pairs),
            lambda: vec![0.0; pairs],
            lambda_stop: vec![0.0; pairs],
            friction: None,
            friction_row: vec![[None; 2]; pairs],
            lambda_t: vec![[0.0; 2]; pairs],
            sliding: vec![false; pairs],
            gaps: vec![0.0; pairs],
        }
    }

    /// With friction of law `law` on held pairs (`None` or zero: frictionless; module docs,
    /// Friction).
    pub fn with_friction(mut self, law: Option<FrictionLaw>) -> Self {
        self.friction = law.filter(FrictionLaw::is_active);
        self
    }

    /// The rows of the current modes: brake rows get `c.v1 = q` (or, with `stop`, the
    /// boundary's velocity `w`), held rows the holding velocity.
    fn push_rows(&mut self, ctx: &mut Context<'_>, fs: &Snapshot, step: &Step, stop: bool) {
        let (t1, bt) = (step.t0 + step.h, step.weight);
        let h = ctx.integ.h();
        ctx.rows.clear();
        self.row_pair.clear();
        for p in 0..self.modes.len() {
            let (terms, g) = match self.modes[p] {
                PairMode::Free => continue,
                PairMode::Brake { q, terms, w } => (terms, if stop { w } else { q }),
                PairMode::Hold => {
                    let geo = ctx.geometry(p, t1, &fs.u);
                    let g = if stop && self.arrive[p] {
                        geo.w
                    } else {
                        holding_velocity(
                            geo.offset,
                            geo.position(ctx.reference, &fs.u),
                            geo.terms.dot(&fs.v),
                            geo.w,
                            h,
                            bt,
                        )
                    };
                    self.hold_terms[p] = Some(geo.terms);
                    (geo.terms, g)
                }
            };
            ctx.rows.push(Row {
                pair: p,
                terms,
                kind: RowKind::Equality,
                y0: -g,
                mu: 1.0,
                reg: 0.0,
            });
            self.row_pair.push(p);
        }
        // Friction rows of the held pairs, after all normal rows (module docs, Friction).
        self.friction_row.fill([None; 2]);
        let Some(law) = self.friction else { return };
        let kt = law.tangential_stiffness;
        for normal in 0..self.row_pair.len() {
            let p = self.row_pair[normal];
            if self.modes[p] != PairMode::Hold {
                continue;
            }
            let mut tangents = [None; 2];
            for (k, slot) in tangents.iter_mut().enumerate() {
                *slot = ctx.tangent(p, t1, &fs.u, k).map(|tg| (tg.terms, tg.w));
            }
            if tangents[0].is_none() {
                continue;
            }
            self.friction_row[p] = tangents;
            let f0 = [fs.pairs[p].tangential_force, fs.pairs[p].tangential_force_2];
            push_friction_rows(
                ctx.rows,
                &law,
                (p, normal),
                tangents,
                (&fs.v, &ctx.pred.v),
                (kt, f0, fs.pairs[p].friction_coefficient),
                (step.maps, ctx.integ.h()),
            );
        }
    }
}

impl SoftWay {
    /// Whether a braking step solves the stopping impulses to give back.
    fn keeps_stop(&self) -> bool {
        matches!(
            self.restore_mode,
            Restore::StoppingImpulse | Restore::ApproachMomentum
        )
    }

    /// The stick's tangential stiffness, N/m per pair (0: a rigid stick;
    /// [`super::friction`]: elastic stick).
    fn stick_stiffness(&self) -> f64 {
        self.friction.map_or(0.0, |l| l.tangential_stiffness)
    }

    /// Solves the previous interval `[t_{k-2}, t_{k-1}]` again with the modes of `ring[0]`
    /// (the brakes just set); a pair found penetrating at `t_{k-1}` in that repetition is
    /// held at once.
    fn repeat_previous(
        &mut self,
        ctx: &mut Context<'_>,
        ring: &mut [Snapshot; 3],
    ) -> Result<(), ContactError> {
        let mut guard = 0;
        loop {
            {
                let (lo, hi) = ring.split_at_mut(1);
                self.solve_interval(ctx, &lo[0], &mut hi[0])?;
            }
            if self.pen.is_empty() || guard >= MAX_RESOLVES {
                return Ok(());
            }
            guard += 1;
            ctx.counts.resolves += 1;
            for i in 0..self.pen.len() {
                let p = self.pen[i];
                ring[0].pairs[p].mode = PairMode::Hold;
            }
        }
    }

    /// Records the pairs' states at the end of the interval `fs -> ts` and their modes for
    /// the next step (a braked pair becomes held, with its braking force and row kept for
    /// the restore); `unit_force` is the force of a unit multiplier.
    fn record(&mut self, ctx: &mut Context<'_>, fs: &Snapshot, ts: &mut Snapshot, unit_force: f64) {
        let h = ctx.integ.h();
        let np = self.modes.len();
        let k = self.row_pair.len();
        for p in 0..np {
            // Read in place and written in place: a pair's state carries two rows of up to
            // `MAX_TERMS` terms, and copying it whole twice a pair and step was a tenth of
            // the paper's wheel's time loop.
            let prev = &fs.pairs[p];
            let i = self.row_pair[..k].iter().position(|&q| q == p);
            let lam = i.map(|i| self.lambda[i]).unwrap_or(0.0);
            let gap = self.gaps[p];
            let st = &mut ts.pairs[p];
            {
                // Every field, by name (a field added to the state must be set here).
                let PairState {
                    mode,
                    restore,
                    brake_force,
                    brake_row,
                    force,
                    held,
                    braked,
                    released,
                    gap: gap_end,
                    tangential_force,
                    tangential_force_2,
                    sliding,
                    slip_power,
                    dissipated,
                    friction_coefficient,
                } = &mut *st;
                mode.assign(&self.modes[p]);
                *restore = None;
                *brake_force = prev.brake_force;
                brake_row.assign(&prev.brake_row);
                *force = lam / h;
                *held = false;
                *braked = false;
                *released = self.released[p];
                *gap_end = gap;
                *tangential_force = 0.0;
                *tangential_force_2 = 0.0;
                *sliding = false;
                *slip_power = 0.0;
                *dissipated = prev.dissipated;
                // Carried through a step out of contact (module docs of
                // `super::friction`, Memory); relaxed below when the pair has friction rows.
                *friction_coefficient = prev.friction_coefficient;
            }
            let mut slips = [0.0; 2];
            for k in 0..2 {
                let Some((terms, wt)) = &self.friction_row[p][k] else {
                    continue;
                };
                let wt = *wt;
                // The slip rate at t1 on which the row posed the law (module docs, Friction).
                let slip = terms.dot(&ts.state.v) - wt;
                let force = self.lambda_t[p][k] * unit_force;
                let kt = self.stick_stiffness();
                let f0 = [prev.tangential_force, prev.tangential_force_2][k];
                record_friction(st, (k, force), self.sliding[p], slip, h, (kt, f0));
                slips[k] = slip;
            }
            if let (Some(law), Some(_)) = (self.friction, self.friction_row[p][0]) {
                st.friction_coefficient = law.remember(prev.friction_coefficient, slips, h);
            }
            match &self.modes[p] {
                PairMode::Brake { terms, .. } => {
                    st.braked = true;
                    let ls = match i {
                        Some(i) if self.keeps_stop() => self.lambda_stop[i],
                        _ => lam,
                    };
                    st.brake_force = ls / h;
                    st.brake_row.assign(terms);
                    st.mode = PairMode::Hold;
                }
                PairMode::Hold => {
                    st.held = true;
                    if !prev.held && !prev.braked {
                        ctx.counts.entries += 1;
                    }
                    // An arrival held at once in place of a tensile braking keeps its
                    // stopping impulse to give back, as a braked pair does.
                    if let (true, Some(i), Some(terms)) =
                        (self.arrive[p], i, self.hold_terms[p].as_ref())
                    {
                        if self.keeps_stop() {
                            st.brake_force = self.lambda_stop[i] / h;
                            st.brake_row.assign(terms);
                        }
                    }
                }
                PairMode::Free => {
                    if self.released[p] {
                        st.brake_force = 0.0;
                    }
                }
            }
        }
    }
}

/// The interval `fs -> ts` (ending at `t1`) of the last solve of the rows: its velocity
/// formed from the multipliers ([`Context::form_x`]) and the end state.
fn stand(ctx: &mut Context<'_>, (step, t1): (&Step, f64), fs: &Snapshot, ts: &mut Snapshot) {
    ctx.form_x();
    ctx.finish(step, &fs.state, &mut ts.state);
    ts.t = t1;
    ts.k = fs.k + 1;
}

impl ContactTreatment for SoftWay {
    fn stored_energy(&self, s: &Snapshot) -> f64 {
        let kt = self.stick_stiffness();
        s.pairs
            .iter()
            .map(|p| {
                spring_energy(kt, p.tangential_force) + spring_energy(kt, p.tangential_force_2)
            })
            .sum()
    }

    fn name(&self) -> String {
        if self.brakes {
            Treatment::SoftWay {
                restore: self.restore_mode,
            }
            .name()
        } else {
            "exact".into()
        }
    }

    fn solve_interval(
        &mut self,
        ctx: &mut Context<'_>,
        fs: &Snapshot,
        ts: &mut Snapshot,
    ) -> Result<(), ContactError> {
        let h = ctx.integ.h();
        let t0 = fs.t;
        let t1 = t0 + h;
        let mut step = ctx.integ.step_at(t0);
        let np = self.modes.len();
        for p in 0..np {
            self.modes[p].assign(&fs.pairs[p].mode);
            self.restore[p] = fs.pairs[p].restore;
            self.released[p] = false;
        }
        let mut gaps_fresh = false;
        let mut finished = false;
        for _ in 0..MAX_RESOLVES {
            gaps_fresh = false;
            ctx.extra.fill(0.0);
            for p in 0..np {
                if let Some(r) = self.restore[p] {
                    fs.pairs[p].brake_row.scatter(r, ctx.extra);
                }
            }
            step = ctx.predict(t0, &fs.state);
            // In a braking step, the impulses that would stop the braked nodes (relative
            // normal velocity w at t1): given back at release.
            let braking =
                self.modes.iter().zip(&self.arrive).any(|(m, &a)| {
                    matches!(m, PairMode::Brake { .. }) || (a && *m == PairMode::Hold)
                });
            if braking && self.keeps_stop() {
                self.push_rows(ctx, fs, &step, true);
                if self.restore_mode == Restore::ApproachMomentum {
                    ctx.solve_multipliers_at(&fs.v, 0.0);
                } else {
                    ctx.solve_multipliers(0.0);
                }
                let k = self.row_pair.len();
                self.lambda_stop[..k].copy_from_slice(&ctx.rows.lambda()[..k]);
            }
            self.push_rows(ctx, fs, &step, false);
            // The multipliers first: a release solves the interval again, and the velocity
            // (every column the rows touch, `n` values each) is formed only for a solve
            // that may stand.
            ctx.solve_multipliers(0.0);
            finished = false;
            let k = self.row_pair.len();
            self.lambda[..k].copy_from_slice(&ctx.rows.lambda()[..k]);
            for (i, row) in ctx.rows.rows().iter().enumerate().skip(k) {
                let t = tangent_index(ctx.rows.rows(), i);
                self.lambda_t[row.pair][t] = ctx.rows.lambda()[i];
                self.sliding[row.pair] = ctx.rows.is_sliding(i);
            }
            // Tension: release (Table 1, item 7).
            let mut changed = false;
            for i in 0..k {
                let p = self.row_pair[i];
                if self.modes[p] == PairMode::Hold && self.lambda[i] < 0.0 {
                    self.modes[p] = PairMode::Free;
                    self.released[p] = true;
                    let bf = fs.pairs[p].brake_force;
                    // Only a compressive impulse is given back: a contact never pulls.
                    if self.restore_mode != Restore::Nothing && bf > 0.0 {
                        self.restore[p] = Some(bf);
                    }
                    changed = true;
                    ctx.counts.releases += 1;
                }
            }
            if changed {
                ctx.counts.resolves += 1;
                continue;
            }
            stand(ctx, (&step, t1), fs, ts);
            finished = true;
            // Penetration of free pairs at t1.
            ctx.gaps_into(t1, &ts.u, &mut self.gaps);
            gaps_fresh = true;
            self.pen.clear();
            for p in 0..np {
                if self.modes[p] != PairMode::Free {
                    continue;
                }
                if self.gaps[p] < -ctx.gap_tol {
                    if self.released[p] {
                        // Released in this very step and penetrating again: hold it.
                        self.modes[p] = PairMode::Hold;
                        self.restore[p] = None;
                        changed = true;
                    } else {
                        self.pen.push(p);
                    }
                }
            }
            if changed {
                ctx.counts.resolves += 1;
                continue;
            }
            break;
        }
        if !finished {
            // The re-solves ran out on a release: the last solve stands.
            stand(ctx, (&step, t1), fs, ts);
        }
        if !gaps_fresh {
            ctx.gaps_into(t1, &ts.u, &mut self.gaps);
        }
        self.record(ctx, fs, ts, step.maps.force);
        Ok(())
    }

    /// Solves `[t_{k-1}, t_k]`, stepping back into `[t_{k-2}, t_{k-1}]` when the soft way
    /// asks for it (Table 1, items 4-6).
    fn advance(
        &mut self,
        ctx: &mut Context<'_>,
        ring: &mut [Snapshot; 3],
        have_prev: bool,
    ) -> Result<(), ContactError> {
        let mut step_backs = 0;
        let mut immediate = 0;
        self.arrive.fill(false);
        loop {
            {
                let (lo, hi) = ring.split_at_mut(2);
                self.solve_interval(ctx, &lo[1], &mut hi[0])?;
            }
            if self.pen.is_empty() {
                return Ok(());
            }
            let mut pen = std::mem::take(&mut self.pen_saved);
            pen.clear();
            pen.extend_from_slice(&self.pen);
            if self.brakes && have_prev && step_backs < 2 {
                step_backs += 1;
                ctx.counts.step_backs += 1;
                let h = ctx.integ.h();
                let t_arrive = ring[2].t;
                let bt = ctx.integ.step_at(ring[0].t).weight;
                for &p in &pen {
                    let geo = ctx.geometry(p, t_arrive, &ring[2].u);
                    let q = braking_velocity(
                        geo.offset,
                        geo.position(ctx.reference, &ring[0].u),
                        geo.terms.dot(&ring[0].v),
                        geo.w,
                        h,
                        bt,
                    );
                    self.pre_brake[p] = ring[0].pairs[p].mode;
                    ring[0].pairs[p].mode = PairMode::Brake {
                        q,
                        terms: geo.terms,
                        w: geo.w,
                    };
                }
                self.repeat_previous(ctx, ring)?;
                // Braking may only push (module docs, Braking may only push): a pair whose
                // braking impulse came out tensile is not braked but held at once in the
                // interval where its penetration was found. Taking one brake off changes
                // the others' impulses (the pairs share the step's matrix): the interval is
                // solved again until no brake pulls, at most once per pair braked.
                let mut tensile = false;
                for _ in 0..pen.len() {
                    let mut pulled = false;
                    for &p in &pen {
                        let st = &ring[1].pairs[p];
                        if st.braked && st.force < 0.0 {
                            ring[0].pairs[p].mode = self.pre_brake[p];
                            pulled = true;
                        }
                    }
                    if !pulled {
                        break;
                    }
                    tensile = true;
                    self.repeat_previous(ctx, ring)?;
                }
                ctx.counts.brakings += pen
                    .iter()
                    .filter(|&&p| matches!(ring[0].pairs[p].mode, PairMode::Brake { .. }))
                    .count();
                if tensile {
                    for &p in &pen {
                        if !ring[1].pairs[p].braked {
                            ring[1].pairs[p].mode = PairMode::Hold;
                            self.arrive[p] = true;
                        }
                    }
                }
            } else {
                immediate += 1;
                ctx.counts.resolves += 1;
                for &p in &pen {
                    ring[1].pairs[p].mode = PairMode::Hold;
                }
                if immediate > MAX_RESOLVES {
                    self.pen_saved = pen;
                    return Ok(());
                }
            }
            // Give the buffer back (no allocation in the loop).
            self.pen_saved = pen;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braking_then_holding_lands_on_the_obstacle_eqs_26_27() {
        // Fixed wall at x_c in 1D written with n = +1 (p = x).
        let (x_c, h, beta) = (0.5, 0.1, 0.2);
        let (xm1, vm1) = (0.32, 1.3);
        let v0 = braking_velocity(x_c, xm1, vm1, 0.0, h, beta);
        assert!((v0 - ((x_c - xm1) / h - (1.0 - beta) * vm1)).abs() < 1e-14);
        let x0 = xm1 + h * ((1.0 - beta) * vm1 + beta * v0);
        // Eq. (27).
        let x0_27 = (1.0 - beta) * xm1 + beta * x_c + (1.0 - beta).powi(2) * h * vm1;
        assert!((x0 - x0_27).abs() < 1e-14);
        // The holding step gives v1 = 0 and x1 = x_cont.
        let v1 = holding_velocity(x_c, x0, v0, 0.0, h, beta);
        assert!(v1.abs() < 1e-12);
        let x1 = x0 + h * ((1.0 - beta) * v0 + beta * v1);
        assert!((x1 - x_c).abs() < 1e-14);
    }

    #[test]
    fn holding_removes_a_velocity_error_instead_of_amplifying_it() {
        // On the wall with a small velocity error: the old zero-gap law multiplied it by
        // -(1-beta)/beta each step; the deadbeat law clears gap and error in two steps.
        let (x_c, h, beta) = (0.5, 0.01, 0.2);
        let (mut x, mut v) = (x_c, 1e-6);
        for _ in 0..50 {
            let v1 = holding_velocity(x_c, x, v, 0.0, h, beta);
            x += h * ((1.0 - beta) * v + beta * v1);
            v = v1;
        }
        assert!(
            v.abs() < 1e-12 && (x - x_c).abs() < 1e-15,
            "v {v:e}, gap {:e}",
            x - x_c
        );
    }

    #[test]
    fn moving_obstacle_arrival_has_the_obstacle_velocity() {
        let (h, beta, w) = (0.01, 0.3, -0.7);
        let (pm1, qm1) = (0.0, 2.0);
        let c1 = 0.035;
        let q0 = braking_velocity(c1, pm1, qm1, w, h, beta);
        let p0 = pm1 + h * ((1.0 - beta) * qm1 + beta * q0);
        let q1 = holding_velocity(c1, p0, q0, w, h, beta);
        assert!((q1 - w).abs() < 1e-10);
    }
}
