use softway::contact::ContactMethod;
use softway::linalg::spmv_into;
use softway::problems::BarImpact;
use softway::simulation::Simulation;
use softway::time::SpaceTimeParams;
use std::sync::atomic::AtomicBool;

#[test]
fn survey() {
    for lumped in [false, true] {
        for ne in [8, 20, 40] {
            for (h, g) in [(0.4, 0.0), (0.1, 0.0), (0.01, 0.0), (0.01, 0.2)] {
                for method in [ContactMethod::SoftWay, ContactMethod::SoftWayNoRestore] {
                    let bar = BarImpact { length: 1.0, ea: 1.0, rho_a: 1.0, speed: 1.0, gap: 0.5, elements: ne, lumped, damping: 0.0 };
                    let (_mesh, pb) = bar.problem(SpaceTimeParams { alpha: 0.8, gamma: g, h }, method, 5.0);
                    let m = pb.model.m.clone();
                    let pat = pb.model.pattern().clone();
                    let mut sim = Simulation::new(pb).unwrap();
                    let stop = AtomicBool::new(false);
                    let mut mv = vec![0.0; ne + 1];
                    let (mut first, mut last, mut p_end) = (None, 0.0, 0.0);
                    let stats = sim.run(&stop, |s| {
                        spmv_into(&pat, &m, &s.state.v, &mut mv);
                        p_end = mv.iter().sum();
                        if s.held > 0 { if first.is_none() { first = Some(s.state.t) }; last = s.state.t; }
                        Ok(())
                    }).unwrap();
                    println!("lumped {lumped} ne {ne} h {h} g {g} {method:?}: first {:.3} last {:.3} vcm {:.4} brakings {}", first.unwrap_or(f64::NAN), last, p_end, stats.brakings);
                }
            }
        }
    }
}
