//! Coulomb friction against exact rigid-body answers: a stiff elastic block (plane-stress
//! triangles, lumped mass) on a rigid plane under gravity, its bottom nodes as contact pairs,
//! with the space-time scheme (exact hold, the soft way) and the generalized-alpha family
//! (exact enforcement).
//!
//! The block is 1 m x 0.25 m x 1 m of density 1000 kg/m^3 (m = 250 kg), E = 1 GPa and
//! Poisson's ratio 0 (no lateral expansion under its weight, so the static state has no
//! tangential reaction), g = 10 m/s^2, mu = 0.3: `mu m g = 750 N`. Loads are body forces
//! (`m_i a(t)` per node), so the block's centre of mass obeys `m a_x = F - friction`
//! whatever its (tiny) deformation. The tangent of the floor (normal `+y` turned by +90
//! degrees) is `-x`.
//!
//! Every run ([`run`]) also asserts at every step that friction dissipates (issue 33): no
//! pair's `slip_power` is negative and the friction energy never falls, beyond a round-off
//! floor ([`dissipation_floor`]).

use softway::assembly::{assemble_mass_stiffness, Assembler};
use softway::contact::{FrictionLaw, HalfSpace, Obstacle, Pair, Plane, Restore, Treatment};
use softway::linalg::spmv_add;
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::rectangle;
use softway::model::LinearModel;
use softway::simulation::{Problem, RunStats, SimError, Simulation};
use softway::time::classic::ClassicParams;
use softway::time::{ClassicKind, Integrator};
use softway::wheel::{static_solve, triangle_geometry};
use std::sync::atomic::AtomicBool;

const G: f64 = 10.0;
const MU: f64 = 0.3;
const MASS: f64 = 250.0;

/// One recorded step.
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    x: f64,
    v: f64,
    friction: f64,
    all_sliding: bool,
    dissipated: f64,
    kinetic: f64,
    strain: f64,
    /// Energy held by the contact springs (penalty, tangential stick), J.
    stored: f64,
}

struct Trace {
    samples: Vec<Sample>,
    stats: RunStats,
}

fn space_time() -> Integrator {
    Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.0,
        coriolis: softway::time::Coriolis::Implicit,
    }
}

fn gen_alpha() -> Integrator {
    Integrator::Classic {
        kind: ClassicKind::GeneralizedAlpha,
        params: ClassicParams::generalized_alpha(0.8).unwrap(),
    }
}

/// The block: `ax(t)` the horizontal body acceleration of the load (m/s^2), `v0` the initial
/// horizontal velocity, `lift` the initial height above the plane (0: resting in its static
/// equilibrium on it).
#[allow(clippy::too_many_arguments)]
fn block(
    integrator: Integrator,
    treatment: Treatment,
    friction: Option<f64>,
    h: f64,
    t_end: f64,
    ax: fn(f64) -> f64,
    v0: f64,
    lift: f64,
) -> Problem {
    let mesh = rectangle(1.0, 0.25, 4, 1).unwrap();
    let (_, geom) = triangle_geometry(&mesh).unwrap();
    let mat = Elastic {
        young: 1e9,
        poisson: 0.0,
        density: 1000.0,
    };
    let d = PlaneModel::Stress.elasticity_matrix(&mat);
    let asm = Assembler::new(&mesh);
    let (m, k) = assemble_mass_stiffness(&asm, &geom, &d, &mat, 1.0, true);
    let n = mesh.n_dofs();
    let mut nodal = vec![0.0; n];
    spmv_add(&asm.pattern, &m, 1.0, &vec![1.0; n], &mut nodal);
    let total: f64 = nodal.iter().step_by(2).sum();
    assert!((total - MASS).abs() < 1e-9, "{total}");
    let bottom = mesh.node_sets["bottom"].clone();
    let mut gravity = vec![0.0; n];
    for i in 0..n / 2 {
        gravity[2 * i + 1] = -G * nodal[2 * i + 1];
    }
    let u0 = if lift == 0.0 {
        let fixed: Vec<usize> = bottom.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
        static_solve(&asm, &k, &gravity, &fixed).unwrap()
    } else {
        (0..n)
            .map(|d| if d % 2 == 1 { lift } else { 0.0 })
            .collect()
    };
    let mut v = vec![0.0; n];
    for i in 0..n / 2 {
        v[2 * i] = v0;
    }
    let model = LinearModel {
        c: asm.zeros(),
        assembler: asm,
        m,
        k,
    };
    let floor: Box<dyn Obstacle> = Box::new(Plane {
        half_space: HalfSpace {
            normal: [0.0, 1.0, 0.0],
            offset: 0.0,
        },
    });
    Problem {
        dim: 2,
        reference: mesh.reference_positions(),
        model,
        integrator,
        h,
        gamma_schedule: vec![],
        dirichlet: vec![],
        load: Box::new(move |t, f| {
            let a = ax(t);
            for i in 0..f.len() / 2 {
                f[2 * i] = nodal[2 * i] * a;
                f[2 * i + 1] = gravity[2 * i + 1];
            }
        }),
        obstacles: vec![floor],
        interfaces: Vec::new(),
        pairs: bottom
            .iter()
            .map(|&node| Pair::Obstacle { node, obstacle: 0 })
            .collect(),
        treatment,
        u0,
        v0: v,
        t0: 0.0,
        steps: (t_end / h).round() as usize,
        gap_tol: 1e-12,
        energy_stiffness: None,
        friction: friction.map(Into::into),
    }
}

/// The speed scale of the block's runs, m/s: no run here goes faster than 2 m/s.
const V_REF: f64 = 10.0;

/// The round-off floor of a pair's dissipation per unit friction force, m/s: a sticking
/// pair's `slip_power / |F_t|` is its slip rate at the step's end, held at 0 by its row to
/// the round-off of the rows' solve, `1e3 eps V_REF` (the residual measured here and on the
/// wheel is 1-30 `eps` times the speed scale). With an elastic stick the stored energy's
/// growth `(F^2 - F0^2) / (2 k_t h)` is subtracted: its round-off per unit force is `eps
/// |F| / (k_t h)`, counted with the same factor.
fn dissipation_floor(pb: &Problem) -> (f64, f64) {
    let kt = match (pb.friction.map(|l| l.tangential_stiffness), pb.treatment) {
        (Some(k), _) if k > 0.0 => k,
        (_, Treatment::Penalty { stiffness }) => stiffness,
        _ => f64::INFINITY,
    };
    (1e3 * f64::EPSILON * V_REF, 1e3 * f64::EPSILON / (kt * pb.h))
}

/// Runs the problem and asserts at every step that friction dissipates (issue 33): every
/// pair's `slip_power >= 0` and the friction energy never decreases, to the round-off floor
/// of [`dissipation_floor`].
fn run(pb: Problem) -> Result<Trace, SimError> {
    let (floor_v, floor_f) = dissipation_floor(&pb);
    let h = pb.h;
    let n = pb.model.n();
    let mut nodal = vec![0.0; n];
    spmv_add(
        pb.model.pattern(),
        &pb.model.m,
        1.0,
        &vec![1.0; n],
        &mut nodal,
    );
    let mut sim = Simulation::new(pb)?;
    let mut samples: Vec<Sample> = Vec::new();
    let stats = sim.run(&AtomicBool::new(false), |view| {
        let s = view.state;
        let mut allowed = 0.0;
        for (p, ps) in s.pairs.iter().enumerate() {
            let f = ps.tangential_force.abs();
            let floor = f * (floor_v + f * floor_f);
            assert!(
                ps.slip_power >= -floor,
                "t {}: pair {p} dissipates {:e} W (floor {floor:e} W, force {:e} N, sliding {})",
                s.t,
                ps.slip_power,
                ps.tangential_force,
                ps.sliding
            );
            allowed += floor * h;
        }
        if let Some(prev) = samples.last() {
            assert!(
                view.friction_dissipated >= prev.dissipated - allowed,
                "t {}: the friction energy falls from {:e} to {:e} J",
                s.t,
                prev.dissipated,
                view.friction_dissipated
            );
        }
        let (mut x, mut v) = (0.0, 0.0);
        for i in 0..n / 2 {
            x += nodal[2 * i] * s.u[2 * i];
            v += nodal[2 * i] * s.v[2 * i];
        }
        samples.push(Sample {
            t: s.t,
            x: x / MASS,
            v: v / MASS,
            friction: s.pairs.iter().map(|p| p.tangential_force).sum(),
            all_sliding: s.pairs.iter().all(|p| p.sliding),
            dissipated: view.friction_dissipated,
            kinetic: view.kinetic(),
            strain: view.strain(),
            stored: view.penalty,
        });
        Ok(())
    })?;
    Ok(Trace { samples, stats })
}

fn ramp(t: f64) -> f64 {
    // F(t) = min(1500 t, 1125) N on 250 kg: mu m g = 750 N is reached at t = 0.5 s.
    (1500.0 * t).min(1125.0) / MASS
}

fn no_push(_t: f64) -> f64 {
    0.0
}

/// The ramp's figures: the first time every pair slides (s), the largest `|x|` before
/// `mu m g` is reached (m), and the acceleration over `[0.8, 1] s` (m/s^2).
fn ramp_figures(tr: &Trace, h: f64) -> (f64, f64, f64) {
    let switch = tr.samples.iter().find(|s| s.all_sliding).unwrap().t;
    let stick = tr
        .samples
        .iter()
        .filter(|s| s.t < 0.5 - 2.0 * h)
        .map(|s| s.x.abs())
        .fold(0.0, f64::max);
    let a = (at(tr, 1.0).v - at(tr, 0.8).v) / (at(tr, 1.0).t - at(tr, 0.8).t);
    (switch, stick, a)
}

fn at(tr: &Trace, t: f64) -> Sample {
    *tr.samples
        .iter()
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        .unwrap()
}

/// The two exact enforcements: the space-time exact hold and generalized-alpha (0.8) with
/// Signorini at the step end (the undamped Newmark rule keeps the contact forces of a held
/// node alternating from step to step, a known defect of displacement-level Signorini with
/// the trapezoidal rule, so friction's bound alternates with them; see the module docs of
/// `softway::contact::complementarity`).
fn exact_runs() -> [(&'static str, Integrator); 2] {
    [("space_time", space_time()), ("gen_alpha", gen_alpha())]
}

/// [`exact_runs`] with exact enforcement and with mass redistribution (the contact nodes
/// massless, then exact enforcement).
fn exact_runs_mr() -> Vec<(String, Integrator, Treatment)> {
    exact_runs()
        .into_iter()
        .flat_map(|(name, integ)| {
            [
                (name.to_string(), integ, Treatment::Exact),
                (
                    format!("{name} mass_redistribution"),
                    integ,
                    Treatment::MassRedistribution,
                ),
            ]
        })
        .collect()
}

/// A body force rising as 1500 t N (held at 1125 N from 0.75 s): the block sticks while it
/// is below `mu m g = 750 N` (t < 0.5 s), then slides with `(F - mu m g)/m`: 1.5 m/s^2
/// after 0.75 s, and `v(1 s) = 1500 (0.25)^2 / (2 m) + 1.5 * 0.25 = 0.5625 m/s`.
#[test]
fn ramp_sticks_below_mu_n_and_slides_with_the_exact_acceleration() {
    let h = 1e-3;
    for (name, integ, treatment) in exact_runs_mr() {
        let tr = run(block(integ, treatment, Some(MU), h, 1.0, ramp, 0.0, 0.0)).unwrap();
        let (switch, stick, a) = ramp_figures(&tr, h);
        let v1 = at(&tr, 1.0).v;
        // In stick the friction balances the push; sliding it is mu m g against the motion
        // (along the tangent -x: positive).
        let f_stick = at(&tr, 0.3).friction;
        let f_slide = at(&tr, 0.9).friction;
        eprintln!(
            "{name}: switch {switch:.4} s (exact 0.5), stick |x| <= {stick:.2e} m, a {a:.6} (exact 1.5), v(1) {v1:.6} (exact 0.5625), friction {f_stick:.3} N at 0.3 s (exact 450), {f_slide:.3} N sliding (exact 750), {:?}",
            tr.stats
        );
        assert!((switch - 0.5).abs() <= 2.0 * h + 1e-9, "{name}: {switch}");
        assert!(stick < 1e-6, "{name}: {stick}");
        assert!((a - 1.5).abs() < 0.01 * 1.5, "{name}: {a}");
        assert!((v1 - 0.5625).abs() < 0.01 * 0.5625, "{name}: {v1}");
        assert!((f_stick - 450.0).abs() < 0.01 * 450.0, "{name}: {f_stick}");
        assert!((f_slide - 750.0).abs() < 0.01 * 750.0, "{name}: {f_slide}");
        assert_eq!(tr.stats.factorizations, 1, "{name}");
        assert!(tr.stats.stick_slip_changes > 0, "{name}");
    }
}

/// Launched at 2 m/s along the plane, the block stops after `v0^2 / (2 mu g) = 2/3 m`, and
/// friction dissipates the kinetic energy lost (500 J) less the small elastic energy left
/// and less the kinetic energy of the impulses' velocity jumps. Friction dissipates
/// `-F_t s_1 h` a step, on the slip rate at the step's end that its row holds
/// (`softway::contact::treatment::record_friction`); the kinetic energy of a rigid block
/// whose velocity the friction impulse `J = -mu m g h` changes, `m (v1 - v0) = J`, changes by
/// `J (v0 + v1) / 2 = J v1 - J^2 / (2 m)`: each step loses `J^2 / (2 m)` beyond the
/// friction's `-J v1`, over the `v0 / (mu g h)` steps of the slide `mu m g h v0 / 2`, the
/// fraction `mu g h / v0` of the initial kinetic energy (0.6% at h = 4 ms, 0.15% at 1 ms).
/// That is the scheme's, not friction's: the balance `(D - lost) / KE0` is asserted to be
/// `-mu g h / v0` within 1e-3 (exact for the rigid block; the elastic block's bottom nodes
/// slide together).
#[test]
fn launched_block_stops_after_v0_squared_over_2_mu_g_and_friction_dissipates_its_energy() {
    let exact = 4.0 / (2.0 * MU * G);
    for (name, integ, treatment) in exact_runs_mr() {
        for h in [4e-3, 1e-3] {
            let tr = run(block(integ, treatment, Some(MU), h, 1.0, no_push, 2.0, 0.0)).unwrap();
            let (f, l) = (tr.samples[0], *tr.samples.last().unwrap());
            let err = (l.x - exact) / exact;
            let lost = f.kinetic - l.kinetic - (l.strain - f.strain);
            let balance = (l.dissipated - lost) / f.kinetic;
            eprintln!(
                "{name} h {h:e}: stop {:.6} m (exact {exact:.6}, {:+.2e}), v end {:.1e}, dissipated {:.3} J, energy lost {lost:.3} J ({balance:+.2e} of KE0), {:?}",
                l.x, err, l.v, l.dissipated, tr.stats
            );
            assert!(err.abs() < 0.01, "{name} {h}: {err}");
            assert!(l.v.abs() < 1e-3, "{name} {h}: {}", l.v);
            let impulses = -MU * G * h / 2.0;
            assert!(
                (balance - impulses).abs() < 1e-3,
                "{name} {h}: {balance} (the impulses' {impulses})"
            );
            assert_eq!(tr.stats.factorizations, 1);
        }
    }
}

/// Without friction (`Some(0)` or `None`: the same rows) the block slides forever at `v0`.
#[test]
fn frictionless_block_slides_forever() {
    for (name, integ) in exact_runs() {
        let a = run(block(
            integ,
            Treatment::Exact,
            Some(0.0),
            1e-3,
            1.0,
            no_push,
            2.0,
            0.0,
        ))
        .unwrap();
        let b = run(block(
            integ,
            Treatment::Exact,
            None,
            1e-3,
            1.0,
            no_push,
            2.0,
            0.0,
        ))
        .unwrap();
        let dv = a
            .samples
            .iter()
            .map(|s| (s.v - 2.0).abs())
            .fold(0.0, f64::max);
        let l = a.samples.last().unwrap();
        eprintln!(
            "{name}: max |v - v0| {dv:.1e}, x(1) - 2 = {:.1e}",
            l.x - 2.0
        );
        assert!(dv < 1e-9, "{name}: {dv}");
        assert!((l.x - 2.0).abs() < 1e-9, "{name}: {}", l.x);
        assert_eq!(l.dissipated, 0.0);
        for (p, q) in a.samples.iter().zip(&b.samples) {
            assert_eq!((p.x, p.v), (q.x, q.v), "{name}");
        }
    }
}

/// The soft way: the block, launched at 2 m/s, starts 20 um above the plane and lands after
/// `t_f = sqrt(2 lift / g) = 2 ms` at `v_n = g t_f = 0.02 m/s`, braked in the step before
/// (normal only). Rigid-body answer with a Coulomb impulse at the landing: it stops at
/// `v0 t_f + (v0 - mu v_n)^2 / (2 mu g)`; without friction in the landing,
/// `v0 t_f + v0^2 / (2 mu g)`. The space-time scheme with `gamma = 0.1` (Eq. 24) damps the
/// stiff block's ringing, which with `gamma = 0` keeps releasing and re-landing its nodes.
#[test]
fn soft_way_landing_block_stops_at_the_rigid_body_distance() {
    let h = 1e-3;
    let lift = 2e-5;
    let integ = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.1,
        coriolis: softway::time::Coriolis::Implicit,
    };
    let tf = (2.0 * lift / G).sqrt();
    let vn = G * tf;
    let exact = 2.0 * tf + (2.0 - MU * vn).powi(2) / (2.0 * MU * G);
    let no_impact = 2.0 * tf + 4.0 / (2.0 * MU * G);
    for treat in [
        Treatment::SOFT_WAY,
        Treatment::SoftWay {
            restore: Restore::Nothing,
        },
    ] {
        let tr = run(block(integ, treat, Some(MU), h, 1.0, no_push, 2.0, lift)).unwrap();
        let l = tr.samples.last().unwrap();
        let err = (l.x - exact) / exact;
        eprintln!(
            "{}: stop {:.6} m (exact {exact:.6}: {err:+.2e}; without landing friction {no_impact:.6}), v end {:.1e}, {:?}",
            treat.name(),
            l.x,
            l.v,
            tr.stats
        );
        assert!(err.abs() < 0.01, "{err}");
        assert!(l.v.abs() < 1e-3);
        assert!(tr.stats.brakings > 0 && tr.stats.step_backs > 0);
        assert_eq!(tr.stats.factorizations, 1);
    }
}

/// Friction on a 1D model (a bar) is refused with the key named.
#[test]
fn friction_is_refused_for_1d_models() {
    let bar = softway::problems::BarImpact {
        length: 1.0,
        ea: 1.0,
        rho_a: 1.0,
        speed: 1.0,
        gap: 0.5,
        elements: 10,
        lumped: true,
        damping: 0.0,
    };
    let (_, mut pb) = bar.problem(space_time(), Treatment::Exact, 0.01, 1.0);
    pb.friction = Some(0.3.into());
    match Simulation::new(pb) {
        Err(SimError::Unsupported(m)) => {
            assert!(m.contains("contact.friction") && m.contains("2D"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    let (_, mut pb) = bar.problem(space_time(), Treatment::Exact, 0.01, 1.0);
    pb.friction = Some(0.0.into());
    assert!(Simulation::new(pb).is_ok());
}

/// The scenario key: `contact.friction` on a bar is refused with one line naming the key; a
/// negative coefficient too.
#[test]
fn scenario_key_is_refused_for_bars_and_negative_values() {
    const BAR: &str = "kind = \"bar_impact\"\n[time]\nalpha = 0.8\nh = 0.1\nt_end = 1.0\n[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n[contact]\nmethod = \"exact\"\n";
    let dir = std::env::temp_dir().join(format!("softway-friction-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, value, must) in [
        ("bar_mu", "0.3", "2D model"),
        ("bar_negative", "-0.1", ">= 0"),
    ] {
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, format!("{BAR}friction = {value}\n")).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .arg("run")
            .arg(&p)
            .arg("--out")
            .arg(dir.join(name))
            .arg("--quiet")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert!(!o.status.success(), "{err}");
        assert_eq!(lines.len(), 1, "{err}");
        assert!(
            err.contains("contact.friction") && err.contains(must),
            "{err}"
        );
    }
    // 0 is frictionless and accepted on a bar.
    let p = dir.join("bar_zero.toml");
    std::fs::write(&p, format!("{BAR}friction = 0.0\n")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
        .arg("run")
        .arg(&p)
        .arg("--out")
        .arg(dir.join("bar_zero"))
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A friction coefficient falling with the slip speed, `mu(v) = mu_k + (mu_s - mu_k)
/// exp(-|v| / v_s)` (`contact.friction_kinetic`, `contact.friction_velocity`): the block
/// launched at `v0` decelerates at `g mu(v)` and stops after `int_0^v0 v / (g mu(v)) dv`
/// (Simpson's rule, 20,000 intervals, as the independent answer), further than with Coulomb
/// at `mu_s` and shorter than at `mu_k`; friction dissipates the kinetic energy lost.
#[test]
fn falling_friction_stops_the_block_at_the_distance_of_its_law() {
    let law = FrictionLaw {
        static_mu: 0.4,
        kinetic: 0.2,
        velocity: 0.5,
        viscosity: 0.0,
        tangential_stiffness: 0.0,
        memory: 0.0,
    };
    let v0 = 2.0;
    let n = 20_000;
    let dv = v0 / n as f64;
    let f = |v: f64| v / (G * law.coefficient(v));
    let exact = dv / 3.0
        * (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(i as f64 * dv)
            })
            .sum::<f64>();
    assert!(exact > v0 * v0 / (2.0 * 0.4 * G) && exact < v0 * v0 / (2.0 * 0.2 * G));
    launched_block_stops_at(law, v0, 1.5, exact, 0.003);
}

/// The falling law with a memory `L` (`contact.friction_memory_um`): a pair's coefficient
/// starts at `mu_s` and relaxes towards `mu(v)` over the distance slid, `d mu / dx = -(mu -
/// mu(v)) / L`. The block launched at `v0` then obeys `v' = -g mu`, `mu' = -(v / L) (mu -
/// mu(v))`, integrated here by fourth-order Runge-Kutta (1e-5 s) to the stop as the
/// independent answer; with `L` = 20 cm it stops 16 % short of the law without memory, and the
/// run must give the memory's distance within 0.5 %.
#[test]
fn falling_friction_with_memory_stops_the_block_where_its_state_says() {
    let law = FrictionLaw {
        static_mu: 0.4,
        kinetic: 0.2,
        velocity: 0.5,
        viscosity: 0.0,
        tangential_stiffness: 0.0,
        memory: 0.2,
    };
    let v0 = 2.0;
    let rate = |[_, v, mu]: [f64; 3]| [v, -G * mu, -(v / law.memory) * (mu - law.coefficient(v))];
    let (mut y, dt) = ([0.0, v0, law.static_mu], 1e-5);
    let exact = loop {
        let add = |y: [f64; 3], k: [f64; 3], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
        let k1 = rate(y);
        let k2 = rate(add(y, k1, dt / 2.0));
        let k3 = rate(add(y, k2, dt / 2.0));
        let k4 = rate(add(y, k3, dt));
        let next: [f64; 3] =
            std::array::from_fn(|i| y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        if next[1] <= 0.0 {
            // The stop within the last step: the speed's zero by linear interpolation.
            let w = y[1] / (y[1] - next[1]);
            break y[0] + w * (next[0] - y[0]);
        }
        y = next;
    };
    // Without memory: the distance of the falling law itself, int v / (g mu(v)) dv.
    let n = 20_000;
    let dv = v0 / n as f64;
    let memoryless: f64 = (0..n)
        .map(|i| {
            let v = (i as f64 + 0.5) * dv;
            v / (G * law.coefficient(v)) * dv
        })
        .sum();
    eprintln!("with memory {exact:.5} m, without {memoryless:.5} m");
    assert!(exact < 0.95 * memoryless, "{exact} {memoryless}");
    launched_block_stops_at(law, v0, 1.5, exact, 0.005);
}

/// The falling law's keys and the stick's spring: each refused alone with one line naming it,
/// and with a bad value.
#[test]
fn falling_law_keys_are_checked() {
    let base = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/wheel-traction.toml"),
    )
    .unwrap();
    let cases = [
        ("friction_kinetic = 0.2", "contact.friction_kinetic"),
        ("friction_velocity = 0.5", "contact.friction_velocity"),
        (
            "friction_kinetic = -0.2\nfriction_velocity = 0.5",
            "contact.friction_kinetic",
        ),
        (
            "friction_kinetic = 0.2\nfriction_velocity = 0.0",
            "contact.friction_velocity",
        ),
        ("tangential_stiffness = 0.0", "contact.tangential_stiffness"),
        (
            "tangential_stiffness = -1e8",
            "contact.tangential_stiffness",
        ),
        ("tangential_stiffness = inf", "contact.tangential_stiffness"),
        ("friction_memory_um = 5", "contact.friction_memory_um"),
        (
            "friction_kinetic = 0.2\nfriction_velocity = 0.5\nfriction_memory_um = 0",
            "contact.friction_memory_um",
        ),
        (
            "friction_kinetic = 0.2\nfriction_velocity = 0.5\nfriction_memory_um = nan",
            "contact.friction_memory_um",
        ),
    ];
    for (extra, key) in cases {
        let text = base.replace("friction = 0.3", &format!("friction = 0.3\n{extra}"));
        let err = softway::scenario::Scenario::from_str(&text, std::path::Path::new("t.toml"))
            .unwrap_err()
            .to_string();
        assert!(err.contains(key) && !err.contains('\n'), "{extra}: {err}");
    }
    let ok = base.replace(
        "friction = 0.3",
        "friction = 0.3\nfriction_kinetic = 0.2\nfriction_velocity = 0.5\nfriction_memory_um = 5\ntangential_stiffness = 1e9",
    );
    assert!(softway::scenario::Scenario::from_str(&ok, std::path::Path::new("t.toml")).is_ok());
    // Without the coefficient beside it, the stick's spring is refused by name.
    let alone = base.replace("friction = 0.3", "tangential_stiffness = 1e9");
    let err = softway::scenario::Scenario::from_str(&alone, std::path::Path::new("t.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("contact.tangential_stiffness"), "{err}");
}

/// Viscoplastic friction (`contact.friction_viscosity`, eta per pair): a sliding pair carries
/// `mu F_n + eta |v|`, so the block of five bottom pairs decelerates at `mu g + b v` with
/// `b = 5 eta / m` and stops after `(v0 - (a/b) ln(1 + b v0 / a)) / b`, `a = mu g` (the exact
/// solution of `v' = -a - b v`): 0.4675 m instead of Coulomb's 2/3 m. The viscosity is per
/// pair, so the answer holds while all five pairs slide (asserted; with h = 2.5e-4 the block's
/// bottom chatters, pairs leave the plane for steps and it stops 9% further).
#[test]
fn viscoplastic_friction_stops_the_block_at_the_exact_distance() {
    let (mu, eta) = (0.1, 20.0);
    let law = FrictionLaw {
        viscosity: eta,
        ..FrictionLaw::coulomb(mu)
    };
    let (v0, a, b) = (2.0, mu * G, 5.0 * eta / MASS);
    let exact = (v0 - (a / b) * (1.0 + b * v0 / a).ln()) / b;
    launched_block_stops_at(law, v0, 2.0, exact, 0.01);
}

/// Launches the block at `v0` on the plane with friction `law` (exact enforcement, both
/// exact integrators, h = 1 ms, `t_end` s) and asserts that it stops at `exact` (m) within
/// the relative `tol`, that friction dissipated the kinetic energy lost (0.5% of the
/// initial) and that nothing was refactored.
fn launched_block_stops_at(law: FrictionLaw, v0: f64, t_end: f64, exact: f64, tol: f64) {
    for (name, integ) in exact_runs() {
        let mut pb = block(integ, Treatment::Exact, None, 1e-3, t_end, no_push, v0, 0.0);
        pb.friction = Some(law);
        let tr = run(pb).unwrap();
        let (f0, l) = (tr.samples[0], *tr.samples.last().unwrap());
        let err = (l.x - exact) / exact;
        let lost = f0.kinetic - l.kinetic - (l.strain - f0.strain);
        let balance = (l.dissipated - lost) / f0.kinetic;
        eprintln!(
            "{name}: stop {:.6} m (exact {exact:.6}, {err:+.2e}), dissipated {:.3} J, lost {lost:.3} J",
            l.x, l.dissipated
        );
        assert!(err.abs() < tol, "{name}: {err}");
        assert!(l.v.abs() < 1e-3, "{name}: {}", l.v);
        assert!(balance.abs() < 0.005, "{name}: {balance}");
        assert_eq!(tr.stats.factorizations, 1, "{name}");
    }
}

/// A constant push held at 300 N (below `mu m g = 750 N`, reached smoothly over 0.5 s), with
/// an elastic stick of `k_t = 1e6 N/m` per pair (`contact.tangential_stiffness`) under the
/// penalty treatment: the block sticks and its five bottom springs share the push, so it
/// shifts by `F / (5 k_t) = 60 um` (the block's own shear compliance, 1/(2e9 N/m), adds
/// 0.25%). The mean offset over the last 0.5 s (several periods of the block on its springs,
/// `2 pi / sqrt(5 k_t / m)` = 44 ms) is asserted within 1.5%, the tangential force within 1%,
/// no pair slides, and nothing is refactored.
#[test]
fn an_elastic_stick_shifts_the_block_by_the_push_over_its_springs() {
    fn push(t: f64) -> f64 {
        let s = (t / 0.5).min(1.0);
        300.0 * s * s * (3.0 - 2.0 * s) / MASS
    }
    let kt = 1e6;
    let exact = 300.0 / (5.0 * kt);
    for (name, integ) in exact_runs() {
        let mut pb = block(
            integ,
            Treatment::Penalty { stiffness: 1e9 },
            None,
            1e-3,
            1.0,
            push,
            0.0,
            0.0,
        );
        pb.friction = Some(FrictionLaw {
            tangential_stiffness: kt,
            ..FrictionLaw::coulomb(MU)
        });
        let tr = run(pb).unwrap();
        let tail: Vec<&Sample> = tr.samples.iter().filter(|s| s.t >= 0.5).collect();
        let mean = tail.iter().map(|s| s.x).sum::<f64>() / tail.len() as f64;
        let force = tail.iter().map(|s| s.friction).sum::<f64>() / tail.len() as f64;
        let slid = tr.samples.iter().filter(|s| s.all_sliding).count();
        eprintln!(
            "{name}: offset {mean:.4e} m (exact {exact:.4e}, {:+.2e}), tangential force {force:.2} N (300 along -x), steps all sliding {slid}, {:?}",
            mean / exact - 1.0,
            tr.stats
        );
        // The floor's tangent is -x: the force holding the block back is +300 along it.
        assert!((mean / exact - 1.0).abs() < 0.015, "{name}: {mean}");
        assert!((force - 300.0).abs() < 3.0, "{name}: {force}");
        assert_eq!(slid, 0, "{name}");
        assert_eq!(tr.stats.factorizations, 1, "{name}");
    }
}

/// The penalty treatment with friction takes an elastic stick of the normal stiffness
/// (`k_t = k_n`, here 1e9 N/m per pair) unless told otherwise. With the push ramp of the
/// exact tests the block sticks (within the springs' `F / (5 k_t)`, under a micrometre) while
/// the push is below `mu m g`, slips when it reaches it (the return mapping: every pair at
/// `mu F_n`), then slides with the exact `(F - mu m g) / m = 1.5 m/s^2`. Launched at 2 m/s, it
/// stops after `v0^2 / (2 mu g)`, and the energy lost is what friction dissipated plus what
/// the springs hold. The space-time scheme runs with `gamma = 0.1`: undamped (`gamma = 0`),
/// the block rings on its stiff springs from the slip onset on and its bottom pairs leave
/// the plane and land again during the sliding (measured: 170-230 entries instead of 5).
#[test]
fn penalty_friction_sticks_slips_and_stops_like_coulomb() {
    let h = 1e-3;
    let treatment = Treatment::Penalty { stiffness: 1e9 };
    let damped = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.1,
        coriolis: softway::time::Coriolis::Implicit,
    };
    for (name, integ) in [("space_time", damped), ("gen_alpha", gen_alpha())] {
        let tr = run(block(integ, treatment, Some(MU), h, 1.0, ramp, 0.0, 0.0)).unwrap();
        let (switch, stick, a) = ramp_figures(&tr, h);
        let f_slide = at(&tr, 0.9).friction;
        eprintln!(
            "{name} ramp: switch {switch:.4} s (exact 0.5), stick |x| <= {stick:.2e} m (springs {:.2e}), a {a:.6} (1.5), sliding force {f_slide:.3} N (750), {:?}",
            750.0 / 5e9,
            tr.stats
        );
        assert!((switch - 0.5).abs() <= 3.0 * h, "{name}: {switch}");
        assert!(stick < 1e-6, "{name}: {stick}");
        assert_eq!(tr.stats.entries, 5, "{name}");
        assert!((a - 1.5).abs() < 0.01 * 1.5, "{name}: {a}");
        assert!((f_slide - 750.0).abs() < 0.01 * 750.0, "{name}: {f_slide}");
        assert_eq!(tr.stats.factorizations, 1, "{name}");

        let exact = 4.0 / (2.0 * MU * G);
        let tr = run(block(integ, treatment, Some(MU), h, 1.0, no_push, 2.0, 0.0)).unwrap();
        let (f, l) = (tr.samples[0], *tr.samples.last().unwrap());
        let err = (l.x - exact) / exact;
        let lost = f.kinetic - l.kinetic - (l.strain - f.strain) - (l.stored - f.stored);
        let balance = (l.dissipated - lost) / f.kinetic;
        eprintln!(
            "{name} launched: stop {:.6} m (exact {exact:.6}, {err:+.2e}), dissipated {:.3} J, lost {lost:.3} J ({balance:+.2e} of KE0), springs hold {:.2e} J",
            l.x, l.dissipated, l.stored
        );
        assert!(err.abs() < 0.01, "{name}: {err}");
        assert!(l.v.abs() < 1e-3, "{name}: {}", l.v);
        assert!(balance.abs() < 0.005, "{name}: {balance}");
    }
}

/// A stiff tangential spring approaches the rigid stick: with `k_t = 1e12 N/m` the exact
/// treatment's ramp (stick, slip, slide) matches the rigid-stick run to 1e-6 m in position
/// and 5e-3 of `mu m g` in the friction force over the whole run.
#[test]
fn a_stiff_stick_spring_tends_to_the_rigid_stick() {
    for (name, integ) in exact_runs() {
        let rigid = run(block(
            integ,
            Treatment::Exact,
            Some(MU),
            1e-3,
            1.0,
            ramp,
            0.0,
            0.0,
        ))
        .unwrap();
        let mut pb = block(integ, Treatment::Exact, None, 1e-3, 1.0, ramp, 0.0, 0.0);
        pb.friction = Some(FrictionLaw {
            tangential_stiffness: 1e12,
            ..FrictionLaw::coulomb(MU)
        });
        let stiff = run(pb).unwrap();
        let (mut dx, mut df) = (0.0_f64, 0.0_f64);
        for (a, b) in rigid.samples.iter().zip(&stiff.samples) {
            dx = dx.max((a.x - b.x).abs());
            df = df.max((a.friction - b.friction).abs());
        }
        eprintln!("{name}: max |dx| {dx:.2e} m, max |dF| {df:.2e} N");
        assert!(dx < 1e-6, "{name}: {dx}");
        assert!(df < 5e-3 * 750.0, "{name}: {df}");
    }
}
