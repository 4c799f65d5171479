//! A rail pass's wear as it rolls ([`Wearing`]): the grid, the patch, the tangential
//! model (module `sliding`) and the tallies, step by step.

use super::*;

/// A pass's wear as it rolls: the set-up (the grid, the patch, the wear law's rate, the
/// rim) and the tallies (the depth per grid sample, the worn volume and what fell off the
/// grid, the contact force's moments, the contact's compression, the force's trace).
pub(super) struct Wearing<'a> {
    pub(super) wot: &'a crate::bodies::rail::rolling::WheelOnTrack,
    pub(super) h: f64,
    /// The grid `(x0, dx, n)`.
    pub(super) x0: f64,
    pub(super) dx: f64,
    pub(super) n: usize,
    pub(super) patch: WearPatch,
    /// The steady model's rate (`None`: the dynamic model, `sliding`).
    rate: Option<WearRate>,
    /// The wear law, the rail's density and the travel speed (the dynamic model's samples).
    pub(super) law: WearLaw,
    pub(super) density: f64,
    pub(super) speed: f64,
    /// The dynamic model's friction tallies.
    pub(super) friction: Option<FrictionTally>,
    pub(super) thickness: f64,
    pub(super) e_star: f64,
    /// The rim's pitch, m.
    pub(super) pitch: f64,
    pub(super) reference: Vec<f64>,
    pub(super) slave: crate::contact::search::Placed,
    /// The second wheel's rim in the search (`vehicle.wheelbase`).
    pub(super) trailing_slave: Option<crate::contact::search::Placed>,
    pub(super) rim: Vec<usize>,
    pub(super) depth: Vec<f64>,
    pub(super) volume: f64,
    pub(super) lost: f64,
    pub(super) f_sum: f64,
    pub(super) f2_sum: f64,
    pub(super) f_max: f64,
    pub(super) f_min: f64,
    pub(super) count: usize,
    /// The contact's compression: the rail's deflection under the axle less the axle's.
    pub(super) squeeze: f64,
    pub(super) bookkeeping: std::time::Duration,
    pub(super) trace: Vec<(f64, f64)>,
    /// The patch's centre and force at the previous step.
    pub(super) last: Option<(f64, f64)>,
    /// The second wheel's (`vehicle.wheelbase`): its patch's centre and force at the
    /// previous step.
    pub(super) last_trailing: Option<(f64, f64)>,
    /// The second wheel's tallies over its recorded steps (it crosses the grid a
    /// wheelbase after the first): its contact force's sum and count, and the dynamic
    /// model's friction.
    pub(super) trailing_f_sum: f64,
    pub(super) trailing_count: usize,
    pub(super) trailing_friction: Option<FrictionTally>,
}

/// Which wheel's rim a step's pairs are (the second's with `vehicle.wheelbase`).
#[derive(Clone, Copy)]
struct Rim {
    /// The rim in the search: its frame and first dof.
    slave: crate::contact::search::Placed,
    /// The rail's abscissa under the first wheel's axle, m (the rim's frame,
    /// `slave.motion`, holds the second wheel's place behind it).
    under: f64,
}

/// The wear law's depth rate under the rail's sliding at the travel speed `v`.
#[derive(Clone, Copy)]
struct WearRate {
    law: WearLaw,
    sliding: RailSliding,
    v: f64,
}

impl WearRate {
    /// The depth rate at pressure `p` (the law reads `p` as a force over an area).
    fn at(&self, p: f64) -> f64 {
        let (sliding, v) = (self.sliding, self.v);
        self.law.depth_rate(
            &ContactSample {
                normal_force: p,
                tangential_force: sliding.traction_coefficient * p,
                slip_speed: sliding.creepage * v,
                area: 1.0,
                rolling_speed: v,
            },
            sliding.density,
        )
    }
}

impl<'a> Wearing<'a> {
    pub(super) fn new(
        runner: &TrackPass,
        wot: &'a crate::bodies::rail::rolling::WheelOnTrack,
        h: f64,
        trace: Vec<(f64, f64)>,
    ) -> Self {
        Wearing {
            wot,
            h,
            x0: runner.x0,
            dx: runner.dx,
            n: runner.n,
            patch: runner.patch,
            rate: match runner.sliding {
                Sliding::Steady(sliding) => Some(WearRate {
                    law: runner.law,
                    sliding,
                    v: runner.ts.vehicle.speed,
                }),
                Sliding::Dynamic { .. } => None,
            },
            law: runner.law,
            density: runner.sliding.density(),
            speed: runner.ts.vehicle.speed,
            friction: matches!(runner.sliding, Sliding::Dynamic { .. })
                .then(FrictionTally::default),
            thickness: runner.ts.vehicle.wheel.thickness,
            e_star: runner.contact_modulus(),
            pitch: 2.0 * std::f64::consts::PI * wot.rim_radius / wot.wheel.rim.len() as f64,
            reference: wot.wheel.mesh.reference_positions(),
            slave: wot.interface.slave(),
            trailing_slave: wot.trailing.as_ref().map(|tr| tr.interface.slave()),
            rim: wot.interface.nodes().to_vec(),
            depth: vec![0.0; runner.n],
            volume: 0.0,
            lost: 0.0,
            f_sum: 0.0,
            f2_sum: 0.0,
            f_max: f64::NEG_INFINITY,
            f_min: f64::INFINITY,
            count: 0,
            squeeze: 0.0,
            bookkeeping: std::time::Duration::ZERO,
            trace,
            last: None,
            last_trailing: None,
            trailing_f_sum: 0.0,
            trailing_count: 0,
            trailing_friction: (wot.trailing.is_some()
                && matches!(runner.sliding, Sliding::Dynamic { .. }))
            .then(FrictionTally::default),
        }
    }

    /// One step: from the grid's start on, the force's trace and moments, the compression,
    /// and the wear the step lays; the second wheel's (`vehicle.wheelbase`) from where it
    /// reaches the grid, by the same model on its own patch.
    pub(super) fn step(&mut self, s: &crate::simulation::StepView) -> Result<(), std::io::Error> {
        let wot = self.wot;
        let st = s.state;
        let (t, u) = (st.t, &st.state.u);
        let under = wot.under_axle(t);
        // The first wheel's pairs, then the second's (`WheelOnTrack::rim_pairs`).
        let (first, second) = st.pairs.split_at(wot.rim_pairs().min(st.pairs.len()));
        if let (Some(tr), Some(slave)) = (&wot.trailing, self.trailing_slave) {
            let behind = under - tr.wheelbase;
            let axle = wot.trailing_axle_ground(t, u).unwrap_or_default();
            let f = second.iter().map(|p| p.force).sum();
            let now = (behind + axle[0], f);
            let before = self.last_trailing.replace(now);
            if behind >= self.x0 {
                let clock = Instant::now();
                self.trailing_f_sum += f;
                self.trailing_count += 1;
                if let Some(tally) = self.trailing_friction.as_mut() {
                    tally.add(second);
                }
                self.wear(s, Rim { slave, under }, second, before, now);
                self.bookkeeping += clock.elapsed();
            }
        }
        let f = first.iter().map(|p| p.force).sum();
        let centre = under + wot.axle_ground(t, u)[0];
        let before = self.last.replace((centre, f));
        if under < self.x0 {
            return Ok(());
        }
        self.trace.push((centre, f));
        self.squeeze += wot
            .rail_deflection(under, u)
            .map_err(|e| std::io::Error::other(e.to_string()))?
            - wot.axle_ground(t, u)[1];
        self.f_sum += f;
        self.f2_sum += f * f;
        self.f_max = self.f_max.max(f);
        self.f_min = self.f_min.min(f);
        self.count += 1;
        let clock = Instant::now();
        if let Some(tally) = self.friction.as_mut() {
            tally.add(first);
        }
        let slave = self.slave;
        self.wear(s, Rim { slave, under }, first, before, (centre, f));
        self.bookkeeping += clock.elapsed();
        Ok(())
    }

    /// The wear one wheel's `pairs` lay in a step, its patch moved from `before` to `now`
    /// (centre, force), by the study's model and patch.
    fn wear(
        &mut self,
        s: &crate::simulation::StepView,
        rim: Rim,
        pairs: &[crate::model::PairState],
        before: Option<(f64, f64)>,
        now: (f64, f64),
    ) {
        match (self.patch, self.rate) {
            (WearPatch::Hertz, Some(rate)) => {
                if let Some(before) = before {
                    self.hertz(rate, before, now);
                }
            }
            (WearPatch::Nodes, Some(rate)) => {
                self.nodes(s, rim, pairs, |ps, area| rate.at(ps.force / area) * area)
            }
            (WearPatch::Hertz, None) => {
                let volume = self.dynamic_volume(pairs);
                let spread = before.is_some_and(|b| self.hertz_spread(b, now, volume));
                if !spread {
                    self.volume += volume;
                    self.lost += volume;
                }
            }
            (WearPatch::Nodes, None) => {
                let (law, density, speed) = (self.law, self.density, self.speed);
                self.nodes(s, rim, pairs, |ps, area| {
                    node_sample(ps, area, speed)
                        .map_or(0.0, |sample| law.depth_rate(&sample, density) * area)
                })
            }
        }
    }

    /// The dynamic model's worn volume of the step under one wheel's `pairs`, m^3: each
    /// rim node in slip through the wear law ([`node_sample`]), over its tributary area.
    fn dynamic_volume(&self, pairs: &[crate::model::PairState]) -> f64 {
        let area = self.pitch * self.thickness;
        pairs
            .iter()
            .filter_map(|ps| node_sample(ps, area, self.speed))
            .map(|sample| self.law.depth_rate(&sample, self.density) * area * self.h)
            .sum()
    }

    /// Hertz's patch of the step's mean force moved from `(c0, f0)` to `(centre, f)`:
    /// calls `visit(j, p)` for each grid sample `j` it passed, `p` the step's mean
    /// pressure there (the load per width that passed over it over the step's travel).
    /// False when it did not move or passed no sample.
    fn passed(
        &self,
        (c0, f0): (f64, f64),
        (centre, f): (f64, f64),
        mut visit: impl FnMut(usize, f64),
    ) -> bool {
        let (x0, dx, n) = (self.x0, self.dx, self.n);
        let travel = centre - c0;
        if travel.abs() <= 0.0 {
            return false;
        }
        let lp = LinePatch::new(
            0.5 * (f0 + f),
            self.thickness,
            self.wot.rim_radius,
            self.e_star,
        );
        let (lo, hi) = (c0.min(centre) - lp.a, c0.max(centre) + lp.a);
        let j0 = ((lo - x0) / dx).ceil().max(0.0) as usize;
        let j1 = ((hi - x0) / dx).floor();
        if j1 < 0.0 {
            return false;
        }
        let j1 = (j1 as usize).min(n - 1);
        for j in j0..=j1 {
            let xj = x0 + j as f64 * dx;
            let (s0, s1) = (xj - centre, xj - c0);
            let passed = (lp.cumulative(s0.max(s1)) - lp.cumulative(s0.min(s1))).abs();
            visit(j, passed / travel.abs());
        }
        j0 <= j1
    }

    /// The dynamic model on Hertz's patch: the step's worn `volume` (m^3) laid over the
    /// samples the patch passed in proportion to the mean pressure there (module
    /// `sliding`); false (nothing laid) when it passed none.
    fn hertz_spread(&mut self, before: (f64, f64), now: (f64, f64), volume: f64) -> bool {
        let mut total = 0.0;
        if !self.passed(before, now, |_, p| total += p) || total <= 0.0 {
            return false;
        }
        let scale = volume / (self.thickness * total * self.dx);
        let mut depth = std::mem::take(&mut self.depth);
        self.passed(before, now, |j, p| depth[j] += p * scale);
        self.depth = depth;
        self.volume += volume;
        true
    }

    /// Hertz's patch moved from `(c0, f0)` to `(centre, f)` (its centre and force): the
    /// step's mean pressure at each grid sample it passed, worn for the step by the steady
    /// model's `rate`. False when it did not move or passed no sample.
    fn hertz(&mut self, rate: WearRate, before: (f64, f64), now: (f64, f64)) -> bool {
        let (h, dx, thickness) = (self.h, self.dx, self.thickness);
        let mut depth = std::mem::take(&mut self.depth);
        let mut volume = 0.0;
        let passed = self.passed(before, now, |j, p_mean| {
            let dz = rate.at(p_mean) * h;
            depth[j] += dz;
            volume += dz * dx * thickness;
        });
        self.depth = depth;
        self.volume += volume;
        passed
    }

    /// One wheel's rim nodes in contact (`pairs`, in the rim's order), each wearing the
    /// rail over its pitch as a hat centred where it is on the rail (`rim.under`: the
    /// rail's abscissa under its axle), at the volume rate `rate(pair, area)` (m^3/s) over
    /// its tributary `area`.
    fn nodes(
        &mut self,
        s: &crate::simulation::StepView,
        rim: Rim,
        pairs: &[crate::model::PairState],
        rate: impl Fn(&crate::model::PairState, f64) -> f64,
    ) {
        let st = s.state;
        let (t, u) = (st.t, &st.state.u);
        let (pitch, thickness) = (self.pitch, self.thickness);
        let d0 = rim.slave.first_dof;
        for (slot, ps) in pairs.iter().enumerate() {
            if ps.force <= 0.0 {
                continue;
            }
            let node = self.rim[slot];
            let local = [
                self.reference[2 * node] + u[d0 + 2 * node],
                self.reference[2 * node + 1] + u[d0 + 2 * node + 1],
                0.0,
            ];
            let x = rim.under + rim.slave.motion.place(t, local)[0];
            let area = pitch * thickness;
            let vol = rate(ps, area) * self.h;
            if vol <= 0.0 {
                continue;
            }
            self.volume += vol;
            if !lay_hat(
                &mut self.depth,
                (self.x0, self.dx),
                x,
                pitch,
                vol / thickness,
            ) {
                self.lost += vol;
            }
        }
    }
}

/// Lays the area `area` (m^2: a volume over the contact's width) on the grid `(x0, dx)` of
/// `depth` as a hat of half-width `b` centred at `x`, normalised on the grid's samples so
/// that `sum(depth) dx` grows by exactly `area`. False (nothing laid) when the hat misses
/// the grid.
pub(super) fn lay_hat(depth: &mut [f64], (x0, dx): (f64, f64), x: f64, b: f64, area: f64) -> bool {
    let n = depth.len();
    if n == 0 || !x.is_finite() {
        return false;
    }
    let lo = ((x - b - x0) / dx).ceil().max(0.0);
    let hi = ((x + b - x0) / dx).floor().min((n - 1) as f64);
    if lo > hi {
        return false;
    }
    let (lo, hi) = (lo as usize, hi as usize);
    let w = |i: usize| (1.0 - ((x0 + i as f64 * dx) - x).abs() / b).max(0.0);
    let total: f64 = (lo..=hi).map(w).sum();
    if total <= 0.0 {
        return false;
    }
    let scale = area / (total * dx);
    for (i, d) in depth.iter_mut().enumerate().take(hi + 1).skip(lo) {
        *d += w(i) * scale;
    }
    true
}
