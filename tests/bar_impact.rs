//! The elastic bar striking a rigid wall against the exact d'Alembert solution (paper §3.1,
//! Figs. 8-9): contact from gap/v0 for 2L/c, force rho A c v0, rebound at v0, energy kept.

use softway::contact::{Restore, Treatment};
use softway::problems::BarImpact;
use softway::run::bar::{simulate, BarSummary};
use softway::scenario::{Model, Run};
use softway::time::Integrator;
use softway::time::SpaceTimeParams;

fn run(bar: BarImpact, h: f64, restore: Restore) -> BarSummary {
    let t_end = bar.exact_impact_time()
        + bar.exact_contact_duration()
        + 1.5 * bar.length / bar.wave_speed();
    let r = Run {
        label: format!("{} el, h {h}", bar.elements),
        params: SpaceTimeParams {
            alpha: 0.8,
            gamma: 0.0,
            h,
        },
        model: Model::new(bar),
        integrator: Integrator::SpaceTime {
            alpha: 0.8,
            gamma: 0.0,
            coriolis: softway::time::Coriolis::Implicit,
        },
        contact: Treatment::SoftWay { restore },
        friction: None,
        t_end,
        step_key: "time.h".into(),
    };
    simulate(&r, None, 1, &Default::default()).unwrap().0
}

const PAPER: BarImpact = BarImpact {
    length: 1.0,
    ea: 1.0,
    rho_a: 1.0,
    speed: 1.0,
    gap: 0.5,
    elements: 8,
    lumped: false,
    damping: 0.0,
};
const OTHER: BarImpact = BarImpact {
    length: 2.0,
    ea: 3.0,
    rho_a: 0.5,
    speed: 0.7,
    gap: 0.3,
    elements: 8,
    lumped: false,
    damping: 0.0,
};

/// Errors on a ladder refining the mesh and the step together (h c / l fixed).
fn ladder(bar: BarImpact) -> Vec<(usize, f64, BarSummary)> {
    let c = bar.wave_speed();
    [10usize, 20, 40, 80]
        .iter()
        .map(|&ne| {
            let h = 0.4 * bar.length / ne as f64 / c;
            let b = BarImpact {
                elements: ne,
                ..bar
            };
            (ne, h, run(b, h, Restore::StoppingImpulse))
        })
        .collect()
}

fn check_ladder(bar: BarImpact) {
    let l = ladder(bar);
    let dur: Vec<f64> = l
        .iter()
        .map(|x| x.2.errors.contact_duration.unwrap().abs())
        .collect();
    let force: Vec<f64> = l
        .iter()
        .map(|x| x.2.errors.mean_contact_force.unwrap().abs())
        .collect();
    let reb: Vec<f64> = l
        .iter()
        .map(|x| x.2.errors.rebound_velocity.abs())
        .collect();
    let en: Vec<f64> = l.iter().map(|x| x.2.errors.energy.abs()).collect();
    for (ne, h, s) in &l {
        println!(
            "{ne:3} el, h {h:.5}: duration {:+.4}, force {:+.4}, rebound {:+.4}, energy {:+.5}, impact {:+.5}",
            s.errors.contact_duration.unwrap(),
            s.errors.mean_contact_force.unwrap(),
            s.errors.rebound_velocity,
            s.errors.energy,
            s.errors.impact_time.unwrap()
        );
        // One arrival (braked, or held at once where the braking would pull:
        // softway::contact::softway, Braking may only push), one release: no chatter.
        assert_eq!((s.entries, s.releases), (1, 1));
        assert!(s.brakings <= 1, "{} brakings", s.brakings);
        // The arrival is at most one step late.
        assert!(
            s.errors.impact_time.unwrap() >= -1e-12 && s.errors.impact_time.unwrap() <= h + 1e-12
        );
    }
    // The contact duration error falls with refinement, to below 1%.
    for w in dur.windows(2) {
        assert!(w[1] <= w[0] + 1e-12, "duration errors {dur:?}");
    }
    assert!(
        dur[3] < 0.01 && dur[3] < 0.5 * dur[0],
        "duration errors {dur:?}"
    );
    // The mean force is within 0.5% once the mesh resolves the wave (40 elements and up).
    assert!(
        force[2] < 0.005 && force[3] < 0.005 && force[3] < force[0],
        "force errors {force:?}"
    );
    // The rebound converges to v0: within 1% on the finest level, better than at 20 elements.
    assert!(reb[3] < 0.01 && reb[3] < reb[1], "rebound errors {reb:?}");
    // Energy is kept across the impact.
    assert!(en[3] < 0.005, "energy errors {en:?}");
}

#[test]
fn paper_bar_converges_to_dalembert() {
    check_ladder(PAPER);
}

#[test]
fn another_bar_converges_to_dalembert() {
    check_ladder(OTHER);
}

#[test]
fn momentum_restoring_on_the_paper_bar() {
    let with = run(PAPER, 0.01, Restore::StoppingImpulse);
    let paper_r = run(PAPER, 0.01, Restore::BrakingReaction);
    let without = run(PAPER, 0.01, Restore::Nothing);
    println!(
        "rebound: restore {:.4}, braking-reaction restore {:.4}, none {:.4}; energy {:.4} / {:.4} / {:.4}",
        with.rebound_velocity, paper_r.rebound_velocity, without.rebound_velocity,
        with.energy_final, paper_r.energy_final, without.energy_final
    );
    // Restoring gives back momentum: clearly faster than without.
    assert!(with.rebound_velocity > without.rebound_velocity + 0.02);
    assert!(paper_r.rebound_velocity > without.rebound_velocity + 0.01);
    // Restoring keeps the energy (E0 = 0.5 J) within 0.5%; without it the braking loses ~4%.
    assert!(
        (with.energy_final / 0.5 - 1.0).abs() < 0.005,
        "{}",
        with.energy_final
    );
    assert!(without.energy_final < 0.49);
    // With 8 elements the rebound is 3% short of v0: the 8-element bar keeps that share of
    // the energy as vibration (its energy is kept to 0.1%); 80 elements and the same
    // step-to-element ratio come within 1% (see the ladders above).
    assert!(with.rebound_velocity > 0.96 && with.rebound_velocity < 1.01);
    // The approach's momentum alone (`soft_way_momentum_restore`) is the stopping impulse
    // less the impulse of the forces in the braking step: none act on the unloaded,
    // unstrained bar before it arrives, so the two give back one impulse.
    let approach = run(PAPER, 0.01, Restore::ApproachMomentum);
    for (a, b) in [
        (approach.rebound_velocity, with.rebound_velocity),
        (approach.energy_final, with.energy_final),
    ] {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
    }
}
