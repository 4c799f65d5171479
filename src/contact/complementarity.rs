//! Contact as one complementarity problem per step, for every integrator: exact enforcement
//! with the generalized-alpha family, penalty, Moreau-Jean, and mass redistribution (exact
//! enforcement after the contact nodes were made massless).
//!
//! With the integrator's maps (`u1 = U + mu_u x`, `v1 = V + mu_v x`, [`crate::time::integrator`])
//! each pair's condition is one unilateral row `y = y0 + mu c.x + reg lambda`
//! ([`crate::contact::rows`]), the geometry taken at the step end `t1`:
//!
//! - **Exact**, generalized-alpha family: the gap at the step end, `y = g(U) + mu_u c.x`
//!   (Signorini at the displacement level; Carpenter, Taylor & Katona 1991). Central
//!   difference (`u1` does not depend on `a1`): Carpenter's forward-increment multiplier, the
//!   force at `t1` keeps the *next* position `u1 + h v1 + h^2 a1/2` out of the obstacle,
//!   `y = g(U) + h (c.V - w) + (h mu_v + h^2/2) c.x`.
//! - **Penalty** with the stiffness `k_pen` (N/m): the force `k_pen max(0, -g)` with the gap
//!   taken where the integrator evaluates `K u` ([`crate::time::integrator::TimeIntegrator::stiffness_point`]),
//!   so the spring is integrated like the elastic forces: `y = g(P) + mu_k c.x + lambda f /
//!   k_pen` (`f` the force per unit multiplier). With the central difference it is the
//!   classic explicit penalty, stable while `h sqrt(k_pen/m_node) < 2`. The stored energy
//!   `k_pen g^2/2` (end gap) is reported.
//! - **Moreau-Jean** (Moreau 1988, Jean 1999): a pair is a candidate in a step when its gap
//!   predicted half a step ahead, `g(u0) + h/2 (c.v0 - w)`, is <= 0; a candidate obeys
//!   Newton's law at the velocity level, `y = (c.v1 - w) + e (c.v0 - w) >= 0` with the
//!   restitution `e`. Positions are not enforced: a drift of order `h |v|` remains.
//!
//! **Candidate search.** Only the pairs that can carry a reaction get a row: those held in
//! the previous step (read from the start state's [`crate::model::PairState::held`]: the
//! treatment keeps no pair state of its own between steps, so whatever restores or relabels
//! the state, a step back or a moving zone, restores or relabels this too), and those whose condition in the free step, `y_free = y0 + mu
//! c.x_free`, is below the margin `max(0, -min_p y_free)` (the deepest predicted violation:
//! the reactions of the violated pairs move their neighbours by amounts of that order).
//! After the solve every other pair's condition is evaluated at the solution, `y0 + mu c.x`;
//! a violated one joins the candidates and the interval is solved again. The solution then
//! satisfies the rows of every pair (the others carry `lambda = 0` with `y >= -tol`), so it
//! is the all-pairs solution (the same active set; the tests compare the two to 1e-12 on the
//! wheel and the bar), while the dense system and the cached columns
//! ([`crate::contact::rows`]) hold the few candidates instead of every contact pair: on the
//! converged wheel (288 rim nodes) a handful of rows instead of a 288 x 288 system per step.
//!
//! **Friction** (coefficient `mu > 0`, 2D): beside each pair's normal row, a bounded row on
//! the pair's tangent `c_t` with `y = (c_t.V - w_t) + mu_v c_t.x`, the slip velocity at the
//! step end, and `|lambda_t| <= mu lambda_n` ([`crate::contact::rows`]): stick (the slip
//! velocity at `t1` is zero) or slip (the force `mu lambda_n` opposes it). The multipliers of
//! the two rows have the same unit, so the bound is the same with forces (exact, penalty) and
//! impulses (Moreau-Jean with the space-time scheme).

use super::context::{ContactError, Context};
use super::friction::{push_rows as push_friction_rows, spring_energy, tangent_index, FrictionLaw};
use super::rows::{Row, RowKind};
use super::treatment::{plain_state, record_friction, ContactTreatment};
use crate::model::Snapshot;
use crate::time::integrator::Maps;

/// The contact law of a [`Complementarity`] treatment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Exact enforcement (displacement level; forward increment for the explicit method).
    Exact,
    /// Penalty with the stiffness in N/m.
    Penalty {
        /// N/m.
        stiffness: f64,
    },
    /// Moreau-Jean with Newton's restitution.
    MoreauJean {
        /// In [0, 1].
        restitution: f64,
    },
}

/// Exact (generalized-alpha family), penalty, Moreau-Jean and mass redistribution.
#[derive(Debug, Clone)]
pub struct Complementarity {
    law: Law,
    point: Vec<f64>,
    vel_tol: Option<f64>,
    friction: Option<FrictionLaw>,
    /// The tangential surface velocity of each pair in the last solve along its tangents,
    /// m/s.
    wt: Vec<[f64; 2]>,
    /// Pose rows for the candidate pairs only (module docs); `false`: every pair.
    search: bool,
    /// Per pair: the row posed in this step (kind of law applied), `None` when the pair is
    /// out of the problem (Moreau-Jean's non-candidates).
    posed: Vec<Option<PairRow>>,
    /// Per pair: a candidate of the current solve.
    candidate: Vec<bool>,
}

/// A pair's normal row of one step, before the search decides whether it is posed.
#[derive(Debug, Clone, Copy)]
struct PairRow {
    row: Row,
    /// The tangential rows' `c_t` and the surface's tangential velocity `w_t` (friction):
    /// one in 2D, two in 3D.
    tangents: [Option<(crate::model::Terms, f64)>; 2],
}

impl Complementarity {
    /// For `pairs` contact pairs of a model of `n` dofs.
    pub fn new(law: Law, pairs: usize, n: usize) -> Self {
        Self {
            law,
            point: vec![0.0; n],
            vel_tol: None,
            friction: None,
            wt: vec![[0.0; 2]; pairs],
            search: true,
            posed: vec![None; pairs],
            candidate: vec![false; pairs],
        }
    }

    /// With friction of law `law` (`None` or zero: frictionless).
    pub fn with_friction(mut self, law: Option<FrictionLaw>) -> Self {
        self.friction = law.filter(FrictionLaw::is_active);
        self
    }

    /// The stick's tangential stiffness, N/m per pair: the law's, else the normal penalty
    /// stiffness for the penalty treatment, else 0 (a rigid stick;
    /// [`super::friction`]: elastic stick).
    pub fn stick_stiffness(&self) -> f64 {
        match (self.friction, self.law) {
            (Some(f), _) if f.tangential_stiffness > 0.0 => f.tangential_stiffness,
            (Some(_), Law::Penalty { stiffness }) => stiffness,
            _ => 0.0,
        }
    }
}

impl Complementarity {
    /// Poses each pair's rows at the step's end (module docs: the law's `y0`, `mu`, `reg`,
    /// the tangent with friction), or none for a Moreau-Jean pair not about to touch, and
    /// marks the candidates; returns the tolerance of the solve.
    fn pose(
        &mut self,
        ctx: &mut Context<'_>,
        fs: &Snapshot,
        (maps, explicit, mu_k, vel_tol): (Maps, bool, f64, f64),
    ) -> f64 {
        let h = ctx.integ.h();
        let (t0, t1) = (fs.t, fs.t + h);
        let mut tol = ctx.gap_tol;
        let mut margin = 0.0_f64;
        for p in 0..self.posed.len() {
            let geo = ctx.geometry(p, t1, &ctx.pred.u);
            let (y0, mu, reg) = match self.law {
                Law::Penalty { stiffness } => {
                    let g = geo.gap(ctx.reference, &self.point);
                    (g, mu_k, maps.force / stiffness)
                }
                Law::MoreauJean { restitution } => {
                    let g0 = ctx.geometry(p, t0, &fs.u);
                    let gn = g0.terms.dot(&fs.v) - g0.w;
                    if g0.gap(ctx.reference, &fs.u) + 0.5 * h * gn > 0.0 {
                        self.posed[p] = None;
                        continue;
                    }
                    tol = vel_tol;
                    (
                        geo.terms.dot(&ctx.pred.v) - geo.w + restitution * gn,
                        maps.mu_v,
                        0.0,
                    )
                }
                Law::Exact if explicit => {
                    // Forward increment: the next position u1 + h v1 + h^2 a1 / 2.
                    let gh = geo.gap(ctx.reference, &ctx.pred.u)
                        + h * (geo.terms.dot(&ctx.pred.v) - geo.w);
                    (gh, h * maps.mu_v + 0.5 * h * h, 0.0)
                }
                Law::Exact => (geo.gap(ctx.reference, &ctx.pred.u), maps.mu_u, 0.0),
            };
            let row = Row {
                pair: p,
                terms: geo.terms,
                kind: RowKind::Unilateral,
                y0,
                mu,
                reg,
            };
            let mut tangents = [None; 2];
            if self.friction.is_some() {
                for (k, slot) in tangents.iter_mut().enumerate() {
                    *slot = ctx
                        .tangent(p, t1, &ctx.pred.u, k)
                        .map(|tg| (tg.terms, tg.w));
                }
            }
            self.posed[p] = Some(PairRow { row, tangents });
            let y_free = y0 + mu * geo.terms.dot(ctx.xfree);
            margin = margin.max(-y_free);
            self.candidate[p] = !self.search || fs.pairs[p].held || y_free < -tol;
        }
        // Candidates: held, violated, or within the margin of the deepest violation.
        if self.search {
            for p in 0..self.posed.len() {
                if let Some(pr) = self.posed[p] {
                    let y_free = pr.row.y0 + pr.row.mu * pr.row.terms.dot(ctx.xfree);
                    if y_free < margin {
                        self.candidate[p] = true;
                    }
                }
            }
        }
        tol
    }

    /// Solves the candidates' rows, adding any pair left out that the solution violates,
    /// until none is; returns the active-set changes.
    fn solve_candidates(
        &mut self,
        ctx: &mut Context<'_>,
        fs: &Snapshot,
        maps: Maps,
        tol: f64,
    ) -> usize {
        let h = ctx.integ.h();
        let kt = self.stick_stiffness();
        let mut changes = 0;
        loop {
            ctx.rows.clear();
            for p in 0..self.posed.len() {
                let Some(pr) = self.posed[p] else { continue };
                if !self.candidate[p] {
                    continue;
                }
                let normal = ctx.rows.push(pr.row);
                if let (Some(law), Some(_)) = (self.friction, pr.tangents[0]) {
                    self.wt[p] = pr.tangents.map(|t| t.map_or(0.0, |(_, w)| w));
                    let f0 = [fs.pairs[p].tangential_force, fs.pairs[p].tangential_force_2];
                    push_friction_rows(
                        ctx.rows,
                        &law,
                        (p, normal),
                        pr.tangents,
                        (&fs.v, &ctx.pred.v),
                        (kt, f0, fs.pairs[p].friction_coefficient),
                        (maps, h),
                    );
                }
            }
            changes += ctx.solve(tol);
            // Every pair left out must hold at the solution (module docs).
            let mut added = false;
            for p in 0..self.posed.len() {
                let Some(pr) = self.posed[p] else { continue };
                if !self.candidate[p] && pr.row.y0 + pr.row.mu * pr.row.terms.dot(ctx.x) < -tol {
                    self.candidate[p] = true;
                    added = true;
                }
            }
            if !added {
                break;
            }
        }
        changes
    }

    /// The pairs' states at the step's end: gaps, forces, friction, entries and releases.
    fn record(&mut self, ctx: &mut Context<'_>, fs: &Snapshot, ts: &mut Snapshot, force: f64) {
        let h = ctx.integ.h();
        let t1 = ts.t;
        let kt = self.stick_stiffness();
        for p in 0..self.posed.len() {
            ts.pairs[p] = plain_state(0.0, false, ctx.gap(p, t1, &ts.u));
            ts.pairs[p].dissipated = fs.pairs[p].dissipated;
            ts.pairs[p].friction_coefficient = fs.pairs[p].friction_coefficient;
        }
        for (i, row) in ctx.rows.rows().iter().enumerate() {
            let lam = ctx.rows.lambda()[i];
            if let RowKind::Bounded { .. } = row.kind {
                // The slip rate at t1 on which the row posed the law (the row's `y`).
                let k = tangent_index(ctx.rows.rows(), i);
                let slip = row.terms.dot(&ts.v) - self.wt[row.pair][k];
                let sliding = ctx.rows.is_sliding(i);
                let prev = &fs.pairs[row.pair];
                let f0 = [prev.tangential_force, prev.tangential_force_2][k];
                record_friction(
                    &mut ts.pairs[row.pair],
                    (k, lam * force),
                    sliding,
                    slip,
                    h,
                    (kt, f0),
                );
                continue;
            }
            ts.pairs[row.pair].force = lam * force * h / h;
            ts.pairs[row.pair].held = lam > 0.0;
        }
        // A friction memory's state (module docs of `super::friction`, Memory) on the pairs
        // in contact with friction rows; a candidate the solve left without a reaction is
        // out of contact and keeps its state, as in the soft way.
        if let Some(law) = self.friction.filter(|l| l.memory > 0.0) {
            for p in 0..self.posed.len() {
                let Some(pr) = self.posed[p] else { continue };
                if !self.candidate[p] || !ts.pairs[p].held || pr.tangents[0].is_none() {
                    continue;
                }
                let slips = pr
                    .tangents
                    .map(|t| t.map_or(0.0, |(c, w)| c.dot(&ts.v) - w));
                ts.pairs[p].friction_coefficient =
                    law.remember(fs.pairs[p].friction_coefficient, slips, h);
            }
        }
        for p in 0..self.posed.len() {
            let (was, now) = (fs.pairs[p].held, ts.pairs[p].held);
            if now && !was {
                ctx.counts.entries += 1;
            }
            if was && !now {
                ctx.counts.releases += 1;
            }
        }
    }
}

impl ContactTreatment for Complementarity {
    fn name(&self) -> String {
        match self.law {
            Law::Exact => "exact".into(),
            Law::Penalty { stiffness } => format!("penalty({stiffness:e})"),
            Law::MoreauJean { restitution } => format!("moreau_jean({restitution})"),
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
        ctx.extra.fill(0.0);
        let step = ctx.predict(t0, &fs.state);
        let maps = step.maps;
        let explicit = step.explicit;
        // Moreau-Jean's tolerance on velocities (m/s), from the initial speeds, once.
        let vel_tol = *self
            .vel_tol
            .get_or_insert_with(|| 1e-12 * fs.v.iter().fold(1e-300_f64, |a, v| a.max(v.abs())));
        let mu_k = match self.law {
            Law::Penalty { .. } => ctx
                .integ
                .stiffness_point(&fs.state, ctx.pred, &mut self.point),
            _ => 0.0,
        };
        let tol = self.pose(ctx, fs, (maps, explicit, mu_k, vel_tol));
        let changes = self.solve_candidates(ctx, fs, maps, tol);
        ctx.counts.resolves += changes;
        ctx.finish(&step, &fs.state, &mut ts.state);
        ts.t = t1;
        ts.k = fs.k + 1;
        self.record(ctx, fs, ts, maps.force);
        Ok(())
    }

    fn set_candidate_search(&mut self, on: bool) {
        self.search = on;
    }

    fn stored_energy(&self, s: &Snapshot) -> f64 {
        let kt = self.stick_stiffness();
        let springs: f64 = s
            .pairs
            .iter()
            .map(|p| {
                spring_energy(kt, p.tangential_force) + spring_energy(kt, p.tangential_force_2)
            })
            .sum();
        springs
            + match self.law {
                Law::Penalty { stiffness } => s
                    .pairs
                    .iter()
                    .map(|p| 0.5 * stiffness * p.gap.min(0.0).powi(2))
                    .sum(),
                _ => 0.0,
            }
    }
}
