//! The contact laboratory: every time integrator with every contact treatment on the same
//! model, for contacts whose gap is a linear function of the displacements (a node against
//! a fixed plane, two nodes facing each other). The soft way itself runs in
//! [`crate::simulation`]; this module holds the treatments it is compared with.
//!
//! # Gaps, reactions, units
//!
//! Pair `p` has the gap `g_p(u) = d_p + c_p . u` (m; positive: open) with a constant row `c_p`
//! (a node against a wall: `-1` on the node's dof; node `a` facing node `b`: `-1` on `a`,
//! `+1` on `b`). Its reaction enters the balance as `c_p^T lambda_p`: a compressive
//! reaction has `lambda_p >= 0`. Every integrator is, for one step, `A x = b + c^T lambda`
//! with a constant, factored `A` and an unknown `x` that fixes the end state linearly:
//!
//! | integrator | `x` | `u1` | `v1` | `lambda` | force |
//! |---|---|---|---|---|---|
//! | space-time (Eqs. 6-10) | `v1` | `u0 + h(1-beta)v0 + h beta x` | `x` | impulse, N s | `lambda / h` |
//! | Newmark family ([`crate::time::classic`]) | `a1` | `u* + beta_N h^2 x` | `v* + gamma_N h x` | force, N | `lambda` |
//!
//! so `x = x_free + sum_q z_q lambda_q` with the columns `z_q = A^{-1} c_q^T` computed once,
//! and every contact condition below is a small linear complementarity problem on the pairs:
//! `y = y_0 + W lambda >= 0`, `lambda >= 0`, `y . lambda = 0`, solved exactly by an active
//! set (`W = mu S`, `S_pq = c_p . z_q`). The contact force reported for a step is the
//! force of the table (for the space-time scheme: the impulse of the step over `h`).
//!
//! # Treatments
//!
//! - **Exact** (Lagrange multiplier, no braking, no momentum given back).
//!   - Newmark family: the gap at the step end, `y = g(u1) = g(u*) + beta_N h^2 c.x`
//!     (Signorini at the displacement level; Carpenter, Taylor & Katona 1991).
//!   - Central difference (`beta_N = 0`, `u1` does not depend on `a1`): the forward-increment
//!     Lagrange multiplier of Carpenter et al.: the force at `t1` keeps the *next* position
//!     `u1 + h v1 + h^2 a1 / 2` out of the obstacle, `y = g(u1 + h v*) + h^2 (gamma_N + 1/2)
//!     c.x`.
//!   - Space-time: as [`crate::contact::ContactMethod::Exact`]: a pair whose end gap is
//!     negative is held from the start of that step with `c.v1 = -g*/h`, `g*` the end gap
//!     if `c.v1` were 0 (the deadbeat hold of [`crate::contact::softway`]), and released when
//!     its multiplier turns tensile. Asking `g(u1) = 0` directly needs `c.v1 = -g*/(h beta)`
//!     and amplifies velocity errors by `-(1-beta)/beta` per step.
//! - **Penalty** with the stiffness `k_pen` (N/m): the force `k_pen max(0, -g)`, with the gap
//!   taken where the integrator evaluates its elastic forces `K u`, so the spring is
//!   integrated exactly like the bar: space-time `u0 + h (alpha - alpha^2/2) v0 +
//!   h alpha^2/2 v1` (the `K` terms of Eq. 9); Newmark family: the step end `u1`. As a
//!   complementarity problem:
//!   `y = g + lambda fs / k_pen`, `fs` the force per unit `lambda`. For the central
//!   difference (`u1` known before `a1`) this is the classic explicit penalty, stable only
//!   while `h sqrt(k_pen / m_node) < 2`. The penalty energy `k_pen g^2 / 2` (end gap) is
//!   counted in the total energy. Tends to Exact as `k_pen` grows.
//! - **Mass redistribution** (Khenous, Laborde & Renard 2008): the contact nodes carry no
//!   mass ([`redistribute_mass`]) and the contact is then enforced exactly as above. A
//!   massless node has no kinetic energy to lose at impact. Needs an implicit integrator
//!   (the explicit matrix `M` would be singular).
//! - **Moreau-Jean** (velocity-level impulses, Moreau 1988, Jean 1999): a pair is active in a
//!   step when its gap predicted half a step ahead, `g(u0) + h/2 c.v0`, is <= 0; an active
//!   pair obeys Newton's law at the velocity level, `y = c.v1 + e c.v0 >= 0` with the
//!   restitution `e` in [0, 1] (default 0). Positions are not enforced: a drift of order
//!   `h |v|` remains, and the impact takes the node's relative normal velocity.
//! - **Subdivision** (the paper's other way, §3, Fig. 5; space-time only): the step in which
//!   a pair enters contact is cut at the instant `t_c` of arrival, found by the secant method
//!   on the end gap of the sub-step (`|g(t_c)| <= gap_tol`), the node's normal velocity jumps
//!   to zero at `t_c` (an impulse through `M^{-1}`: Fig. 6), and the rest of the step is
//!   solved with the pair held; a held pair whose multiplier turns tensile is released at
//!   the instant `t_f` where its force, interpolated linearly over the step, is zero. Each
//!   sub-step has its own `h`, hence its own factorization of `A`: the cost the soft way
//!   avoids. Outputs stay on the regular grid.

use crate::linalg::{quadratic_form, LinalgError, Pattern, SparseLu};
use crate::simulation::LoadFn;
use crate::time::classic::{
    initial_acceleration, ClassicError, ClassicParams, ClassicStepper, Dirichlet, Kinematic, State,
};
use crate::time::params::beta as st_beta;
use crate::time::step::{dense_solve_in_place, LinearModel, Stepper};
use crate::time::SpaceTimeParams;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};

/// A time integrator of the laboratory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Integrator {
    /// The space-time velocity scheme (Eqs. 6-10, 24).
    SpaceTime {
        /// `alpha` in (0, 1].
        alpha: f64,
        /// `gamma` in [0, 1].
        gamma: f64,
    },
    /// A member of the generalized-alpha family ([`crate::time::classic`]).
    Classic {
        /// Short name: `newmark`, `newmark_dissipative`, `hht`, `generalized_alpha`,
        /// `central_difference`.
        kind: ClassicKind,
        /// Its parameters.
        params: ClassicParams,
    },
}

/// The classic integrators by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ClassicKind {
    /// Newmark average acceleration (`beta = 1/4`, `gamma = 1/2`).
    Newmark,
    /// Newmark with `gamma_N > 1/2`.
    NewmarkDissipative,
    /// HHT-alpha.
    Hht,
    /// Generalized-alpha (Chung-Hulbert).
    GeneralizedAlpha,
    /// Explicit central difference.
    CentralDifference,
}

impl Integrator {
    /// The name used in tables.
    pub fn name(&self) -> String {
        match self {
            Integrator::SpaceTime { alpha, gamma } => {
                format!("space_time(alpha={alpha} gamma={gamma})")
            }
            Integrator::Classic { kind, params } => match kind {
                ClassicKind::Newmark => "newmark".into(),
                ClassicKind::NewmarkDissipative => format!("newmark({:.2})", params.gamma),
                ClassicKind::Hht => format!("hht({:.3})", -params.alpha_f),
                ClassicKind::GeneralizedAlpha => {
                    format!("gen_alpha({:.2})", crate::time::classic::rho_inf(*params))
                }
                ClassicKind::CentralDifference => "central_difference".into(),
            },
        }
    }

    /// True for the explicit central difference.
    pub fn is_explicit(&self) -> bool {
        matches!(self, Integrator::Classic { params, .. } if params.is_explicit())
    }
}

/// A contact treatment of the laboratory (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Treatment {
    /// Exact enforcement by a Lagrange multiplier.
    Exact,
    /// Penalty.
    Penalty {
        /// Penalty stiffness, N/m.
        stiffness: f64,
    },
    /// Massless contact nodes, then exact enforcement.
    MassRedistribution,
    /// Velocity-level impulses with Newton's restitution.
    MoreauJean {
        /// Restitution coefficient in [0, 1].
        restitution: f64,
    },
    /// Sub-steps at the instants of entering and leaving contact (space-time only).
    Subdivision,
}

impl Treatment {
    /// The name used in tables.
    pub fn name(&self) -> String {
        match self {
            Treatment::Exact => "exact".into(),
            Treatment::Penalty { stiffness } => format!("penalty({stiffness:e})"),
            Treatment::MassRedistribution => "mass_redistribution".into(),
            Treatment::MoreauJean { restitution } => format!("moreau_jean({restitution})"),
            Treatment::Subdivision => "subdivision".into(),
        }
    }
}

/// A gap linear in the displacements: `g(u) = offset + sum coef u[dof]`, m.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearGap {
    /// `(dof, coefficient)`.
    pub terms: Vec<(usize, f64)>,
    /// The gap at `u = 0`, m.
    pub offset: f64,
}

impl LinearGap {
    /// `c . x` (no offset).
    pub fn dot(&self, x: &[f64]) -> f64 {
        self.terms.iter().map(|&(d, c)| c * x[d]).sum()
    }
    /// `g(u)`, m.
    pub fn eval(&self, u: &[f64]) -> f64 {
        self.offset + self.dot(u)
    }
}

/// Everything a laboratory run needs.
pub struct LabProblem {
    /// The semi-discrete model (before any mass redistribution).
    pub model: LinearModel,
    /// Dofs held at zero velocity.
    pub fixed: Vec<usize>,
    /// External load.
    pub load: LoadFn,
    /// The contact pairs' gaps.
    pub gaps: Vec<LinearGap>,
    /// Initial displacement, m.
    pub u0: Vec<f64>,
    /// Initial velocity, m/s.
    pub v0: Vec<f64>,
    /// Start time, s.
    pub t0: f64,
    /// Time step, s.
    pub h: f64,
    /// Number of steps.
    pub steps: usize,
    /// The integrator.
    pub integrator: Integrator,
    /// The contact treatment.
    pub treatment: Treatment,
    /// A gap below `-gap_tol` (m) counts as penetration.
    pub gap_tol: f64,
}

/// Errors of a laboratory run.
#[derive(Debug, thiserror::Error)]
pub enum LabError {
    /// A matrix could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The classic integrator could not be set up.
    #[error(transparent)]
    Classic(#[from] ClassicError),
    /// A combination that does not exist.
    #[error("{0}")]
    Unsupported(String),
    /// The observer failed (writing output).
    #[error("writing results failed: {0}")]
    Output(#[from] std::io::Error),
    /// The solution blew up.
    #[error("the solution is not finite at step {step} (t = {t:e} s): the step is beyond the stability limit of the integrator (with a penalty: of the penalty spring)")]
    NotFinite {
        /// Step.
        step: usize,
        /// Time, s.
        t: f64,
    },
}

/// What the observer sees of a step end.
#[derive(Debug)]
pub struct LabView<'a> {
    /// Step index (0: the initial state).
    pub k: usize,
    /// Time, s.
    pub t: f64,
    /// Displacements, m.
    pub u: &'a [f64],
    /// Velocities, m/s.
    pub v: &'a [f64],
    /// Kinetic energy, J.
    pub kinetic: f64,
    /// Strain energy, J.
    pub strain: f64,
    /// Energy stored in the penalty springs, J.
    pub penalty: f64,
    /// Contact force of each pair over the step, N (compressive > 0).
    pub forces: &'a [f64],
    /// Gap of each pair at the step end, m.
    pub gaps: &'a [f64],
    /// Whether each pair carried a reaction in the step.
    pub active: &'a [bool],
}

/// Counters of a laboratory run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct LabStats {
    /// Steps taken.
    pub steps: usize,
    /// Factorizations of a system matrix (1 for a fixed step; more with subdivision).
    pub factorizations: usize,
    /// Entries into contact.
    pub entries: usize,
    /// Releases.
    pub releases: usize,
    /// Solves of a step beyond the first (active-set changes).
    pub resolves: usize,
    /// True when the run stopped on an interrupt.
    pub interrupted: bool,
}

/// Makes the dofs of `nodes` massless (Khenous, Laborde & Renard 2008): their rows and
/// columns of `M` are zeroed and the mass removed is added to the diagonal of the
/// neighbouring dofs of the same direction (those coupled in the pattern, contact dofs
/// excluded), so the total mass in each direction is kept. Returns the massless dofs.
pub fn redistribute_mass(model: &mut LinearModel, dim: usize, nodes: &[usize]) -> Vec<usize> {
    let n = model.n();
    let mut contact = vec![false; n];
    for &nd in nodes {
        for c in 0..dim {
            contact[dim * nd + c] = true;
        }
    }
    let pattern: Pattern = model.pattern().clone();
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let mut dofs = Vec::new();
    for d in 0..n {
        if !contact[d] {
            continue;
        }
        dofs.push(d);
        // Removed: row d plus column d, the diagonal once.
        let mut removed = 0.0;
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                if i == d || j == d {
                    removed += model.m[p];
                    model.m[p] = 0.0;
                }
            }
        }
        let neighbours: Vec<usize> = (cp[d]..cp[d + 1])
            .map(|p| ri[p])
            .filter(|&i| i != d && !contact[i] && i % dim == d % dim)
            .collect();
        if neighbours.is_empty() {
            continue;
        }
        let share = removed / neighbours.len() as f64;
        for &j in &neighbours {
            for p in cp[j]..cp[j + 1] {
                if ri[p] == j {
                    model.m[p] += share;
                }
            }
        }
    }
    dofs
}

enum Kind {
    St {
        st: Box<Stepper>,
        beta: f64,
        alpha: f64,
    },
    Cl {
        cl: Box<ClassicStepper>,
    },
}

/// One factored step of length `h` with its constraint columns.
struct Engine {
    kind: Kind,
    h: f64,
    n: usize,
    k: usize,
    /// `z_q = A^{-1} c_q^T`, `k` columns of `n`.
    z: Vec<f64>,
    /// `S_pq = c_p . z_q`, row-major `k x k`.
    s: Vec<f64>,
}

impl Engine {
    fn new(
        model: &LinearModel,
        integrator: Integrator,
        h: f64,
        fixed: &[usize],
        gaps: &[LinearGap],
    ) -> Result<Self, LabError> {
        let n = model.n();
        let kind = match integrator {
            Integrator::SpaceTime { alpha, gamma } => {
                let bcs: Vec<(usize, f64)> = fixed.iter().map(|&d| (d, 0.0)).collect();
                let st = Stepper::new(model, 1, SpaceTimeParams { alpha, gamma, h }, &bcs, 0, 0)?;
                Kind::St {
                    st: Box::new(st),
                    beta: st_beta(alpha, gamma),
                    alpha,
                }
            }
            Integrator::Classic { params, .. } => {
                let bcs: Vec<Dirichlet> = fixed
                    .iter()
                    .map(|&d| Dirichlet {
                        dof: d,
                        kind: Kinematic::Velocity,
                        value: 0.0,
                    })
                    .collect();
                let cl = ClassicStepper::new(model, 1, params, h, &bcs, 0, 0)?;
                Kind::Cl { cl: Box::new(cl) }
            }
        };
        let k = gaps.len();
        let mut e = Self {
            kind,
            h,
            n,
            k,
            z: vec![0.0; k * n],
            s: vec![0.0; k * k],
        };
        for q in 0..k {
            let col = &mut e.z[q * n..(q + 1) * n];
            for &(d, c) in &gaps[q].terms {
                col[d] += c;
            }
            match &mut e.kind {
                Kind::St { st, .. } => st.apply_inverse(col),
                Kind::Cl { cl } => cl.apply_inverse(col),
            }
        }
        for p in 0..k {
            for q in 0..k {
                e.s[p * k + q] = gaps[p].dot(&e.z[q * n..(q + 1) * n]);
            }
        }
        Ok(e)
    }

    /// `(mu_u, mu_v, fs)`: `u1 = U + mu_u x`, `v1 = V + mu_v x`, force = `fs lambda`.
    fn maps(&self) -> (f64, f64, f64) {
        match &self.kind {
            Kind::St { beta, .. } => (self.h * beta, 1.0, 1.0 / self.h),
            Kind::Cl { cl } => {
                let p = cl.params();
                (p.beta * self.h * self.h, p.gamma * self.h, 1.0)
            }
        }
    }

    /// The free step from `(t0, s0)`: `pred.u = U`, `pred.v = V`, `x = x_free`.
    fn free(&mut self, load: &LoadFn, t0: f64, s0: &State, w: &mut Work) {
        let h = self.h;
        match &mut self.kind {
            Kind::St { st, beta, alpha } => {
                load(t0 + *alpha * h, &mut w.f0);
                st.rhs_into(&s0.u, &s0.v, &w.f0, &mut w.x);
                st.solve(&mut w.x, &[], &mut []);
                for i in 0..self.n {
                    w.pred.u[i] = s0.u[i] + h * (1.0 - *beta) * s0.v[i];
                    w.pred.v[i] = 0.0;
                }
            }
            Kind::Cl { cl } => {
                load(t0, &mut w.f0);
                load(t0 + h, &mut w.f1);
                cl.predict(s0, &w.f0, &w.f1, &mut w.pred);
                std::mem::swap(&mut w.pred.a, &mut w.x);
            }
        }
    }

    /// `x += sum_q z_q lambda_q`.
    fn correct(&self, x: &mut [f64], lambda: &[f64]) {
        for (q, &l) in lambda.iter().enumerate().take(self.k) {
            if l != 0.0 {
                for (xi, zi) in x.iter_mut().zip(&self.z[q * self.n..(q + 1) * self.n]) {
                    *xi += l * zi;
                }
            }
        }
    }

    /// The end state from `pred` and `x`.
    fn finish(&self, s0: &State, w: &Work, s1: &mut State) {
        let (mu_u, mu_v, _) = self.maps();
        for i in 0..self.n {
            s1.u[i] = w.pred.u[i] + mu_u * w.x[i];
            s1.v[i] = w.pred.v[i] + mu_v * w.x[i];
        }
        match &self.kind {
            Kind::St { .. } => {
                for i in 0..self.n {
                    s1.a[i] = (s1.v[i] - s0.v[i]) / self.h;
                }
            }
            Kind::Cl { .. } => s1.a.copy_from_slice(&w.x),
        }
    }

    /// The gap where the scheme evaluates the internal force `K u`, as `y + mu c.x`:
    /// space-time: `u0 + h (alpha - alpha^2/2) v0 + h alpha^2/2 v1` (Eq. 9's `K` terms);
    /// generalized-alpha family: the step end `u1` (the contact force at `t1`, as in most codes).
    fn stiffness_point(&self, g: &LinearGap, s0: &State, pred: &State) -> (f64, f64) {
        match &self.kind {
            Kind::St { alpha, .. } => {
                let (a, h) = (*alpha, self.h);
                (
                    g.eval(&s0.u) + h * (a - 0.5 * a * a) * g.dot(&s0.v),
                    0.5 * h * a * a,
                )
            }
            Kind::Cl { cl } => {
                let mu = cl.params().beta * self.h * self.h;
                (g.eval(&pred.u), mu)
            }
        }
    }

    fn is_explicit(&self) -> bool {
        matches!(&self.kind, Kind::Cl { cl } if cl.params().is_explicit())
    }
}

struct Work {
    f0: Vec<f64>,
    f1: Vec<f64>,
    x: Vec<f64>,
    pred: State,
    y0: Vec<f64>,
    w: Vec<f64>,
    cand: Vec<bool>,
    lam: Vec<f64>,
    lcp: Lcp,
}

/// Exact active-set solver of `y = y0 + W lambda >= 0, lambda >= 0, y . lambda = 0` on the
/// candidate pairs (the others keep `lambda = 0`) for the few pairs of a contact problem.
#[derive(Debug, Clone)]
struct Lcp {
    act: Vec<bool>,
    idx: Vec<usize>,
    m: Vec<f64>,
    r: Vec<f64>,
}

impl Lcp {
    fn new(k: usize) -> Self {
        Self {
            act: vec![false; k],
            idx: Vec::with_capacity(k),
            m: vec![0.0; k * k],
            r: vec![0.0; k],
        }
    }

    /// Solves the equalities `y_p = 0` on the pairs of `self.act` (the others get
    /// `lambda = 0`).
    fn solve_set(&mut self, w: &[f64], y0: &[f64], lam: &mut [f64]) {
        let k = y0.len();
        self.idx.clear();
        self.idx.extend((0..k).filter(|&p| self.act[p]));
        let m = self.idx.len();
        for (a, &p) in self.idx.iter().enumerate() {
            self.r[a] = -y0[p];
            for (b, &q) in self.idx.iter().enumerate() {
                self.m[a * m + b] = w[p * k + q];
            }
        }
        dense_solve_in_place(&mut self.m[..m * m], &mut self.r[..m], m);
        lam[..k].fill(0.0);
        for (a, &p) in self.idx.iter().enumerate() {
            lam[p] = self.r[a];
        }
    }

    /// Returns the number of active-set changes.
    fn solve(&mut self, w: &[f64], y0: &[f64], cand: &[bool], tol: f64, lam: &mut [f64]) -> usize {
        let k = y0.len();
        for p in 0..k {
            self.act[p] = cand[p] && y0[p] < -tol;
            lam[p] = 0.0;
        }
        let mut changes = 0;
        for _ in 0..(10 + 4 * k) {
            self.solve_set(w, y0, lam);
            let mut worst = None;
            for &p in &self.idx {
                if lam[p] < 0.0 && worst.is_none_or(|(_, v)| lam[p] < v) {
                    worst = Some((p, lam[p]));
                }
            }
            if let Some((p, _)) = worst {
                self.act[p] = false;
                changes += 1;
                continue;
            }
            let mut viol = None;
            for p in 0..k {
                if !cand[p] || self.act[p] {
                    continue;
                }
                let y: f64 = y0[p] + (0..k).map(|q| w[p * k + q] * lam[q]).sum::<f64>();
                if y < -tol && viol.is_none_or(|(_, v)| y < v) {
                    viol = Some((p, y));
                }
            }
            match viol {
                Some((p, _)) => {
                    self.act[p] = true;
                    changes += 1;
                }
                None => break,
            }
        }
        changes
    }
}

/// A laboratory run: the model, the engine and all work memory.
pub struct Lab {
    pb: LabProblem,
    engine: Engine,
    s0: State,
    s1: State,
    w: Work,
    held: Vec<bool>,
    locked: Vec<bool>,
    force: Vec<f64>,
    impulse: Vec<f64>,
    gapv: Vec<f64>,
    active: Vec<bool>,
    /// Subdivision's velocity jumps: `M^{-1} c_p^T`, `k` columns of `n` (computed once).
    minv_c: Vec<f64>,
    /// Subdivision's work: the state at the current sub-step start, the forces at the step
    /// start and the multipliers of an accepted sub-step.
    cur: State,
    f_start: Vec<f64>,
    lam_keep: Vec<f64>,
    /// Moreau-Jean's tolerance on velocities, m/s.
    vel_tol: f64,
    stats: LabStats,
    massless: Vec<usize>,
}

impl std::fmt::Debug for Lab {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Lab")
            .field("integrator", &self.pb.integrator)
            .field("treatment", &self.pb.treatment)
            .field("pairs", &self.pb.gaps.len())
            .finish()
    }
}

const MAX_RESOLVES: usize = 32;

impl Lab {
    /// Checks the combination, redistributes the mass if asked, factors the system and
    /// computes the initial acceleration (classic integrators).
    ///
    /// # Errors
    /// [`LabError::Unsupported`] for a combination that does not exist; [`LabError`] when a
    /// matrix is singular.
    pub fn new(mut pb: LabProblem) -> Result<Self, LabError> {
        let explicit = pb.integrator.is_explicit();
        let st = matches!(pb.integrator, Integrator::SpaceTime { .. });
        match pb.treatment {
            Treatment::Subdivision if !st => {
                return Err(LabError::Unsupported(format!(
                    "subdivision of the time step (the paper's Fig. 5) is a space-time treatment; not available with {}",
                    pb.integrator.name()
                )))
            }
            Treatment::MassRedistribution if explicit => {
                return Err(LabError::Unsupported(
                    "mass redistribution makes the contact nodes massless: the explicit central difference would divide by a zero mass; use an implicit integrator".into(),
                ))
            }
            Treatment::Penalty { stiffness } if !(stiffness.is_finite() && stiffness > 0.0) => {
                return Err(LabError::Unsupported(format!(
                    "the penalty stiffness must be > 0 N/m, got {stiffness}"
                )))
            }
            Treatment::MoreauJean { restitution } if !(0.0..=1.0).contains(&restitution) => {
                return Err(LabError::Unsupported(format!(
                    "the restitution must be in [0, 1], got {restitution}"
                )))
            }
            _ => {}
        }
        let n = pb.model.n();
        let k = pb.gaps.len();
        let massless = if pb.treatment == Treatment::MassRedistribution {
            let mut nodes: Vec<usize> = pb
                .gaps
                .iter()
                .flat_map(|g| g.terms.iter().map(|&(d, _)| d))
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            redistribute_mass(&mut pb.model, 1, &nodes)
        } else {
            vec![]
        };
        let engine = Engine::new(&pb.model, pb.integrator, pb.h, &pb.fixed, &pb.gaps)?;
        let mut s0 = State::zeros(n);
        s0.u.copy_from_slice(&pb.u0);
        s0.v.copy_from_slice(&pb.v0);
        for &d in &pb.fixed {
            s0.v[d] = 0.0;
        }
        if !st {
            let mut f = vec![0.0; n];
            (pb.load)(pb.t0, &mut f);
            let mut bc: Vec<usize> = pb.fixed.clone();
            bc.extend_from_slice(&massless);
            s0.a = initial_acceleration(&pb.model, &bc, &s0.u, &s0.v, &f)?;
        }
        let minv_c = if pb.treatment == Treatment::Subdivision {
            let mut lu = SparseLu::new(pb.model.pattern(), &pb.model.m)?;
            let mut cols = vec![0.0; k * n];
            for (p, col) in cols.chunks_mut(n).enumerate() {
                for &(d, c) in &pb.gaps[p].terms {
                    col[d] += c;
                }
                lu.solve_in_place(col);
            }
            cols
        } else {
            vec![]
        };
        let vel_tol = 1e-12 * pb.v0.iter().fold(1e-300_f64, |a, v| a.max(v.abs()));
        let gapv = pb.gaps.iter().map(|g| g.eval(&s0.u)).collect();
        let lab = Self {
            engine,
            s1: s0.clone(),
            s0,
            w: Work {
                f0: vec![0.0; n],
                f1: vec![0.0; n],
                x: vec![0.0; n],
                pred: State::zeros(n),
                y0: vec![0.0; k],
                w: vec![0.0; k * k],
                cand: vec![false; k],
                lam: vec![0.0; k],
                lcp: Lcp::new(k),
            },
            held: vec![false; k],
            locked: vec![false; k],
            force: vec![0.0; k],
            impulse: vec![0.0; k],
            gapv,
            active: vec![false; k],
            minv_c,
            cur: State::zeros(n),
            f_start: vec![0.0; k],
            lam_keep: vec![0.0; k],
            vel_tol,
            stats: LabStats {
                factorizations: 1,
                ..LabStats::default()
            },
            massless,
            pb,
        };
        Ok(lab)
    }

    /// The model actually integrated (after any mass redistribution).
    pub fn model(&self) -> &LinearModel {
        &self.pb.model
    }

    /// The dofs made massless by mass redistribution.
    pub fn massless_dofs(&self) -> &[usize] {
        &self.massless
    }

    /// Runs all steps, calling `observer` at every step end (the initial state included).
    ///
    /// # Errors
    /// [`LabError`].
    pub fn run<F>(&mut self, interrupt: &AtomicBool, mut observer: F) -> Result<LabStats, LabError>
    where
        F: FnMut(&LabView) -> Result<(), std::io::Error>,
    {
        self.emit(0, self.pb.t0, &mut observer)?;
        for k in 1..=self.pb.steps {
            if interrupt.load(Ordering::Relaxed) {
                self.stats.interrupted = true;
                break;
            }
            let t0 = self.pb.t0 + (k - 1) as f64 * self.pb.h;
            self.step(t0)?;
            if !self.s1.v.iter().all(|x| x.is_finite()) {
                return Err(LabError::NotFinite {
                    step: k,
                    t: t0 + self.pb.h,
                });
            }
            std::mem::swap(&mut self.s0, &mut self.s1);
            self.stats.steps += 1;
            self.emit(k, t0 + self.pb.h, &mut observer)?;
        }
        Ok(self.stats)
    }

    fn emit<F>(&self, k: usize, t: f64, observer: &mut F) -> Result<(), std::io::Error>
    where
        F: FnMut(&LabView) -> Result<(), std::io::Error>,
    {
        let m = &self.pb.model;
        let kinetic = 0.5 * quadratic_form(m.pattern(), &m.m, &self.s0.v);
        let strain = 0.5 * quadratic_form(m.pattern(), &m.k, &self.s0.u);
        let penalty = match self.pb.treatment {
            Treatment::Penalty { stiffness } => self
                .gapv
                .iter()
                .map(|&g| 0.5 * stiffness * g.min(0.0).powi(2))
                .sum(),
            _ => 0.0,
        };
        observer(&LabView {
            k,
            t,
            u: &self.s0.u,
            v: &self.s0.v,
            kinetic,
            strain,
            penalty,
            forces: &self.force,
            gaps: &self.gapv,
            active: &self.active,
        })
    }

    /// One step `[t0, t0 + h]` from `s0` into `s1`.
    fn step(&mut self, t0: f64) -> Result<(), LabError> {
        let st = matches!(self.pb.integrator, Integrator::SpaceTime { .. });
        self.impulse.fill(0.0);
        match self.pb.treatment {
            Treatment::Subdivision => self.step_subdivided(t0)?,
            Treatment::Exact | Treatment::MassRedistribution if st => self.step_held(t0),
            _ => self.step_lcp(t0),
        }
        let h = self.pb.h;
        for p in 0..self.pb.gaps.len() {
            self.force[p] = self.impulse[p] / h;
            self.gapv[p] = self.pb.gaps[p].eval(&self.s1.u);
            self.active[p] = self.impulse[p] != 0.0 || self.held[p];
        }
        Ok(())
    }

    /// Exact, penalty, Moreau-Jean and mass redistribution as one complementarity problem.
    fn step_lcp(&mut self, t0: f64) {
        let e = &mut self.engine;
        let w = &mut self.w;
        let pb = &self.pb;
        let k = pb.gaps.len();
        e.free(&pb.load, t0, &self.s0, w);
        let (mu_u, mu_v, fs) = e.maps();
        let h = e.h;
        let mut tol = pb.gap_tol;
        for p in 0..k {
            let g = &pb.gaps[p];
            let cx = g.dot(&w.x);
            w.cand[p] = true;
            let (y0, mu, reg) = match pb.treatment {
                Treatment::Penalty { stiffness } => {
                    // The spring acts where the scheme evaluates K u.
                    let (y, mu) = e.stiffness_point(g, &self.s0, &w.pred);
                    (y + mu * cx, mu, fs / stiffness)
                }
                Treatment::MoreauJean { restitution } => {
                    let gn = g.dot(&self.s0.v);
                    w.cand[p] = g.eval(&self.s0.u) + 0.5 * h * gn <= 0.0;
                    tol = self.vel_tol;
                    (g.dot(&w.pred.v) + restitution * gn + mu_v * cx, mu_v, 0.0)
                }
                _ if e.is_explicit() => {
                    // Forward increment: the next position u1 + h v1 + h^2 a1 / 2.
                    let gh = g.eval(&w.pred.u) + h * g.dot(&w.pred.v);
                    let mu = h * mu_v + 0.5 * h * h;
                    (gh + mu * cx, mu, 0.0)
                }
                _ => (g.eval(&w.pred.u) + mu_u * cx, mu_u, 0.0),
            };
            w.y0[p] = y0;
            for q in 0..k {
                w.w[p * k + q] = mu * e.s[p * k + q] + if p == q { reg } else { 0.0 };
            }
        }
        let changes = w.lcp.solve(&w.w, &w.y0, &w.cand, tol, &mut w.lam);
        self.stats.resolves += changes;
        e.correct(&mut w.x, &w.lam);
        e.finish(&self.s0, w, &mut self.s1);
        for p in 0..k {
            let was = self.held[p];
            let now = w.lam[p] > 0.0;
            if now && !was {
                self.stats.entries += 1;
            }
            if was && !now {
                self.stats.releases += 1;
            }
            self.held[p] = now;
            self.impulse[p] = w.lam[p] * fs * h;
        }
    }

    /// Solves `[t, t + e.h]` from `s0` into `s1` with the held pairs at `c.v1 = -g*/h`
    /// (space-time engines); the multipliers go to `w.lam`.
    fn solve_held(
        e: &mut Engine,
        pb: &LabProblem,
        held: &[bool],
        t: f64,
        s0: &State,
        w: &mut Work,
        s1: &mut State,
    ) {
        let k = pb.gaps.len();
        e.free(&pb.load, t, s0, w);
        // Equalities on the held pairs: y = g(U) + h c.x = 0.
        let h = e.h;
        for p in 0..k {
            let g = &pb.gaps[p];
            w.y0[p] = g.eval(&w.pred.u) + h * g.dot(&w.x);
            for q in 0..k {
                w.w[p * k + q] = h * e.s[p * k + q];
            }
        }
        w.lcp.act.copy_from_slice(held);
        w.lcp.solve_set(&w.w, &w.y0, &mut w.lam);
        e.correct(&mut w.x, &w.lam);
        e.finish(s0, w, s1);
    }

    /// A sub-step `[t, t + len]` (`span = (t, len)`) with its own factorization, from `cur`
    /// into `s1` with the held pairs held.
    #[allow(clippy::too_many_arguments)]
    fn sub_step(
        pb: &LabProblem,
        held: &[bool],
        span: (f64, f64),
        cur: &State,
        w: &mut Work,
        s1: &mut State,
        stats: &mut LabStats,
    ) -> Result<(), LabError> {
        stats.factorizations += 1;
        let mut es = Engine::new(&pb.model, pb.integrator, span.1, &pb.fixed, &pb.gaps)?;
        Self::solve_held(&mut es, pb, held, span.0, cur, w, s1);
        Ok(())
    }

    /// The space-time exact treatment (as the driver's `exact`): hold on penetration,
    /// release on tension.
    fn step_held(&mut self, t0: f64) {
        let k = self.pb.gaps.len();
        self.locked.fill(false);
        for it in 0..=MAX_RESOLVES {
            Self::solve_held(
                &mut self.engine,
                &self.pb,
                &self.held,
                t0,
                &self.s0,
                &mut self.w,
                &mut self.s1,
            );
            if it == MAX_RESOLVES {
                break;
            }
            let mut changed = false;
            for p in 0..k {
                if self.held[p] && self.w.lam[p] < 0.0 && !self.locked[p] {
                    self.held[p] = false;
                    self.stats.releases += 1;
                    changed = true;
                }
            }
            if !changed {
                for p in 0..k {
                    if !self.held[p] && self.pb.gaps[p].eval(&self.s1.u) < -self.pb.gap_tol {
                        self.held[p] = true;
                        self.locked[p] = true;
                        self.stats.entries += 1;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
            self.stats.resolves += 1;
        }
        for p in 0..k {
            self.impulse[p] = self.w.lam[p];
        }
    }

    /// The paper's Fig. 5: sub-steps at the instants of entering and leaving contact.
    fn step_subdivided(&mut self, t0: f64) -> Result<(), LabError> {
        let k = self.pb.gaps.len();
        let h = self.pb.h;
        let t1 = t0 + h;
        // The force of each pair at the start (for locating a release).
        self.f_start.copy_from_slice(&self.force);
        let cur = &mut self.cur;
        cur.u.copy_from_slice(&self.s0.u);
        cur.v.copy_from_slice(&self.s0.v);
        cur.a.copy_from_slice(&self.s0.a);
        let f_start = &self.f_start;
        let lam_keep = &mut self.lam_keep;
        let mut t = t0;
        for _ in 0..4 * k + 4 {
            let rem = t1 - t;
            if rem <= 1e-12 * h {
                break;
            }
            let mut sub = if (rem - h).abs() <= 1e-12 * h {
                None
            } else {
                self.stats.factorizations += 1;
                Some(Engine::new(
                    &self.pb.model,
                    self.pb.integrator,
                    rem,
                    &self.pb.fixed,
                    &self.pb.gaps,
                )?)
            };
            let e = sub.as_mut().unwrap_or(&mut self.engine);
            Self::solve_held(e, &self.pb, &self.held, t, cur, &mut self.w, &mut self.s1);
            // Release: the first held pair whose force crosses zero.
            let mut rel: Option<(usize, f64)> = None;
            for p in 0..k {
                if self.held[p] && self.w.lam[p] < 0.0 {
                    let fe = self.w.lam[p] / rem;
                    let fs = f_start[p].max(0.0);
                    let th = if fs > 0.0 { fs / (fs - fe) } else { 0.0 };
                    if rel.is_none_or(|(_, v)| th < v) {
                        rel = Some((p, th));
                    }
                }
            }
            if let Some((p, th)) = rel {
                self.stats.releases += 1;
                if th * rem > 1e-9 * h {
                    Self::sub_step(
                        &self.pb,
                        &self.held,
                        (t, th * rem),
                        cur,
                        &mut self.w,
                        &mut self.s1,
                        &mut self.stats,
                    )?;
                    // Keep the held part only if it stayed compressive; otherwise the
                    // force crossed zero earlier than interpolated: release at `t`.
                    if self.w.lam[p] >= 0.0 {
                        for q in 0..k {
                            self.impulse[q] += self.w.lam[q];
                        }
                        cur.u.copy_from_slice(&self.s1.u);
                        cur.v.copy_from_slice(&self.s1.v);
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
                let g1 = self.pb.gaps[p].eval(&self.s1.u);
                if g1 < -self.pb.gap_tol {
                    let g0 = self.pb.gaps[p].eval(&cur.u).max(0.0);
                    let th = g0 / (g0 - g1);
                    if ent.is_none_or(|(_, v)| th < v) {
                        ent = Some((p, th));
                    }
                }
            }
            let Some((p, th0)) = ent else {
                for q in 0..k {
                    self.impulse[q] += self.w.lam[q];
                }
                return Ok(());
            };
            // Secant on the end gap of the sub-step [t, t + th rem].
            let g0 = self.pb.gaps[p].eval(&cur.u);
            let (mut ta, mut ga) = (0.0, g0);
            let (mut tb, mut gb) = (1.0, self.pb.gaps[p].eval(&self.s1.u));
            let mut th = th0.clamp(0.0, 1.0);
            for _ in 0..12 {
                if th * rem <= 1e-9 * h {
                    th = 0.0;
                    self.s1.u.copy_from_slice(&cur.u);
                    self.s1.v.copy_from_slice(&cur.v);
                    lam_keep.fill(0.0);
                    break;
                }
                Self::sub_step(
                    &self.pb,
                    &self.held,
                    (t, th * rem),
                    cur,
                    &mut self.w,
                    &mut self.s1,
                    &mut self.stats,
                )?;
                lam_keep.copy_from_slice(&self.w.lam);
                let g = self.pb.gaps[p].eval(&self.s1.u);
                if g.abs() <= self.pb.gap_tol {
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
                self.impulse[q] += lam_keep[q];
            }
            cur.u.copy_from_slice(&self.s1.u);
            cur.v.copy_from_slice(&self.s1.v);
            t += th * rem;
            // The velocity jump at t_c: M dv = c^T P with c.(v + dv) = 0.
            let n = cur.v.len();
            let col = &self.minv_c[p * n..(p + 1) * n];
            let pimp = -self.pb.gaps[p].dot(&cur.v) / self.pb.gaps[p].dot(col);
            for (vi, ci) in cur.v.iter_mut().zip(col) {
                *vi += pimp * ci;
            }
            self.impulse[p] += pimp.max(0.0);
            self.held[p] = true;
            self.stats.entries += 1;
        }
        // Finished by sub-steps: the state is in `cur`.
        self.s1.u.copy_from_slice(&self.cur.u);
        self.s1.v.copy_from_slice(&self.cur.v);
        Ok(())
    }
}
