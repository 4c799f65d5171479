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
//! stick does not slip).

use super::{PassResult, PassRunner, SurfaceProfile};
use crate::contact::obstacle::RotatingLine;
use crate::linalg::team::Par;
use crate::run::wheel::build;
use crate::run::RunError;
use crate::scenario::{Model, Run, Scenario, WheelScenario};
use crate::simulation::Simulation;
use crate::wear::{ContactSample, WearLaw};
use crate::wheel::{Coupling, WheelModel};
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
        let Model::Wheel(ws) = &run.model else {
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
        let friction = run.friction.is_some_and(|l| l.is_active());
        if !friction {
            return Err(RunError::input(&path, "contact.friction: the wear laws need the friction force and the slip (give contact.friction > 0 and a rolling.creepage)"));
        }
        let smooth = build(ws, &path)?;
        let n = smooth.rim.len();
        let r = ws.spec.radius;
        let dx = 2.0 * PI * r / n as f64;
        let angle = |i: usize| {
            let p = smooth.mesh.point(i);
            p[1].atan2(p[0])
        };
        let a0 = angle(smooth.rim[0]);
        for (k, &i) in smooth.rim.iter().enumerate() {
            let want = a0 + 2.0 * PI * k as f64 / n as f64;
            let d = (angle(i) - want + PI).rem_euclid(2.0 * PI) - PI;
            if d.abs() > 1e-6 {
                return Err(RunError::input(&path, format!("the rim's nodes are not evenly spaced (node {k} of {n} is {:.3e} rad off): the growth study needs one profile sample per rim node at one pitch (a generated disk with wheel.rim_nodes)", d)));
            }
        }
        let base_radius = smooth.base().radius;
        let density = density.unwrap_or(ws.spec.material.density);
        Ok(Self {
            ws: (**ws).clone(),
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

    /// The model with the rim moved radially by the profile.
    fn model(&self, profile: &SurfaceProfile) -> Result<WheelModel, RunError> {
        let mut mesh = self.smooth.mesh.clone();
        for (&node, &z) in self.smooth.rim.iter().zip(&profile.z) {
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
        let build_start = Instant::now();
        let wm = self.model(profile)?;
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
        let mut sim = Simulation::new(problem).map_err(sim_error)?;
        sim.set_par(self.par);
        let build_s = build_start.elapsed().as_secs_f64();
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
            .map_err(sim_error)?;
        let loop_s = loop_start.elapsed().as_secs_f64();
        let m = samples.max(1) as f64;
        Ok(PassResult {
            wear_depth: wear,
            plastic: vec![0.0; n],
            scalars: vec![
                ("mean_force_n".into(), f_sum / m),
                ("max_force_n".into(), f_max),
                ("min_force_n".into(), f_min),
                ("mean_tangential_force_n".into(), -q_sum / m),
                ("steps".into(), stats.steps as f64),
                ("brakings".into(), stats.brakings as f64),
                ("build_s".into(), build_s),
                ("loop_s".into(), loop_s),
                ("wear_bookkeeping_s".into(), bookkeeping.as_secs_f64()),
            ],
        })
    }
}
