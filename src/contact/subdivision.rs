//! The paper's other way (§3, Fig. 5; space-time only): the step in which a pair enters
//! contact is cut at the instant `t_c` of arrival, found by the secant method on the end gap
//! of the sub-step (`|g(t_c)| <= gap_tol`); the pair's normal velocity jumps to the
//! boundary's at `t_c` (an impulse through `M^{-1}`: Fig. 6), and the rest of the step is
//! solved with the pair held; a held pair whose multiplier turns tensile is released at the
//! instant `t_f` where its force, interpolated linearly over the step, is zero. Each sub-step
//! has its own length, hence its own numeric factorization of `A`
//! ([`crate::time::integrator::TimeIntegrator::set_step`], on the run's one symbolic
//! analysis): the cost the soft way avoids. Outputs stay on the regular grid.
//!
//! A held pair's row over a sub-step of length `h_s` asks the end gap to vanish in the
//! deadbeat way of [`super::softway`]: `y = g(U) + h_s c.x = 0`, i.e.
//! `c.v1 = -g(U)/h_s` with `U = u0 + h_s (1 - beta) v0`.

use super::context::{ContactError, Context};
use super::rows::{Row, RowKind};
use super::treatment::{plain_state, ContactTreatment};
use crate::linalg::SparseLu;
use crate::model::Snapshot;
use crate::model::State;

/// The subdivision treatment (module docs).
#[derive(Debug)]
pub struct Subdivision {
    held: Vec<bool>,
    force: Vec<f64>,
    impulse: Vec<f64>,
    lam: Vec<f64>,
    lam_keep: Vec<f64>,
    cur: State,
    mass_lu: Option<SparseLu>,
    minv_c: Vec<f64>,
}

impl Subdivision {
    /// For `pairs` contact pairs.
    pub fn new(pairs: usize) -> Self {
        Self {
            held: vec![false; pairs],
            force: vec![0.0; pairs],
            impulse: vec![0.0; pairs],
            lam: vec![0.0; pairs],
            lam_keep: vec![0.0; pairs],
            cur: State::zeros(0),
            mass_lu: None,
            minv_c: Vec::new(),
        }
    }

    /// Solves `[t, t + h_s]` from `s0` into `s1` with the held pairs held, `h_s` the
    /// integrator's current step; the multipliers go to `self.lam`.
    fn solve_held(&mut self, ctx: &mut Context<'_>, t: f64, s0: &State, s1: &mut State) {
        let hs = ctx.integ.h();
        ctx.extra.fill(0.0);
        let step = ctx.predict(t, s0);
        ctx.rows.clear();
        for p in 0..self.held.len() {
            if !self.held[p] {
                continue;
            }
            let geo = ctx.geometry(p, t + hs, &ctx.pred.u);
            ctx.rows.push(Row {
                pair: p,
                terms: geo.terms,
                kind: RowKind::Equality,
                y0: geo.gap(ctx.reference, &ctx.pred.u),
                mu: hs,
                reg: 0.0,
            });
        }
        ctx.solve(0.0);
        self.lam.fill(0.0);
        for (i, row) in ctx.rows.rows().iter().enumerate() {
            self.lam[row.pair] = ctx.rows.lambda()[i];
        }
        ctx.finish(&step, s0, s1);
    }

    /// A sub-step `[t, t + len]` from `cur` into `s1`, with its own factorization.
    fn sub_step(
        &mut self,
        ctx: &mut Context<'_>,
        t: f64,
        len: f64,
        s1: &mut State,
    ) -> Result<(), ContactError> {
        ctx.set_step(len)?;
        let cur = std::mem::replace(&mut self.cur, State::zeros(0));
        self.solve_held(ctx, t, &cur, s1);
        self.cur = cur;
        Ok(())
    }

    /// The velocity jump of pair `p` at `t` on the state `cur`: `M dv = c^T P` with
    /// `c.(v + dv) = w`; returns the impulse `P`, N s.
    fn jump(&mut self, ctx: &Context<'_>, p: usize, t: f64) -> Result<f64, ContactError> {
        let n = self.cur.v.len();
        if self.mass_lu.is_none() {
            self.mass_lu = Some(SparseLu::new(ctx.model.pattern(), &ctx.model.m)?);
            self.minv_c = vec![0.0; n];
        }
        let geo = ctx.geometry(p, t, &self.cur.u);
        self.minv_c.fill(0.0);
        geo.terms.scatter(1.0, &mut self.minv_c);
        if let Some(lu) = self.mass_lu.as_mut() {
            lu.solve_in_place(&mut self.minv_c);
        }
        let pimp = (geo.w - geo.terms.dot(&self.cur.v)) / geo.terms.dot(&self.minv_c);
        for (vi, ci) in self.cur.v.iter_mut().zip(&self.minv_c) {
            *vi += pimp * ci;
        }
        Ok(pimp)
    }
}

impl ContactTreatment for Subdivision {
    fn name(&self) -> String {
        "subdivision".into()
    }

    fn solve_interval(
        &mut self,
        ctx: &mut Context<'_>,
        fs: &Snapshot,
        ts: &mut Snapshot,
    ) -> Result<(), ContactError> {
        let k = self.held.len();
        let h = ctx.h;
        let t0 = fs.t;
        let t1 = t0 + h;
        if self.cur.u.len() != fs.u.len() {
            self.cur = fs.state.clone();
        }
        self.impulse.fill(0.0);
        // The force of each pair at the start (for locating a release).
        for p in 0..k {
            self.force[p] = fs.pairs[p].force;
        }
        self.cur.u.copy_from_slice(&fs.u);
        self.cur.v.copy_from_slice(&fs.v);
        self.cur.a.copy_from_slice(&fs.a);
        let mut t = t0;
        let mut done_by_substeps = true;
        for _ in 0..4 * k + 4 {
            let rem = t1 - t;
            if rem <= 1e-12 * h {
                break;
            }
            let len = if (rem - h).abs() <= 1e-12 * h { h } else { rem };
            ctx.set_step(len)?;
            let cur = std::mem::replace(&mut self.cur, State::zeros(0));
            self.solve_held(ctx, t, &cur, &mut ts.state);
            self.cur = cur;
            // Release: the first held pair whose force crosses zero.
            let mut rel: Option<(usize, f64)> = None;
            for p in 0..k {
                if self.held[p] && self.lam[p] < 0.0 {
                    let fe = self.lam[p] / rem;
                    let fs0 = self.force[p].max(0.0);
                    let th = if fs0 > 0.0 { fs0 / (fs0 - fe) } else { 0.0 };
                    if rel.is_none_or(|(_, v)| th < v) {
                        rel = Some((p, th));
                    }
                }
            }
            if let Some((p, th)) = rel {
                ctx.counts.releases += 1;
                if th * rem > 1e-9 * h {
                    self.sub_step(ctx, t, th * rem, &mut ts.state)?;
                    // Keep the held part only if it stayed compressive; otherwise the
                    // force crossed zero earlier than interpolated: release at `t`.
                    if self.lam[p] >= 0.0 {
                        for q in 0..k {
                            self.impulse[q] += self.lam[q];
                        }
                        self.cur.u.copy_from_slice(&ts.u);
                        self.cur.v.copy_from_slice(&ts.v);
                        t += th * rem;
                    }
                }
                self.held[p] = false;
                continue;
            }
            // Entry: the free pair penetrating first.
            let mut ent: Option<(usize, f64)> = None;
            for p in 0..k {
                if self.held[p] {
                    continue;
                }
                let g1 = ctx.gap(p, t + rem, &ts.u);
                if g1 < -ctx.gap_tol {
                    let g0 = ctx.gap(p, t, &self.cur.u).max(0.0);
                    let th = g0 / (g0 - g1);
                    if ent.is_none_or(|(_, v)| th < v) {
                        ent = Some((p, th));
                    }
                }
            }
            let Some((p, th0)) = ent else {
                for q in 0..k {
                    self.impulse[q] += self.lam[q];
                }
                done_by_substeps = false;
                break;
            };
            // Secant on the end gap of the sub-step [t, t + th rem].
            let g0 = ctx.gap(p, t, &self.cur.u);
            let (mut ta, mut ga) = (0.0, g0);
            let (mut tb, mut gb) = (1.0, ctx.gap(p, t + rem, &ts.u));
            let mut th = th0.clamp(0.0, 1.0);
            for _ in 0..12 {
                if th * rem <= 1e-9 * h {
                    th = 0.0;
                    ts.state.u.copy_from_slice(&self.cur.u);
                    ts.state.v.copy_from_slice(&self.cur.v);
                    self.lam_keep.fill(0.0);
                    break;
                }
                self.sub_step(ctx, t, th * rem, &mut ts.state)?;
                self.lam_keep.copy_from_slice(&self.lam);
                let g = ctx.gap(p, t + th * rem, &ts.u);
                if g.abs() <= ctx.gap_tol {
                    break;
                }
                if g > 0.0 {
                    (ta, ga) = (th, g);
                } else {
                    (tb, gb) = (th, g);
                }
                th = ta + (tb - ta) * ga / (ga - gb);
            }
            for q in 0..k {
                self.impulse[q] += self.lam_keep[q];
            }
            self.cur.u.copy_from_slice(&ts.u);
            self.cur.v.copy_from_slice(&ts.v);
            t += th * rem;
            let pimp = self.jump(ctx, p, t)?;
            self.impulse[p] += pimp.max(0.0);
            self.held[p] = true;
            ctx.counts.entries += 1;
        }
        if done_by_substeps {
            // Finished by sub-steps: the state is in `cur`.
            ts.state.u.copy_from_slice(&self.cur.u);
            ts.state.v.copy_from_slice(&self.cur.v);
        }
        ctx.set_step(h)?;
        ts.t = t1;
        ts.k = fs.k + 1;
        for p in 0..k {
            let force = self.impulse[p] / h;
            let active = self.impulse[p] != 0.0 || self.held[p];
            ts.pairs[p] = plain_state(force, active, ctx.gap(p, t1, &ts.u));
        }
        Ok(())
    }
}
