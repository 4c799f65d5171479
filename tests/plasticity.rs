//! The plastic wheel rolling over its rigid base: Johnson's line-contact rolling shakedown
//! (Contact Mechanics, 1985, §9.2; issue 31). An elastic-perfectly-plastic wheel (von Mises,
//! `k = sigma_y / sqrt 3`), plane strain, frictionless, rolled slowly (quasi-static) by the
//! turning base: first yield at `p0 / k = 3.1` at depth `0.78 a` below the contact, elastic
//! shakedown below `p0 / k = 4.0` (the plastic strain added per turn falls to zero) and
//! ratchetting above it (the plastic strain keeps growing by about the same amount each turn).
//! `p0` and `a` are Hertz's for a cylinder on a rigid plane in plane strain from the measured
//! contact force per unit thickness `P`: `a^2 = 4 P R / (pi E*)`, `p0 = 2 P / (pi a)`,
//! `E* = E / (1 - nu^2)`.
//!
//! Hertz needs a body large against the contact: the wheel of radius `R = 0.1 m` on a hub
//! of 5 cm carries a patch of `a / R = 0.03` (12 rim pitches across `2a`, the hub 17 `a`
//! below the surface). On a wheel of `a / R = 0.1` on a hub 3.7 `a` deep (360 rim nodes)
//! the ring's own bending adds about `0.07 p0` to `sqrt(J2)` everywhere under the contact
//! and the first yield comes at `p0 / k = 2.5`: not Johnson's problem.
//!
//! Also here: a plate in uniaxial tension loaded past yield and unloaded through the
//! driver, against the exact elastic-plastic answer (the initial-stress iteration on the
//! elastic factor end to end).

use softway::contact::obstacle::Flattening;
use softway::contact::Treatment;
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::{disk_graded, DiskOptions};
use softway::plasticity::{Isotropic, J2Material, Kinematic, PlasticBody, STATE_LEN};
use softway::simulation::Simulation;
use softway::time::{Coriolis, Integrator};
use softway::wheel::{ContactSurface, Coupling, Support, WheelModel, WheelSpec};
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

const STEEL: Elastic = Elastic {
    young: 2.05e11,
    poisson: 0.3,
    density: 7830.0,
};
const R: f64 = 0.1;
const THICK: f64 = 0.01;
/// Rim nodes: 12 pitches across `2a`.
fn rim() -> usize {
    1260
}
/// Hub radius, m.
fn hub() -> f64 {
    0.05
}
/// Steps per rim pitch while rolling.
const STEPS_PER_PITCH: usize = 4;
/// The step, s: far above the wheel's periods (quasi-static rolling on the damped scheme).
const H: f64 = 1e-3;
const SETTLE_STEPS: usize = 40;
/// The flattening, m (`a / R = 0.03`).
fn depth() -> f64 {
    1.6e-4
}

fn wheel() -> WheelModel {
    let omega = 2.0 * PI / (rim() * STEPS_PER_PITCH) as f64 / H;
    let spec = WheelSpec {
        radius: R,
        thickness: THICK,
        material: STEEL,
        plane: PlaneModel::Strain,
        lumped: false,
        damping: 0.0,
        support: Support::Hub { radius: hub() },
        omega,
        flattening: Flattening {
            depth: depth(),
            settle_time: SETTLE_STEPS as f64 * H,
        },
        stress_stiffening: false,
        rotating_frame: false,
        creepage: 0.0,
        surface: ContactSurface::Nodes,
        coupling: Coupling::Coupled,
    };
    let mesh = disk_graded(
        R,
        rim(),
        DiskOptions {
            grading: 1.1,
            hub: Some(hub()),
        },
    )
    .unwrap();
    WheelModel::new(mesh, spec).unwrap()
}

fn e_star() -> f64 {
    STEEL.young / (1.0 - STEEL.poisson * STEEL.poisson)
}

/// Hertz: `(a, p0)` for the force per unit thickness `p` (N/m).
fn hertz(p: f64) -> (f64, f64) {
    let a = (4.0 * p * R / (PI * e_star())).sqrt();
    (a, 2.0 * p / (PI * a))
}

/// The elastic wheel pressed by the base: the contact force per unit thickness `P` (N/m),
/// and the element of the largest `sqrt(J2)` (Pa) with its depth below the rim (m).
fn pressed(wm: &WheelModel) -> (f64, f64, f64) {
    let steps = SETTLE_STEPS + 2;
    let integ = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.2,
        coriolis: Coriolis::Implicit,
    };
    // The base turns from the start (slowly: quasi-static); the force and the stresses are
    // taken at the end of settling.
    let problem = wm.problem(integ, H, Vec::new(), Treatment::SOFT_WAY, steps);
    let mut sim = Simulation::new(problem).unwrap();
    let mut out = (0.0, 0.0, 0.0);
    let mut s = vec![[0.0; 3]; wm.triangles.len()];
    sim.run(&AtomicBool::new(false), |v| {
        if v.state.k == SETTLE_STEPS + 1 {
            wm.stresses_into(&v.state.u, &mut s);
            let mut best = (0.0, 0.0);
            for (e, t) in wm.triangles.iter().enumerate() {
                let (j2, _) = PlaneModel::Strain.stress_invariants(&STEEL, s[e]);
                if j2.sqrt() > best.0 {
                    let c = [0, 1].map(|k| {
                        (wm.mesh.point(t[0])[k] + wm.mesh.point(t[1])[k] + wm.mesh.point(t[2])[k])
                            / 3.0
                    });
                    best = (j2.sqrt(), R - c[0].hypot(c[1]));
                }
            }
            out = (v.contact_force / THICK, best.0, best.1);
        }
        Ok(())
    })
    .unwrap();
    out
}

/// `J2`'s largest `sqrt` under Hertz's line contact (plane strain, `nu = 0.3`, on the axis):
/// `(max sqrt(J2) / p0, depth / a)` from the closed-form axis stresses
/// `sigma_z = -p0 a / sqrt(a^2 + z^2)`, `sigma_x = -p0 [(a^2 + 2 z^2) / (a sqrt(a^2 + z^2))
/// - 2 z / a]`, `sigma_y = nu (sigma_x + sigma_z)` (Johnson, Eq. 4.49).
fn hertz_first_yield() -> (f64, f64) {
    let nu = STEEL.poisson;
    let mut best = (0.0, 0.0);
    for i in 1..4000 {
        let z = i as f64 * 5e-4;
        let sz = -1.0 / (1.0 + z * z).sqrt();
        let sx = -((1.0 + 2.0 * z * z) / (1.0 + z * z).sqrt() - 2.0 * z);
        let sy = nu * (sx + sz);
        let j2 = ((sx - sz).powi(2) + (sz - sy).powi(2) + (sy - sx).powi(2)) / 6.0;
        if j2.sqrt() > best.0 {
            best = (j2.sqrt(), z);
        }
    }
    best
}

#[test]
fn first_yield_under_the_pressed_wheel_is_hertzs() {
    // Johnson: p0 / k = 3.1 at 0.70 a (von Mises, nu = 0.3); the closed form here 3.107 at
    // 0.705 a. The wheel's constant-strain triangles, 12 across 2a (elements of a / 6 at
    // the surface, graded by 1.1 inwards), put the largest element value 10% above it
    // (p0 / k = 2.79 at 0.72 a): the test allows 12% on the ratio and 0.2 a on the depth.
    let (j2_hertz, z_hertz) = hertz_first_yield();
    assert!((1.0 / j2_hertz - 3.107).abs() < 0.005 && (z_hertz - 0.705).abs() < 0.005);
    let wm = wheel();
    let (p, sqrt_j2, depth) = pressed(&wm);
    let (a, p0) = hertz(p);
    let pitch = 2.0 * PI * R / rim() as f64;
    let first = p0 / sqrt_j2;
    println!(
        "P = {p:.4e} N/m, a = {a:.4e} m = {:.4} R ({:.1} pitches across 2a), p0 = {p0:.4e} Pa; \
         first yield at p0/k = {first:.3} (Hertz {:.3}), depth {:.3} a (Hertz {z_hertz:.3} a)",
        a / R,
        2.0 * a / pitch,
        1.0 / j2_hertz,
        depth / a
    );
    assert!(
        a / R < 0.035 && (R - hub()) / a > 15.0,
        "a Hertzian contact"
    );
    assert!((2.0 * a / pitch - 12.0).abs() < 1.0);
    assert!(
        (first * j2_hertz - 1.0).abs() < 0.12,
        "first yield at p0/k = {first}"
    );
    assert!(
        (depth / a - z_hertz).abs() < 0.2,
        "first yield at {} a",
        depth / a
    );
}

#[test]
fn a_plastic_plate_in_tension_follows_the_exact_curve_through_the_driver() {
    use softway::assembly::{assemble_mass_stiffness, Assembler};
    use softway::mesh::generators::rectangle;
    use softway::model::LinearModel;
    use softway::simulation::Problem;
    use softway::wheel::triangle_geometry;
    // A plate 100 x 20 mm, 10 mm thick, plane stress, held at x = 0 (x) and at its corner
    // (y), pulled at x = L by sigma(t) = sigma_max sin(pi t / T) over T (slow against its
    // axial period 1/(12.6 kHz)), then at rest: isotropic hardening H, so the permanent
    // strain is (sigma_max - sigma_y) / H and the plate keeps (sigma_max - sigma_y) L / H.
    let (lx, ly, th) = (0.1, 0.02, 0.01);
    let (sy, hmod, smax) = (250e6, 10e9, 400e6);
    let mesh = rectangle(lx, ly, 10, 2).unwrap();
    let (tris, geo) = triangle_geometry(&mesh).unwrap();
    let d = PlaneModel::Stress.elasticity_matrix(&STEEL);
    let asm = Assembler::new(&mesh);
    let (m, k) = assemble_mass_stiffness(&asm, &geo, &d, &STEEL, th, false);
    let mut model = LinearModel::zeros(asm);
    model.m = m;
    model.k = k;
    let left = mesh.node_set("left").unwrap().to_vec();
    let right = mesh.node_set("right").unwrap().to_vec();
    let mut dirichlet: Vec<(usize, f64)> = left.iter().map(|&n| (2 * n, 0.0)).collect();
    dirichlet.push((2 * left[0] + 1, 0.0));
    // Consistent nodal forces of a uniform traction on the right edge.
    let n = mesh.n_dofs();
    let mut unit = vec![0.0; n];
    let dy = ly / (right.len() - 1) as f64;
    for &nd in &right {
        let y = mesh.point(nd)[1];
        let w = if y.abs() < 1e-12 || (y - ly).abs() < 1e-12 {
            0.5
        } else {
            1.0
        };
        unit[2 * nd] = w * dy * th;
    }
    let (t_load, h) = (0.05, 2.5e-4);
    let steps = 300;
    let load = move |t: f64, f: &mut [f64]| {
        let s = if t < t_load {
            smax * (PI * t / t_load).sin()
        } else {
            0.0
        };
        for (fi, ui) in f.iter_mut().zip(&unit) {
            *fi = s * ui;
        }
    };
    let problem = Problem {
        dim: 2,
        reference: mesh.reference_positions(),
        model,
        integrator: Integrator::SpaceTime {
            alpha: 0.8,
            gamma: 0.2,
            coriolis: Coriolis::Implicit,
        },
        h,
        gamma_schedule: Vec::new(),
        dirichlet,
        load: Box::new(load),
        obstacles: Vec::new(),
        interfaces: Vec::new(),
        pairs: Vec::new(),
        treatment: Treatment::SOFT_WAY,
        u0: vec![0.0; n],
        v0: vec![0.0; n],
        t0: 0.0,
        steps,
        gap_tol: 1e-12,
        energy_stiffness: None,
        friction: None,
    };
    let mat = J2Material {
        elastic: STEEL,
        yield_stress: sy,
        isotropic: Isotropic {
            modulus: hmod,
            voce_q: 0.0,
            voce_b: 0.0,
        },
        kinematic: Kinematic { c: 0.0, gamma: 0.0 },
    };
    let body = PlasticBody::new(mat, PlaneModel::Stress, th, tris.clone(), geo.clone());
    let mut sim = Simulation::new(problem).unwrap();
    sim.set_internal_force(Box::new(body), 1e-8, 200).unwrap();
    let mut end_u = 0.0;
    let mut max_eq_seen = 0.0f64;
    let stats = sim
        .run(&AtomicBool::new(false), |s| {
            if let Some(st) = s.internal_state() {
                for e in 0..tris.len() {
                    max_eq_seen = max_eq_seen.max(st[e * STATE_LEN + 8]);
                }
            }
            if s.last {
                end_u = right.iter().map(|&nd| s.state.u[2 * nd]).sum::<f64>() / right.len() as f64;
            }
            Ok(())
        })
        .unwrap();
    let nl = sim.nonlinear().unwrap();
    let ep = (smax - sy) / hmod;
    let eq: Vec<f64> = (0..tris.len())
        .map(|e| nl.state(1)[e * STATE_LEN + 8])
        .collect();
    println!(
        "permanent elongation {end_u:.6e} m (exact {:.6e}), eps_p {:?} (exact {ep:.6e}); {} steps, {} plastic corrections, at most {} in one solve",
        ep * lx,
        &eq[..4],
        stats.steps,
        stats.plastic_iterations,
        stats.plastic_max_in_one_solve
    );
    assert_eq!(stats.plastic_unconverged, 0);
    assert!(stats.plastic_iterations > 0);
    for &e in &eq {
        assert!((e / ep - 1.0).abs() < 2e-3, "eps_p {e:e} against {ep:e}");
    }
    assert!((max_eq_seen / ep - 1.0).abs() < 2e-3);
    assert!((end_u / (ep * lx) - 1.0).abs() < 5e-3, "{end_u:e}");
}

#[test]
fn plastic_keys_are_validated_with_the_file_and_the_key() {
    use softway::scenario::Scenario;
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/wheel-plastic.toml"
    ))
    .unwrap();
    let dir = std::env::temp_dir().join(format!("softway-plastic-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let load = |name: &str, text: &str| {
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, text).unwrap();
        Scenario::from_file(&p)
    };
    // The shipped file: J2 with Armstrong-Frederick's constants.
    let sc = load("shipped", &base).unwrap();
    let Some(ws) = sc.runs[0].model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let pl = ws.plastic.expect("plastic");
    assert_eq!(pl.material.yield_stress, 1.0e9);
    assert_eq!(
        (pl.material.kinematic.c, pl.material.kinematic.gamma),
        (20e9, 100.0)
    );
    assert_eq!(pl.tolerance, 1e-8);
    let cases: [(&str, &str, &str, &[&str]); 7] = [
        (
            "model",
            "model = \"j2\"",
            "model = \"tresca\"",
            &["material.model", "\"elastic\", \"j2\""],
        ),
        (
            "yield",
            "yield_stress = 1.0e9",
            "yield_stress = -1.0",
            &["material.yield_stress"],
        ),
        (
            "hardening",
            "hardening = \"armstrong_frederick\"",
            "hardening = \"chaboche\"",
            &["material.hardening", "\"kinematic\""],
        ),
        (
            "af_for_kinematic",
            "hardening = \"armstrong_frederick\"",
            "hardening = \"kinematic\"\nhardening_modulus = 1e9",
            &["material.af_c", "armstrong_frederick"],
        ),
        (
            "missing_yield",
            "yield_stress = 1.0e9",
            "",
            &["material.yield_stress"],
        ),
        (
            "tolerance",
            "plastic_tolerance = 1e-8",
            "plastic_tolerance = 2.0",
            &["material.plastic_tolerance"],
        ),
        (
            "subdivision",
            "method = \"soft_way\"",
            "method = \"subdivision\"",
            &["material.model", "subdivision"],
        ),
    ];
    for (name, from, to, must) in cases {
        let text = base.replace(from, to);
        assert_ne!(text, base, "{name}: the replacement did nothing");
        let e = load(name, &text).expect_err(name).to_string();
        assert!(!e.contains('\n'), "{name}: one line: {e}");
        assert!(e.contains(&format!("{name}.toml")), "{name}: the file: {e}");
        for m in must {
            assert!(e.contains(m), "{name}: `{m}` in {e}");
        }
    }
    // An elastic material refuses a plastic key.
    let elastic = base.replace("model = \"j2\"", "model = \"elastic\"");
    let e = load("elastic", &elastic).unwrap_err().to_string();
    assert!(
        e.contains("material.yield_stress") && e.contains("j2"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
