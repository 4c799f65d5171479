use softway::contact::obstacle::Flattening;
use softway::contact::ContactMethod;
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::disk_rings;
use softway::simulation::Simulation;
use softway::time::SpaceTimeParams;
use softway::wheel::{Support, WheelModel, WheelSpec};
use std::sync::atomic::AtomicBool;

#[test]
fn probe() {
    let h: f64 = std::env::var("H").ok().and_then(|s| s.parse().ok()).unwrap_or(2e-6);
    let settle: f64 = 5e-3;
    let omega = 300.0;
    let spec = WheelSpec {
        radius: 0.1, thickness: 0.01,
        material: Elastic { young: 2.05e11, poisson: 0.3, density: 7830.0 },
        plane: PlaneModel::Stress, lumped: false, damping: 0.0, support: Support::CentrePinned,
        omega, flattening: Flattening { depth: 1e-3, settle_time: settle }, stress_stiffening: true, rotating_frame: true,
    };
    let t0 = std::time::Instant::now();
    let w = WheelModel::new(disk_rings(0.1, 12).unwrap(), spec).unwrap();
    let t_end = settle + 0.25 * 2.0 * std::f64::consts::PI / omega;
    let steps = (t_end / h) as usize;
    let pb = w.problem(SpaceTimeParams { alpha: 0.8, gamma: 0.2, h }, vec![], ContactMethod::SoftWay, steps);
    let mut sim = Simulation::new(pb).unwrap();
    println!("setup {:?}", t0.elapsed());
    let t1 = std::time::Instant::now();
    let stop = AtomicBool::new(false);
    let mut fmax: f64 = 0.0;
    let stats = sim.run(&stop, |s| {
        fmax = fmax.max(s.contact_force);
        if s.state.k % (steps / 40).max(1) == 0 {
            let minpen = s.state.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
            println!("t {:.4e} F {:.4e} held {} KE {:.3e} SE {:.3e} min gap {:.3e}", s.state.t, s.contact_force, s.held, s.kinetic, s.strain, minpen);
        }
        Ok(())
    }).unwrap();
    let el = t1.elapsed();
    println!("steps {} in {:?} = {:.2} us/step; {:?}; fmax {fmax:.4e}", stats.steps, el, el.as_secs_f64() / stats.steps as f64 * 1e6, stats);
}

#[test]
fn solve_cost() {
    let spec = WheelSpec {
        radius: 0.1, thickness: 0.01,
        material: Elastic { young: 2.05e11, poisson: 0.3, density: 7830.0 },
        plane: PlaneModel::Stress, lumped: false, damping: 0.0, support: Support::CentrePinned,
        omega: 300.0, flattening: Flattening { depth: 1e-3, settle_time: 5e-3 }, stress_stiffening: true, rotating_frame: true,
    };
    let w = WheelModel::new(disk_rings(0.1, 12).unwrap(), spec).unwrap();
    let p = SpaceTimeParams { alpha: 0.8, gamma: 0.2, h: 2e-6 };
    let mut st = softway::time::step::Stepper::new(&w.model, 2, p, &[(0, 0.0), (1, 0.0)], 4, 4).unwrap();
    let n = w.model.n();
    let mut b = vec![1.0; n];
    let u = vec![0.0; n];
    let t = std::time::Instant::now();
    for _ in 0..2000 { st.solve(&mut b, &[], &mut []); }
    println!("solve {:.2} us", t.elapsed().as_secs_f64() / 2000.0 * 1e6);
    let t = std::time::Instant::now();
    for _ in 0..2000 { st.rhs_into(&u, &b, &u, &mut b.clone()); }
    println!("rhs {:.2} us (with clone)", t.elapsed().as_secs_f64() / 2000.0 * 1e6);
    println!("nnz {}", w.model.m.len());
}

#[test]
fn llt_cost() {
    use softway::linalg::SparseLlt;
    let spec = WheelSpec {
        radius: 0.1, thickness: 0.01,
        material: Elastic { young: 2.05e11, poisson: 0.3, density: 7830.0 },
        plane: PlaneModel::Stress, lumped: false, damping: 0.0, support: Support::CentrePinned,
        omega: 300.0, flattening: Flattening { depth: 1e-3, settle_time: 5e-3 }, stress_stiffening: true, rotating_frame: true,
    };
    let w = WheelModel::new(disk_rings(0.1, 12).unwrap(), spec).unwrap();
    let a: Vec<f64> = w.model.m.iter().zip(&w.model.k).map(|(m, k)| m + 0.32 * 4e-12 * k).collect();
    let mut l = SparseLlt::new(w.model.pattern(), &a).unwrap();
    let mut b = vec![1.0; w.model.n()];
    let t = std::time::Instant::now();
    for _ in 0..2000 { l.solve_in_place(&mut b); }
    println!("llt: solve {:.2} us, nnz(L) {}", t.elapsed().as_secs_f64() / 2000.0 * 1e6, l.factor_nnz());
}
