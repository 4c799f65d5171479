//! The wheel on its rigid base as a pass runner (`kind = "wheel"`, the paper's setting): a
//! pass is the settling of the scenario, then its turns; the wear is summed over the last
//! full turn, so that every rim node crosses the patch once.
//!
//! **The profile** is the rim's radial deviation over the arc length `s = R (theta -
//! theta_0)` from the first rim node (by angle), one sample per rim node: periodic, `n` the
//! rim's nodes, `dx = 2 pi R / n`. It enters the gap by moving each rim node's reference
//! position radially by `z` (the worn shape is taken as stress-free: a rim turned to that
//! shape, not one worn under load; the interior nodes stay where they are, which for
//! micrometres of roughness on millimetres of element is immaterial). The model is rebuilt
//! on the moved mesh for every pass (its matrices, the spinning equilibrium); the base
//! stays where the smooth wheel's is (at the smooth wheel's spinning radius minus the
//! flattening), so the mean load is the smooth wheel's.
//!
//! **Wear per rim node** from its [`crate::model::PairState`] at the end of every step of
//! the last turn: the normal force `force`, the friction force `|tangential_force|`, the
//! slip speed `slip_power / |T|`, over the node's tributary area (`dx` times the wheel's
//! thickness), through the scenario's [`WearLaw`], times the step `h`. Friction with a
//! creepage is needed for any wear (`contact.friction`, `rolling.creepage`: a node in
//! stick does not slip); a plastic wheel may roll without friction (plastic flow alone,
//! the free rolling of Johnson's shakedown analysis).
//!
//! **Plastic flow** (`material.model = "j2"`, [`crate::plasticity`]): the wheel's plastic
//! state (per triangle: plastic strain, backstress, equivalent plastic strain) is carried
//! from pass to pass and checkpointed with the study ([`PassRunner::carried_state`]), so the
//! residual stresses of earlier passes are there in the next one and a wheel below its
//! shakedown limit stops flowing. A pass starts from the carried state in equilibrium: the
//! spinning equilibrium plus the state's residual displacement on the spinning stiffness
//! ([`crate::plasticity::residual_displacement`]), and the driver's iteration starts from
//! the state ([`crate::simulation::Simulation::set_internal_state`]). The pass's plastic
//! increment `d_p` is the change of the rim's permanent radial displacement
//! ([`crate::plasticity::permanent_radial_displacement`], load off, at rest) from the start
//! state to the end state, on the pass's mesh; its mean (a uniform change of radius) is
//! reported (`plastic_mean_m`) and taken out, like the wear's; the largest growth of an
//! element's equivalent plastic strain over the pass is `plastic_strain_increment_max`
//! (zero once the wheel has shaken down). The profile holds both
//! (`z = wear part + sum of d_p`), but the rim's nodes are moved by the wear part alone
//! (`z` less the carried sum of `d_p`): the plastic part is in the carried state's residual
//! displacement, and moving the nodes by it too would count it twice. Plastic flow is not
//! scaled by the wear step: a simulated pass is one real pass for it (ratcheting under
//! repeated passes is what the carried state gives, pass by pass); the smoothing and the
//! cutoff, which tame the wear step's amplification, do not touch it. The reference pass
//! (`growth.reference`) runs from the carried state and leaves it as it was.

use crate::bodies::wheel::{Coupling, WheelModel};
use crate::contact::obstacle::RotatingLine;
use crate::growth::{PassResult, PassRunner, SurfaceProfile};
use crate::kinds::wheel::run::build;
use crate::linalg::team::Par;
use crate::run::error::RunError;
use crate::scenario::{Run, Scenario, WheelScenario};
use crate::simulation::Simulation;
use crate::wear::{ContactSample, WearLaw};
use std::f64::consts::PI;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The wheel-on-rigid-base runner (module docs).
pub struct WheelPassRunner {
    smooth: WheelModel,
    ws: WheelScenario,
    run: Run,
    path: PathBuf,
    base_radius: f64,
    law: WearLaw,
    density: f64,
    par: Par,
    dx: f64,
    plastic: Option<Carried>,
}

/// A plastic wheel's state carried from pass to pass (module docs).
struct Carried {
    pl: crate::scenario::Plastic,
    /// The plastic state (`crate::plasticity::STATE_LEN` per triangle).
    state: Vec<f64>,
    /// The sum of the passes' plastic increments `d_p` (zero-mean), per rim node, m.
    profile: Vec<f64>,
}

impl WheelPassRunner {
    /// The runner of a built wheel scenario (its first run) with the wear law `law` and the
    /// worn material's density (`None`: the wheel's).
    ///
    /// # Errors
    /// [`RunError::Input`] for a scenario that is not a wheel on its rigid base, a rim that
    /// is not evenly spaced, a model that cannot be built.
    pub fn new(
        sc: &Scenario,
        law: WearLaw,
        density: Option<f64>,
        par: Par,
    ) -> Result<Self, RunError> {
        let path = sc.path.clone();
        let run = sc
            .runs
            .first()
            .cloned()
            .ok_or_else(|| RunError::input(&path, "the scenario has no run"))?;
        let Some(ws) = run.model.get::<crate::scenario::WheelScenario>() else {
            return Err(RunError::input(
                &path,
                "the wheel's growth runner needs kind = \"wheel\"",
            ));
        };
        if ws.block.is_some() {
            return Err(RunError::input(
                &path,
                "[block]: the wheel's growth study runs on the rigid base; remove [block]",
            ));
        }
        if matches!(ws.mesh, crate::scenario::MeshSource::Zone(_)) {
            return Err(RunError::input(&path, "wheel.zone_rim_nodes: the growth study needs the whole rim at one pitch (its profile is one sample per rim node); remove the refined zone"));
        }
        if ws.spec.coupling == Coupling::Uncoupled {
            return Err(RunError::input(&path, "rolling.coupling = \"uncoupled\": the growth study runs the coupled wheel; remove it"));
        }
        if ws.large.is_some() {
            return Err(RunError::input(&path, "material.geometry = \"large\": the growth study's passes are linear in the geometry (the wheel's profile and its plastic state are carried on the linear model); remove the key"));
        }
        let friction = run.friction.is_some_and(|l| l.is_active());
        if !friction && ws.plastic.is_none() {
            return Err(RunError::input(&path, "contact.friction: the wear laws need the friction force and the slip (give contact.friction > 0 and a rolling.creepage; a frictionless study needs a plastic wheel, material.model = \"j2\")"));
        }
        let smooth = build(ws, &path)?;
        let n = smooth.rim.len();
        let r = ws.spec.radius;
        let dx = 2.0 * PI * r / n as f64;
        if let Some((k, d)) = crate::growth::uneven_rim(&smooth.mesh, &smooth.rim) {
            return Err(RunError::input(&path, format!("the rim's nodes are not evenly spaced (node {k} of {n} is {d:.3e} rad off): the growth study needs one profile sample per rim node at one pitch (a generated disk with wheel.rim_nodes)")));
        }
        let base_radius = smooth.base().radius;
        let density = density.unwrap_or(ws.spec.material.density);
        let plastic = ws.plastic.map(|pl| Carried {
            pl,
            state: vec![0.0; smooth.triangles.len() * crate::plasticity::STATE_LEN],
            profile: vec![0.0; n],
        });
        Ok(Self {
            plastic,
            ws: ws.clone(),
            smooth,
            run,
            path,
            base_radius,
            law,
            density,
            par,
            dx,
        })
    }

    /// The surface the next pass over `profile` meets, with the load off and at rest: per
    /// rim node, its radius on the pass's mesh plus the permanent radial displacement of
    /// the carried plastic state (none for an elastic wheel), m. It is the smooth rim's
    /// radius plus `profile.z` plus the plastic flow's accumulated mean radius change
    /// (module docs: the plastic part is counted once).
    ///
    /// # Errors
    /// [`RunError::Input`] when the model cannot be built or its stiffness is singular.
    pub fn rim_surface_at_rest(&self, profile: &SurfaceProfile) -> Result<Vec<f64>, RunError> {
        let wm = self.model(profile)?;
        let reference = wm.mesh.reference_positions();
        let radius = |node: usize| reference[2 * node].hypot(reference[2 * node + 1]);
        let mut out: Vec<f64> = wm.rim.iter().map(|&node| radius(node)).collect();
        if let Some(c) = &self.plastic {
            let body = crate::kinds::wheel::run::plastic_body(&wm, &self.ws, c.pl);
            let d = crate::plasticity::permanent_radial_displacement(
                &body,
                &c.state,
                (wm.model.pattern(), &wm.k_elastic, &wm.fixed_dofs),
                &reference,
                &wm.rim,
            )
            .map_err(|e| RunError::input(&self.path, e))?;
            out.iter_mut().zip(&d).for_each(|(r, d)| *r += d.1);
        }
        Ok(out)
    }

    /// The radius of the smooth rim's nodes, m.
    pub fn smooth_rim_radii(&self) -> Vec<f64> {
        let reference = self.smooth.mesh.reference_positions();
        self.smooth
            .rim
            .iter()
            .map(|&node| reference[2 * node].hypot(reference[2 * node + 1]))
            .collect()
    }

    /// The model with the rim moved radially by the profile.
    fn model(&self, profile: &SurfaceProfile) -> Result<WheelModel, RunError> {
        let mut mesh = self.smooth.mesh.clone();
        for (k, (&node, &z)) in self.smooth.rim.iter().zip(&profile.z).enumerate() {
            // The plastic part of the profile is in the carried state (module docs).
            let z = z - self.plastic.as_ref().map_or(0.0, |c| c.profile[k]);
            let (x, y) = (mesh.coords[2 * node], mesh.coords[2 * node + 1]);
            let r = x.hypot(y);
            let s = (r + z) / r;
            mesh.coords[2 * node] = x * s;
            mesh.coords[2 * node + 1] = y * s;
        }
        WheelModel::new(mesh, self.smooth.spec.clone()).map_err(|e| RunError::input(&self.path, e))
    }
}

impl PassRunner for WheelPassRunner {
    fn grid(&self) -> (f64, f64, usize, bool) {
        (0.0, self.dx, self.smooth.rim.len(), true)
    }

    fn speed(&self) -> f64 {
        self.ws.spec.omega.abs() * self.ws.spec.radius
    }

    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        _pass: usize,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.pass(profile, interrupt, true)
    }

    fn run_reference(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.pass(profile, interrupt, false)
    }

    fn carried_state(&self) -> Option<Vec<f64>> {
        self.plastic.as_ref().map(|c| {
            let mut s = c.state.clone();
            s.extend_from_slice(&c.profile);
            s
        })
    }

    /// The heights against the wheel's radius, then the rim moved by them (with the
    /// plastic flow's part taken out, as a pass moves it) still a mesh.
    fn check_profile(&self, z: &[f64]) -> Result<(), String> {
        crate::growth::check_profile_height(z, self.ws.spec.radius)?;
        let profile = SurfaceProfile {
            x0: 0.0,
            dx: self.dx,
            z: z.to_vec(),
            periodic: true,
        };
        self.model(&profile).map(|_| ()).map_err(|e| match e {
            RunError::Input { message, .. } => {
                format!("the rim moved by it is not a mesh ({message})")
            }
            other => other.to_string(),
        })
    }

    fn restore_state(&mut self, state: Option<&[f64]>) -> Result<(), String> {
        match (self.plastic.as_mut(), state) {
            (None, None) => Ok(()),
            (Some(c), Some(s)) => {
                let (m, n) = (c.state.len(), c.profile.len());
                if s.len() != m + n {
                    return Err(format!("the checkpoint's plastic state has {} numbers, this wheel's {} ({} per triangle and one per rim node)", s.len(), m + n, crate::plasticity::STATE_LEN));
                }
                c.state.copy_from_slice(&s[..m]);
                c.profile.copy_from_slice(&s[m..]);
                Ok(())
            }
            (Some(_), None) => Err("the checkpoint has no plastic state, but material.model = \"j2\": it was written by an elastic study (start afresh without --resume)".into()),
            (None, Some(_)) => Err("the checkpoint carries a plastic state, but this wheel is elastic (material.model): resume with the scenario that wrote it".into()),
        }
    }

    /// The wheel writes no files of its own.
    fn extra_outputs(
        &mut self,
        _out: &std::path::Path,
        _bands: &[(f64, f64)],
        _plots: bool,
        _interrupt: &AtomicBool,
    ) -> Result<Vec<std::path::PathBuf>, RunError> {
        Ok(Vec::new())
    }
}

impl WheelPassRunner {
    /// One pass over `profile`; a plastic wheel's carried state advances when `commit`.
    fn pass(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &AtomicBool,
        commit: bool,
    ) -> Result<PassResult, RunError> {
        let build_start = Instant::now();
        let wm = self.model(profile)?;
        let body = self
            .plastic
            .as_ref()
            .map(|c| crate::kinds::wheel::run::plastic_body(&wm, &self.ws, c.pl));
        let (mut sim, steps) = self.simulation(&wm, body.as_ref())?;
        let build_s = build_start.elapsed().as_secs_f64();
        let tally = self.roll(&mut sim, &wm, steps, interrupt)?;
        let stats = tally.stats;
        let (plastic, plastic_scalars) = match (self.plastic.as_mut(), &body) {
            (Some(c), Some(body)) if !stats.interrupted => {
                let linalg = |e: crate::linalg::LinalgError| RunError::input(&self.path, e);
                let end = sim
                    .nonlinear()
                    .map(|nl| nl.state(1).to_vec())
                    .unwrap_or_default();
                plastic_change(c, body, &wm, end, &stats, commit).map_err(linalg)?
            }
            _ => (vec![0.0; wm.rim.len()], Vec::new()),
        };
        let m = tally.samples.max(1) as f64;
        let mut scalars: Vec<(String, f64)> = vec![
            ("mean_force_n".into(), tally.f_sum / m),
            ("max_force_n".into(), tally.f_max),
            ("min_force_n".into(), tally.f_min),
            ("mean_tangential_force_n".into(), -tally.q_sum / m),
            ("steps".into(), stats.steps as f64),
            ("brakings".into(), stats.brakings as f64),
            ("build_s".into(), build_s),
            ("loop_s".into(), tally.loop_s),
            ("wear_bookkeeping_s".into(), tally.bookkeeping.as_secs_f64()),
        ];
        scalars.extend(plastic_scalars);
        Ok(PassResult {
            wear_depth: tally.wear,
            plastic,
            scalars,
        })
    }

    /// The pass's simulation of the wheel `wm` on its base at the study's radius, a
    /// plastic wheel (`body`) starting in equilibrium with its carried state (module
    /// docs); its steps.
    fn simulation(
        &self,
        wm: &WheelModel,
        body: Option<&crate::plasticity::PlasticBody>,
    ) -> Result<(Simulation, usize), RunError> {
        let h = self.run.params.h;
        let steps = (self.ws.duration() / h).round() as usize;
        let mut problem = wm.problem(
            self.run.integrator,
            h,
            self.ws.gamma_schedule(self.run.params.gamma),
            self.run.contact,
            steps,
        );
        problem.friction = self.run.friction;
        problem.obstacles[0] = Box::new(RotatingLine {
            radius: self.base_radius,
            ..wm.base()
        });
        let sim_error = |source| RunError::Simulation {
            run: self.run.label.clone(),
            source,
        };
        let linalg = |e: crate::linalg::LinalgError| RunError::input(&self.path, e);
        if let (Some(c), Some(body)) = (&self.plastic, body) {
            // Start in equilibrium with the carried state (module docs).
            let up = crate::plasticity::residual_displacement(
                body,
                &c.state,
                (wm.model.pattern(), &wm.model.k, &wm.fixed_dofs),
            )
            .map_err(linalg)?;
            problem.u0.iter_mut().zip(&up).for_each(|(u, d)| *u += d);
        }
        let mut sim = Simulation::new(problem).map_err(sim_error)?;
        sim.set_par(self.par);
        if let (Some(c), Some(body)) = (&self.plastic, body) {
            sim.set_internal_force(
                Box::new(body.clone()),
                c.pl.tolerance,
                crate::model::DEFAULT_MAX_ITERATIONS,
            )
            .map_err(sim_error)?;
            sim.set_internal_state(&c.state).map_err(sim_error)?;
        }
        Ok((sim, steps))
    }

    /// Rolls the pass's `steps`, the wear depth of each rim node of `wm` and the forces
    /// summed over the last full turn.
    fn roll(
        &self,
        sim: &mut Simulation,
        wm: &WheelModel,
        steps: usize,
        interrupt: &AtomicBool,
    ) -> Result<Tally, RunError> {
        let h = self.run.params.h;
        let n = wm.rim.len();
        let area = self.dx * self.ws.spec.thickness;
        let speed = self.speed();
        let turn = 2.0 * PI / self.ws.spec.omega.abs();
        let t_end = steps as f64 * h;
        // The last full turn: (t_end - turn, t_end].
        let t_from = t_end - turn - 0.5 * h;
        let mut wear = vec![0.0; n];
        let (mut f_sum, mut f_max, mut f_min, mut q_sum, mut samples) =
            (0.0, f64::NEG_INFINITY, f64::INFINITY, 0.0, 0usize);
        let mut bookkeeping = std::time::Duration::ZERO;
        let (law, density) = (self.law, self.density);
        let loop_start = Instant::now();
        let stats = sim
            .run(interrupt, |s| {
                let st = s.state;
                if st.t <= t_from {
                    return Ok(());
                }
                let t0 = Instant::now();
                let mut q = 0.0;
                for (w, ps) in wear.iter_mut().zip(&st.pairs) {
                    q += ps.tangential_force;
                    let t_abs = ps.tangential_force.abs();
                    if ps.force <= 0.0 || t_abs <= 0.0 || ps.slip_power <= 0.0 {
                        continue;
                    }
                    let sample = ContactSample {
                        normal_force: ps.force,
                        tangential_force: t_abs,
                        slip_speed: ps.slip_power / t_abs,
                        area,
                        rolling_speed: speed,
                    };
                    *w += law.depth_rate(&sample, density) * h;
                }
                bookkeeping += t0.elapsed();
                f_sum += s.contact_force;
                f_max = f_max.max(s.contact_force);
                f_min = f_min.min(s.contact_force);
                q_sum += q;
                samples += 1;
                Ok(())
            })
            .map_err(|source| RunError::Simulation {
                run: self.run.label.clone(),
                source,
            })?;
        Ok(Tally {
            wear,
            f_sum,
            f_max,
            f_min,
            q_sum,
            samples,
            bookkeeping,
            loop_s: loop_start.elapsed().as_secs_f64(),
            stats,
        })
    }
}

/// What a pass's rolling gave: the wear depth per rim node, the contact and tangential
/// forces over the last full turn (sum, extremes, samples), the time spent on the wear's
/// bookkeeping and in the loop, the run's counters.
struct Tally {
    wear: Vec<f64>,
    f_sum: f64,
    f_max: f64,
    f_min: f64,
    q_sum: f64,
    samples: usize,
    bookkeeping: std::time::Duration,
    loop_s: f64,
    stats: crate::simulation::RunStats,
}

/// A pass's named figures.
type Scalars = Vec<(String, f64)>;

/// A plastic wheel's pass from the carried state `c` to `end` (ignored unless it is a
/// whole state): the change of the permanent radial displacement per rim node (zero-mean)
/// and the pass's plastic figures; with `commit` the carried state and profile advance,
/// else (the reference pass) they stay and the change returned is zero.
fn plastic_change(
    c: &mut Carried,
    body: &crate::plasticity::PlasticBody,
    wm: &WheelModel,
    end: Vec<f64>,
    stats: &crate::simulation::RunStats,
    commit: bool,
) -> Result<(Vec<f64>, Scalars), crate::linalg::LinalgError> {
    let mut plastic = vec![0.0; wm.rim.len()];
    if end.len() != c.state.len() {
        return Ok((plastic, Vec::new()));
    }
    let reference = wm.mesh.reference_positions();
    let stiffness = (wm.model.pattern(), &wm.k_elastic[..], &wm.fixed_dofs[..]);
    let before = crate::plasticity::permanent_radial_displacement(
        body, &c.state, stiffness, &reference, &wm.rim,
    )?;
    let after = crate::plasticity::permanent_radial_displacement(
        body, &end, stiffness, &reference, &wm.rim,
    )?;
    for (d, (a, b)) in plastic.iter_mut().zip(after.iter().zip(&before)) {
        *d = a.1 - b.1;
    }
    let mean = crate::growth::spectrum::mean(&plastic);
    plastic.iter_mut().for_each(|d| *d -= mean);
    let mut eq = vec![0.0; wm.triangles.len()];
    body.equivalent_plastic_strain_into(&end, &mut eq);
    let mut eq0 = vec![0.0; wm.triangles.len()];
    body.equivalent_plastic_strain_into(&c.state, &mut eq0);
    let flow = eq.iter().zip(&eq0).fold(0.0, |m: f64, (a, b)| m.max(a - b));
    let scalars = vec![
        ("plastic_strain_increment_max".into(), flow),
        (
            "plastic_increment_rms_m".into(),
            crate::growth::spectrum::rms(&plastic),
        ),
        ("plastic_mean_m".into(), mean),
        (
            "max_equivalent_plastic_strain".into(),
            eq.iter().fold(0.0, |a: f64, &b| a.max(b)),
        ),
        (
            "plastic_iterations_per_step".into(),
            stats.plastic_iterations as f64 / stats.steps.max(1) as f64,
        ),
        (
            "plastic_unconverged".into(),
            stats.plastic_unconverged as f64,
        ),
    ];
    if commit {
        c.state = end;
        c.profile
            .iter_mut()
            .zip(&plastic)
            .for_each(|(p, d)| *p += d);
    } else {
        // The reference pass leaves the profile and the state as they were.
        plastic.fill(0.0);
    }
    Ok((plastic, scalars))
}
