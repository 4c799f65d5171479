//! `track.png`: the rolling wheel's passage in four panels (a fifth with friction).

use super::*;

/// The four panels of `track.png`, and a fifth with friction.
pub(super) struct Panels {
    force: Panel,
    motion: Panel,
    spectrum: Panel,
    pads: Panel,
    pub(super) traction: Option<Panel>,
}

impl Panels {
    pub(super) fn new(ts: &TrackScenario) -> Self {
        let v = &ts.vehicle;
        let mut spectrum = Panel::new(
            format!(
                "Contact force spectrum over the passage (frequencies at {} km/h)",
                sig(3.6 * v.speed, 3)
            ),
            "wavelength on the rail [m]",
            "amplitude [kN]",
        );
        spectrum.x_log = true;
        spectrum.y_log = true;
        Panels {
            force: Panel::new(
                format!(
                    "Wheel on the track at {} km/h: contact force",
                    sig(3.6 * v.speed, 3)
                ),
                "distance travelled [m]",
                "contact force [kN]",
            ),
            motion: Panel::new(
                "Axle and rail under it",
                "distance travelled [m]",
                "vertical displacement [mm]",
            ),
            spectrum,
            pads: Panel::new(
                "Force in the pad nearest the axle",
                "distance travelled [m]",
                "pad force (compression) [kN]",
            ),
            traction: None,
        }
    }

    /// Adds run `ri` of `runs` (its `label`, summary and records) to the panels; the
    /// static load, the settling and the track's lines are marked with the first run.
    pub(super) fn add(
        &mut self,
        ri: usize,
        runs: usize,
        label: &str,
        ts: &TrackScenario,
        sum: &RollingSummary,
        recs: &[Rec],
    ) {
        let run = RunLines {
            style: if ri % 2 == 0 {
                SeriesStyle::Line
            } else {
                SeriesStyle::Dashed
            },
            label: (runs > 1).then_some(label),
            x: recs.iter().map(|r| r.distance).collect(),
            // The force averaged over a rim node's passage (the node-passing ripple out).
            window: (sum.steps_per_rim_node.round() as usize).max(1),
        };
        let smooth = self.add_force(&run, recs);
        if let Some(l) = ts.vehicle.wheelbase {
            // The second wheel's force where it is: over the rail `l` behind the first's.
            let x: Vec<f64> = run.x.iter().map(|x| x - l).collect();
            let f = moving_average(&col(recs, |r| 1e-3 * r.trailing_force), run.window);
            let keep = x.iter().position(|&x| x >= 0.0).unwrap_or(x.len());
            self.force.series.push(Series::new(
                run.name(&format!(
                    "second wheel, {l} m behind, over the rail under it"
                )),
                x[keep..].to_vec(),
                f[keep..].to_vec(),
                SeriesStyle::Dashed,
            ));
        }
        if ri == 0 {
            self.mark_static_load(ts, sum);
        }
        self.motion.series.push(Series::new(
            run.name("axle"),
            run.x.clone(),
            col(recs, |r| 1e3 * r.axle_y),
            run.style,
        ));
        self.motion.series.push(Series::new(
            run.name("rail under the axle"),
            run.x.clone(),
            col(recs, |r| 1e3 * r.rail_w),
            SeriesStyle::Dashed,
        ));
        self.pads.series.push(Series::new(
            run.name("nearest pad"),
            run.x.clone(),
            col(recs, |r| 1e-3 * r.pad),
            run.style,
        ));
        if let Some(t) = sum.traction {
            self.add_traction(&run, ts, &t, &smooth, recs);
        }
        self.add_spectrum(&run, ri == 0, ts, sum, recs);
    }

    /// The contact force averaged over a rim node's passage (returned, in kN), the axis
    /// kept from 0 to above the passage's range.
    fn add_force(&mut self, run: &RunLines, recs: &[Rec]) -> Vec<f64> {
        let window = run.window;
        let smooth = moving_average(&col(recs, |r| 1e-3 * r.force), window);
        self.force.series.push(Series::new(
            run.name(&format!(
                "contact force, mean over a rim node's passage ({window} steps)"
            )),
            run.x.clone(),
            smooth.clone(),
            run.style,
        ));
        let passage = smooth
            .iter()
            .zip(recs)
            .filter(|(_, r)| !r.settling)
            .map(|(&f, _)| f);
        let (lo, hi) = passage.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), f| {
            (a.min(f), b.max(f))
        });
        if lo.is_finite() {
            let (cur_lo, cur_hi) = self.force.y_range.unwrap_or((0.0, hi));
            self.force.y_range = Some((cur_lo.min(0.0), cur_hi.max(hi + 0.6 * (hi - lo).max(1.0))));
        }
        smooth
    }

    /// The contact's share of the static load as a line on the force, and the settling
    /// as a band on the force, the motion and the pads.
    fn mark_static_load(&mut self, ts: &TrackScenario, sum: &RollingSummary) {
        // A suspension spring about the axle's nominal position carries `-k_s z` of the
        // load: the contact's share is the static load less it (the mean force's balance).
        let k_s = ts.vehicle.suspension_stiffness;
        let (line, label) = if k_s > 0.0 {
            let share = sum.static_load_n + k_s * sum.axle_displacement_mean_m;
            (
                share,
                format!(
                    "static load less the suspension's share, F_axle + m_u g + k_s z = {:.1} kN",
                    1e-3 * share
                ),
            )
        } else {
            (
                sum.static_load_n,
                format!(
                    "static load F_axle + m_u g = {:.1} kN",
                    1e-3 * sum.static_load_n
                ),
            )
        };
        if let Some((lo, hi)) = self.force.y_range {
            self.force.y_range = Some((lo, hi.max(1.1e-3 * line)));
        }
        self.force.hlines.push((1e-3 * line, label));
        let settle = ts.settle_distance();
        if settle > 0.0 {
            for p in [&mut self.force, &mut self.motion, &mut self.pads] {
                p.vspans
                    .push((0.0, settle, "load applied, settling".to_string()));
            }
        }
    }

    /// The tangential force (averaged as the contact force `smooth`) and its full-slip
    /// bound, on the fifth panel (made at the first run with friction).
    fn add_traction(
        &mut self,
        run: &RunLines,
        ts: &TrackScenario,
        t: &TractionSummary,
        smooth: &[f64],
        recs: &[Rec],
    ) {
        let panel = self.traction.get_or_insert_with(|| {
            let mut p = Panel::new(
                "Tangential force on the wheel (+: along the travel, traction)",
                "distance travelled [m]",
                "force [kN]",
            );
            let settle = ts.settle_distance();
            if settle > 0.0 {
                p.vspans
                    .push((0.0, settle, "load applied, settling".to_string()));
            }
            p
        });
        let window = run.window;
        let tangential = moving_average(&col(recs, |r| 1e-3 * r.tangential), window);
        panel.series.push(Series::new(
            run.name(&format!(
                "tangential force Q, creepage {:+.2}% (mean over {window} steps)",
                1e2 * t.creepage
            )),
            run.x.clone(),
            tangential,
            run.style,
        ));
        let bound = t.traction.signum() * t.friction;
        panel.series.push(Series::new(
            run.name(&format!("{bound:+.2} x contact force (full slip)")),
            run.x.clone(),
            smooth.iter().map(|f| bound * f).collect(),
            SeriesStyle::Dashed,
        ));
    }

    /// The passage's force spectrum against the wavelength V / f, from four rim pitches to
    /// 5 m; with the first run (`marks`), the track's lines marked on it.
    fn add_spectrum(
        &mut self,
        run: &RunLines,
        marks: bool,
        ts: &TrackScenario,
        sum: &RollingSummary,
        recs: &[Rec],
    ) {
        let forces: Vec<f64> = recs
            .iter()
            .filter(|r| !r.settling)
            .map(|r| r.force)
            .collect();
        let spec = amplitude_spectrum(&forces, sum.h_s);
        let v = ts.vehicle.speed;
        // Wavelengths from four rim pitches (the node-passing ripple below) to 5 m.
        let top = 0.25 * v / sum.rim_pitch_m;
        let (wl, amp): (Vec<f64>, Vec<f64>) = spec
            .frequency_hz
            .iter()
            .zip(&spec.amplitude)
            .filter(|(&f, &a)| f > v / 5.0 && f < top && a > 0.0)
            .map(|(&f, &a)| (v / f, 1e-3 * a))
            .unzip();
        let peak = amp.iter().copied().fold(0.0, f64::max);
        if peak > 0.0 {
            // Three decades under the strongest line; the legend goes under the axes.
            self.spectrum.y_range = Some((1e-3 * peak, 3.0 * peak));
            self.spectrum.x_range = Some((4.0 * sum.rim_pitch_m, 5.0));
        }
        let (lo, hi) = self.spectrum.x_range.unwrap_or((0.0, f64::INFINITY));
        let mut points = Vec::new();
        for (label, lambdas) in track_lines(ts, sum) {
            let (xs, ys): (Vec<f64>, Vec<f64>) = lambdas
                .into_iter()
                .filter(|l| *l >= lo && *l <= hi)
                .filter_map(|l| amp_at(&wl, &amp, l).map(|a| (l, a)))
                .unzip();
            if !xs.is_empty() {
                points.push((label, xs, ys));
            }
        }
        self.spectrum
            .series
            .push(Series::new(run.name("contact force"), wl, amp, run.style));
        if marks {
            for (label, xs, ys) in points {
                self.spectrum
                    .series
                    .push(Series::new(label, xs, ys, SeriesStyle::Markers));
            }
        }
    }

    pub(super) fn into_vec(self) -> Vec<Panel> {
        let mut v = vec![self.force, self.motion, self.spectrum, self.pads];
        v.extend(self.traction);
        v
    }
}

/// What a run's lines share: their style, the run's label (with more than one run), the
/// distance travelled at each record, and the records over a rim node's passage.
struct RunLines<'a> {
    style: SeriesStyle,
    label: Option<&'a str>,
    x: Vec<f64>,
    window: usize,
}

impl RunLines<'_> {
    /// A line's name, after the run's label when there is more than one run.
    fn name(&self, what: &str) -> String {
        match self.label {
            Some(label) => format!("{label}: {what}"),
            None => what.to_string(),
        }
    }
}

/// A column of the records.
fn col(recs: &[Rec], f: impl Fn(&Rec) -> f64) -> Vec<f64> {
    recs.iter().map(f).collect()
}

/// The spectrum's largest amplitude within 3 % of a wavelength (its line, where the
/// spectrum's resolution puts it), else at the nearest sample.
fn amp_at(wl: &[f64], amp: &[f64], lambda: f64) -> Option<f64> {
    let near = wl
        .iter()
        .zip(amp)
        .filter(|(w, _)| (w.ln() - lambda.ln()).abs() < 0.03)
        .map(|(_, &a)| a)
        .fold(f64::NAN, f64::max);
    if near.is_finite() {
        return Some(near);
    }
    wl.iter()
        .zip(amp)
        .min_by(|a, b| {
            (a.0.ln() - lambda.ln())
                .abs()
                .total_cmp(&(b.0.ln() - lambda.ln()).abs())
        })
        .map(|(_, &a)| a)
}

/// Every line the track explains, labelled, with its wavelengths (issue 48: the rail
/// element's line at 0.1 m was not): the sleeper passing and its harmonics, the passing of
/// the rail's elements (the beam's nodes: the discretisation's own excitation), P2 and the
/// pinned-pinned resonance.
fn track_lines(ts: &TrackScenario, sum: &RollingSummary) -> Vec<(String, Vec<f64>)> {
    let v = ts.vehicle.speed;
    let element = ts.spec.spacing / ts.spec.elements_per_bay.max(1) as f64;
    let one = |what: &str, f: f64| {
        let lambda = v / f;
        (
            format!("{what}: {} m ({} Hz)", sig(lambda, 3), sig(f, 3)),
            vec![lambda],
        )
    };
    let mut marks: Vec<(String, Vec<f64>)> = vec![one("sleepers", v / ts.spec.spacing)];
    let harmonics: Vec<f64> = (2..=6)
        .map(|k| ts.spec.spacing / k as f64)
        .filter(|l| (*l - element).abs() > 0.02 * element)
        .collect();
    marks.push(("sleepers x 2..6".to_string(), harmonics));
    if ts.spec.elements_per_bay > 1 {
        // The elements' passing and its second harmonic (0.1 and 0.05 m on UIC60).
        let (label, _) = one("rail elements (mesh) x 1, 2", v / element);
        marks.push((label, vec![element, 0.5 * element]));
    }
    if let Some(f) = sum.p2_hz {
        marks.push(one("P2", f));
    }
    if let Some(f) = sum.pinned_pinned_hz {
        marks.push(one("pinned-pinned", f));
    }
    marks
}
