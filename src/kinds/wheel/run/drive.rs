//! The step loop of a wheel run ([`drive`]): the one place that speaks to the driver, with
//! the observers on the stepping thread or behind it, and the watch of the wheel's rigid
//! rotation against its frame ([`RotationWatch`]).

use super::observers::{Observer, Timeline, WheelStep};
use super::plastic_body;
use super::seen::{batches, Batch, Seen};
use crate::bodies::wheel::WheelModel;
use crate::linalg::{quadratic_form, quadratic_forms};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::scenario::{Run, WheelScenario};
use std::time::Instant;

/// What the step loop reports back, in the job's terms.
#[derive(Debug, Clone, Copy)]
pub struct LoopOutcome {
    /// Steps taken.
    pub steps: usize,
    /// Brakings (steps stepped back).
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// Stopped by Ctrl-C.
    pub interrupted: bool,
    /// Numeric factorizations of the step matrix (a gamma schedule changes it once).
    pub factorizations: usize,
    /// Stick/slip changes of the friction rows (dense re-solves, no factorization).
    pub stick_slip_changes: usize,
    /// Relocations of the refined zone.
    pub relocations: usize,
    /// Wall-clock time of the loop, s.
    pub wall_time_s: f64,
    /// Corrections of the plastic iteration (0 when elastic).
    pub plastic_iterations: usize,
    /// Solves whose plastic iteration stopped at the cap.
    pub plastic_unconverged: usize,
    /// Most plastic corrections in one solve.
    pub plastic_max_in_one_solve: usize,
}

/// What [`drive`] returns: the counters, the internal force's state at the end (a plastic
/// wheel's) and the last step's displacement.
pub type Driven = (LoopOutcome, Option<Vec<f64>>, Vec<f64>);

/// Runs the wheel's step loop with the observers attached: the one place that speaks to
/// the driver (the [`crate::simulation::Problem`] of [`WheelModel::problem`],
/// [`crate::simulation::Simulation`], its step view and counters). With a plastic wheel
/// (`material.model = "j2"`) the plastic body is the driver's internal force, and its state
/// at the end is returned beside the counters; in large deformation
/// (`material.geometry = "large"`) the hyperelastic body of [`crate::kinds::wheel::large`]
/// is. The last step's displacement comes third.
///
/// # Errors
/// [`RunError::Simulation`] (an observer's I/O error included).
pub fn drive(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    (steps, timeline, stride): (usize, Timeline, usize),
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> Result<Driven, RunError> {
    use crate::simulation::Simulation;
    let sim_error = |source| RunError::Simulation {
        run: run.label.clone(),
        source,
    };
    let gamma_schedule = ws.gamma_schedule(run.params.gamma);
    let mut problem = wm.problem(
        run.integrator,
        run.params.h,
        gamma_schedule,
        run.contact,
        steps,
    );
    problem.friction = run.friction;
    let mut sim = Simulation::with_settings(problem, opts.settings()).map_err(sim_error)?;
    match (ws.plastic, ws.large) {
        (Some(pl), Some(large)) => {
            // J2 at finite strain: the hyperelastic triangles with the plastic Green strain.
            let body = crate::kinds::wheel::large::finite_body(wm, large);
            sim.set_internal_force(
                Box::new(crate::finite::FinitePlastic::new(body, pl.material)),
                pl.tolerance.min(large.tolerance),
                crate::model::DEFAULT_MAX_ITERATIONS,
            )
            .map_err(sim_error)?;
        }
        (Some(pl), None) => {
            sim.set_internal_force(
                Box::new(plastic_body(wm, ws, pl)),
                pl.tolerance,
                crate::model::DEFAULT_MAX_ITERATIONS,
            )
            .map_err(sim_error)?;
        }
        _ => {}
    }
    if let (Some(large), None) = (ws.large, ws.plastic) {
        sim.set_internal_force(
            Box::new(crate::kinds::wheel::large::finite_body(wm, large)),
            large.tolerance,
            crate::model::DEFAULT_MAX_ITERATIONS,
        )
        .map_err(sim_error)?;
    }
    if let Some((sources, step)) = &wm.zone {
        sim.set_relocation(crate::simulation::Relocation {
            sources: sources.clone(),
            step: *step,
            omega: ws.spec.omega,
            angle0: 0.0,
            turned: sources.len(),
        })
        .map_err(sim_error)?;
    }
    let start = Instant::now();
    // The energies (two sparse quadratic forms) only where they are written: every
    // `stride`-th step, the first step of the rolling phase and the last one.
    let stride = stride.max(1);
    let timing = Timing {
        timeline,
        stride,
        last_turn: timeline.last_full_turn(),
        with_friction: run.friction.is_some_and(|l| l.is_active()),
    };
    // Behind the loop (module `seen`) where the stepping thread is alone on its core: a
    // run with threads to spare, a factor solved on one thread (below the split's order),
    // a wheel coupled to its base. Else every observer on the stepping thread.
    let n = wm.mesh.n_dofs();
    let behind = matches!(opts.par(), crate::linalg::team::Par::Threads(_))
        && n < crate::linalg::SPLIT_MIN_ORDER
        && wm.twin.is_none();
    let (stats, observed) = if behind {
        drive_behind(wm, &mut sim, timing, (observers, inline), opts)
    } else {
        let stats = drive_inline(wm, &mut sim, timing, (observers, inline), opts);
        (stats, Ok(()))
    };
    // An observer's error is the cause of a stop the loop reports as its own.
    observed.map_err(|e| sim_error(crate::simulation::SimError::Output(e)))?;
    let stats = stats.map_err(|e| sim_error(stopped_by_observer(e)))?;
    // The triangles' plastic states (a finite-strain body's state holds its prediction
    // after them).
    let cells = wm.triangles.len() * crate::plasticity::STATE_LEN;
    let plastic_state = sim
        .nonlinear()
        .map(|nl| nl.state(1)[..cells.min(nl.state(1).len())].to_vec());
    let u_end = sim.last_state().u.clone();
    Ok((
        LoopOutcome {
            steps: stats.steps,
            brakings: stats.brakings,
            releases: stats.releases,
            interrupted: stats.interrupted,
            factorizations: stats.factorizations,
            stick_slip_changes: stats.stick_slip_changes,
            relocations: stats.relocations,
            wall_time_s: start.elapsed().as_secs_f64(),
            plastic_iterations: stats.plastic_iterations,
            plastic_unconverged: stats.plastic_unconverged,
            plastic_max_in_one_solve: stats.plastic_max_in_one_solve,
        },
        plastic_state,
        u_end,
    ))
}

/// When a wheel run's observers want what (the steps' schedule of [`drive`]).
#[derive(Debug, Clone, Copy)]
struct Timing {
    timeline: Timeline,
    /// The tables' and energies' stride.
    stride: usize,
    /// The last full turn (the turn average and the velocity snapshots), s.
    last_turn: (f64, f64),
    /// Friction: the traction's watch reads the pairs every step.
    with_friction: bool,
}

impl Timing {
    /// True when step `k` at `t` reports its energies (`last`: the run's last step;
    /// `rolling_seen`: the rolling phase was reached before, updated).
    fn energy_due(&self, k: usize, t: f64, last: bool, rolling_seen: &mut bool) -> bool {
        let first_rolling = !*rolling_seen && self.timeline.rolling(t);
        *rolling_seen |= first_rolling;
        k % self.stride == 0 || last || first_rolling
    }
}

/// The observers behind the loop and those on the stepping thread.
type Sides<'a, 'b, 'c, 'd> = (
    &'a mut [&'b mut (dyn Observer + Send + 'b)],
    &'c mut [&'d mut (dyn Observer + 'd)],
);

/// The step loop with every observer on the stepping thread (an uncoupled twin: the
/// observers see the wheel's own state, the sum of the disk's and its twin's).
fn drive_inline(
    wm: &WheelModel,
    sim: &mut crate::simulation::Simulation,
    timing: Timing,
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> Result<crate::simulation::RunStats, crate::simulation::SimError> {
    let mut rolling_seen = false;
    let twin = wm.twin.is_some();
    let own = if twin { wm.mesh.n_dofs() } else { 0 };
    let (mut u_own, mut v_own) = (vec![0.0; own], vec![0.0; own]);
    sim.run(opts.cancel.flag(), |s| {
        let st = s.state;
        let due = timing.energy_due(st.k, st.t, s.last, &mut rolling_seen);
        let (u, v): (&[f64], &[f64]) = if twin {
            wm.own_state(&st.u, &mut u_own);
            wm.own_state(&st.v, &mut v_own);
            (&u_own, &v_own)
        } else {
            (&st.u, &st.v)
        };
        let energy = due.then(|| {
            if twin {
                let p = wm.model.pattern();
                (
                    0.5 * quadratic_form(p, &wm.model.m, v),
                    0.5 * quadratic_form(p, &wm.k_elastic, u),
                )
            } else {
                s.energies()
            }
        });
        let step = WheelStep {
            k: st.k,
            t: st.t,
            u,
            v,
            energy,
            penalty: s.penalty,
            contact_force: s.contact_force,
            held: s.held,
            min_gap: st.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min),
            pairs: &st.pairs,
            slip_power: s.slip_power,
            friction_dissipated: s.friction_dissipated,
            frame_angle: s.frame_angle,
            team: Some(s.team()),
        };
        observers.iter_mut().try_for_each(|o| o.observe(&step))?;
        inline.iter_mut().try_for_each(|o| o.observe(&step))
    })
}

/// The step loop with the observers of `observers` behind it ([`crate::simulation::behind`],
/// module `seen`), those of `inline` on the stepping thread. The wheel is coupled to its
/// base (no twin).
fn drive_behind(
    wm: &WheelModel,
    sim: &mut crate::simulation::Simulation,
    timing: Timing,
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> (
    Result<crate::simulation::RunStats, crate::simulation::SimError>,
    std::io::Result<()>,
) {
    let mut rolling_seen = false;
    // The energies behind the loop, except with a plastic wheel (its state corrects them).
    let forms = sim
        .energy_matrices()
        .map(|(p, m, k)| (p.clone(), m.to_vec(), k.to_vec()));
    let (h, (t0, t1)) = (timing.timeline.h, timing.last_turn);
    let energies = |seen: &Seen| {
        seen.energy.or_else(|| {
            let (p, m, k) = forms.as_ref()?;
            seen.want_energy.then(|| {
                let (mv, ku) = quadratic_forms(p, (m, &seen.v), (k, &seen.u));
                (0.5 * mv, 0.5 * ku)
            })
        })
    };
    let observe = |batch: &mut Batch| {
        let len = std::mem::take(&mut batch.len);
        batch.items[..len].iter().try_for_each(|seen| {
            let step = seen.step(energies(seen), None);
            observers.iter_mut().try_for_each(|o| o.observe(&step))
        })
    };
    let slots = batches(wm.mesh.n_dofs(), wm.rim.len());
    crate::simulation::behind::behind(slots, observe, |feed| {
        sim.run(opts.cancel.flag(), |s| {
            let st = s.state;
            let want_energy = timing.energy_due(st.k, st.t, s.last, &mut rolling_seen);
            // With the plastic state's correction: here, where the state is.
            let energy = (want_energy && forms.is_none()).then(|| s.energies());
            let batch = feed.current().map_err(std::io::Error::other)?;
            let seen = &mut batch.items[batch.len];
            // Module `seen`: the state where an observer reads it, the pairs likewise.
            seen.fields = want_energy || timing.timeline.within(st.t, t0 - h, t1 + h);
            seen.with_pairs = timing.with_friction || st.k % timing.stride == 0 || s.last;
            if seen.fields {
                seen.u.copy_from_slice(&st.u);
                seen.v.copy_from_slice(&st.v);
            }
            seen.pairs.clear();
            if seen.with_pairs {
                seen.pairs.extend_from_slice(&st.pairs);
            }
            (seen.k, seen.t, seen.energy, seen.want_energy) = (st.k, st.t, energy, want_energy);
            (seen.penalty, seen.contact_force, seen.held) = (s.penalty, s.contact_force, s.held);
            seen.min_gap = st.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
            (seen.slip_power, seen.friction_dissipated) = (s.slip_power, s.friction_dissipated);
            seen.frame_angle = s.frame_angle;
            // The stepping thread's observers read the state in place.
            let step = WheelStep {
                u: &st.u,
                v: &st.v,
                pairs: &st.pairs,
                ..seen.step(energy, Some(s.team()))
            };
            // A stop of the guard here still leaves its step to the observers, as before.
            let inline_result = inline.iter_mut().try_for_each(|o| o.observe(&step));
            batch.len += 1;
            if batch.len == batch.items.len() {
                feed.send().map_err(std::io::Error::other)?;
            }
            inline_result
        })
    })
}

/// An observer's stop ([`RotationWatch`]: a [`crate::guard::Diverged`] carried in the
/// I/O error an observer returns) as the guard's own; other errors as they are.
fn stopped_by_observer(e: crate::simulation::SimError) -> crate::simulation::SimError {
    use crate::simulation::SimError;
    match e {
        SimError::Output(io) => {
            match io
                .get_ref()
                .and_then(|x| x.downcast_ref::<crate::guard::Diverged>())
            {
                Some(d) => SimError::Diverged(*d),
                None => SimError::Output(io),
            }
        }
        e => e,
    }
}

/// The wheel's rigid rotation about its centre against its frame, `theta = sum (x u_y -
/// y u_x) / sum r^2` over the rim nodes, watched every step. The model is linear: a rotation
/// `theta` shortens the rim's reach by `R theta^2 / 2`, which it does not see. A clamped hub
/// holds the rotation; the paper's pinned centre does not, and the contact's lever arms
/// rock the disk: about 2e-3 rad at 300 rad/s on the paper's mesh, 0.04 rad at 520 rad/s
/// (Fig. 15's fastest point: 8% of the flattening) and at 100 rad/s. Past 1% of the
/// flattening ([`ROTATION_REACH`]) the run warns, with the figure; past a quarter of it
/// ([`ROTATION_STOP`]) the run is stopped ([`crate::guard::Cause::Turned`]): the contact
/// force is then wrong by about as much (the penetration it sees is `d + R theta^2 / 2`
/// for a flattening `d`), and such a run (a 24-node rim at 31 rad/s: 0.14 rad, 100% of the
/// flattening, its energy up tenfold) is not a result. In large deformation
/// (`material.geometry = "large"`) the rotation makes no strain and the contact sees the
/// rim where it is: the watch measures it (`sin theta` then) and neither warns nor stops.
pub(super) struct RotationWatch {
    /// The rim nodes' dofs and reference coordinates `(dof, x, y)`.
    rim: Vec<(usize, f64, f64)>,
    /// `sum r^2` over them.
    r2: f64,
    /// The spun rim's radius and the flattening, m.
    radius: f64,
    depth: f64,
    /// The largest `|theta|` seen, rad, and its time, s.
    max: (f64, f64),
    /// The wheel is in large deformation: measure only.
    large: bool,
}

/// The rim's shortening by a rigid rotation, as a fraction of the flattening, beyond which
/// a wheel run warns ([`RotationWatch`]).
const ROTATION_REACH: f64 = 0.01;

/// The rim's shortening by a rigid rotation, as a fraction of the flattening, beyond which
/// a wheel run is stopped ([`RotationWatch`]).
const ROTATION_STOP: f64 = 0.25;

impl RotationWatch {
    pub(super) fn new(wm: &WheelModel, large: bool) -> Self {
        let rim: Vec<(usize, f64, f64)> = wm
            .rim
            .iter()
            .map(|&i| {
                let p = wm.mesh.point(i);
                (2 * i, p[0], p[1])
            })
            .collect();
        let r2 = rim.iter().map(|&(_, x, y)| x * x + y * y).sum::<f64>();
        Self {
            rim,
            r2,
            radius: wm.spinning_radius(),
            depth: wm.spec.flattening.depth,
            max: (0.0, 0.0),
            large,
        }
    }

    /// The largest rotation seen, rad, and its time, s.
    pub(super) fn max(&self) -> (f64, f64) {
        self.max
    }

    /// The warning when the rotation passed [`ROTATION_REACH`] of the flattening.
    pub(super) fn warning(&self, label: &str) -> Option<String> {
        let (radius, depth) = (self.radius, self.depth);
        let (theta, t) = self.max;
        let reach = radius * theta * theta / 2.0;
        (!self.large && depth > 0.0 && reach > ROTATION_REACH * depth).then(|| {
            format!(
                "{label}: the wheel turned up to {theta:.3e} rad against its frame (at t = {t:.4e} s; its rigid rotation about the centre, which only the contact holds): a linear model misses the rim's shortening R theta^2 / 2 = {:.1}% of the flattening; hold the wheel by its hub (`wheel.support = \"hub\"`)",
                100.0 * reach / depth
            )
        })
    }
}

impl Observer for RotationWatch {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if self.r2 > 0.0 {
            let m: f64 = self
                .rim
                .iter()
                .map(|&(d, x, y)| x * s.u[d + 1] - y * s.u[d])
                .sum();
            let theta = (m / self.r2).abs();
            if theta > self.max.0 {
                self.max = (theta, s.t);
                let reach = self.radius * theta * theta / 2.0 / self.depth;
                if !self.large && self.depth > 0.0 && reach > ROTATION_STOP {
                    return Err(std::io::Error::other(crate::guard::Diverged {
                        step: s.k,
                        t: s.t,
                        cause: crate::guard::Cause::Turned {
                            theta,
                            reach,
                            limit: ROTATION_STOP,
                        },
                    }));
                }
            }
        }
        Ok(())
    }
}
