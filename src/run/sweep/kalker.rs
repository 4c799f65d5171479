//! Kalker's linear creep coefficients from a creepage sweep of the 3D rolling wheel, on a
//! refinement ladder ([`crate::analysis::kalker`]).
//!
//! A sweep of a `rolling3d` scenario on a crowned base (its summaries carry `hertz3d`) over
//! one or more of the creepages (`rolling.creepage`, `rolling.lateral_creepage`,
//! `rolling.spin_creepage`), alone or on a ladder of one more numeric key (`[sweep] ladder =
//! { key = "wheel.zone_sectors", ... }`), fits on each rung the steady creep forces and spin
//! moment as linear functions of the creepages that vary (least squares), and gives the
//! slopes as Kalker's coefficients. The wheel and its crowned base are symmetric about the
//! wheel's mid-plane (the zone is graded symmetrically about the crest), so the mirror `eta
//! -> -eta`, `phi -> -phi` keeps `Q` and reverses `Q_y` and `M_z` (`tests/rolling3d_cli.rs`
//! checks it to 1e-9): `Q` is fitted on a constant (the free-rolling offset, which a finite
//! wheel has and a half-space has not) and `xi`, `Q_y` and `M_z` on `eta` and `phi` without
//! a constant ([`regressors`]). A longitudinal coefficient takes two runs a rung, a lateral
//! one a single run:
//!
//! | creepage | coefficient |
//! |---|---|
//! | `xi` | `C_11 = dQ / dxi / (G c^2)` |
//! | `eta` | `C_22 = -dQ_y / deta / (G c^2)`, `C_23 = -dM_z / deta / (G c^3)` |
//! | `phi` (1/m) | `C_23 = dQ_y / dphi / (G c^3)`, `C_33 = -dM_z / dphi / (G c^4)` |
//!
//! The spin's signs follow from two facts no convention changes. Kalker's forces are
//! `F_y = -G c^2 (C_22 eta + c C_23 phi)` and `M_z = G c^3 (C_23 eta - c C_33 phi)`: the
//! coupling is antisymmetric, `dQ_y / dphi = -dM_z / deta`, whatever the orientation of the
//! axis `phi` and `M_z` are taken about (softway takes both about the base's normal `n`), so
//! the coefficient read from `Q_y` at `phi` has the sign opposite to the one read from `M_z`
//! at `eta`. And the moment on the wheel resists its spin on the base, `dM_z / dphi < 0`, so
//! `C_33` is minus that slope. `tests/rolling3d_rail.rs` checks both on the elastic rail.
//!
//! `Q`, `Q_y` and `M_z` are the base's force and moment on the wheel as the run's summary
//! gives them (`steady.creep_force_N`, `lateral_force_N`, `spin_moment_N_m`); the signs make
//! each coefficient positive in Kalker's sense (his `F_x = -G c^2 C_11 xi` with softway's `xi`
//! of the other sign, `validation/halfspace3d`'s convention), `G c^k` from `hertz3d` (`G` the
//! pair's combined modulus, `2 G_1` on the rigid base; `c = sqrt(a b)` of Hertz's ellipse at
//! the run's normal force), the mean over the rung's points.
//!
//! On three or more rungs at one ratio each coefficient gets its observed order and
//! Richardson limit ([`super::creep::order_and_limit`]), and every rung is set against
//! Kalker's Table E.3 at the runs' Poisson's ratio and `a/b`. The table is the theory of two
//! bodies of one material in full adhesion: it is this problem when the runs are
//! `rolling.coupling = "uncoupled"` (the twin wheel), or the wheel on an elastic rail of its
//! material (`[rail]`), with a friction coefficient high enough that only a node or two at
//! the trailing edge slide (the table gives the slip nodes); the coupled wheel on its rigid
//! base is another problem (`validation/halfspace3d/coupled.py`), and the files say so.
//! A limit is given only where the last three rungs converge monotonically: the steps of an
//! oscillating ladder (a coarse rung's ripple) give an order but no trustworthy limit.
//!
//! Files: `kalker.md` (the table), `kalker.csv` (a row per rung and coefficient) and
//! `kalker.png` on a ladder (each coefficient against the rung, the table's value and the
//! limit).

use super::{SweepError, SweepPoint};
use crate::analysis::kalker::kalker_table;
use crate::output::csv::{push_record, record};
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::run::RunError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The largest `Q / (mu N)` of a run read as full adhesion: on Vermeulen and Johnson's
/// cubic, the chord there is within 2 % of the slope at zero.
pub const FULL_ADHESION: f64 = 0.05;

/// The creepage keys, in the order `xi`, `eta`, `phi`.
pub const CREEP_KEYS: [&str; 3] = [
    "rolling.creepage",
    "rolling.lateral_creepage",
    "rolling.spin_creepage",
];

/// A coefficient: its name, the creepage (index into [`CREEP_KEYS`]), the force (0 `Q`, 1
/// `Q_y`, 2 `M_z`), the sign and the power of `c` (module docs), and the column of
/// [`kalker_table`] (none for `C_33`).
type Coefficient = (&'static str, usize, usize, f64, i32, Option<usize>);

/// The coefficients ([`Coefficient`]).
const COEFFICIENTS: [Coefficient; 5] = [
    ("C11", 0, 0, 1.0, 2, Some(0)),
    ("C22", 1, 1, -1.0, 2, Some(1)),
    ("C23 (M_z, eta)", 1, 2, -1.0, 3, Some(2)),
    ("C23 (Q_y, phi)", 2, 1, 1.0, 3, Some(2)),
    ("C33", 2, 2, -1.0, 4, None),
];

/// The sweep's keys this study reads: the creepages that vary and the ladder's key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KalkerKeys {
    /// The varying creepages, as indices into [`CREEP_KEYS`].
    pub creepages: Vec<usize>,
    /// The ladder's key (index into the sweep's keys), if any.
    pub rung: Option<usize>,
}

/// Whether the sweep is one this study reads (module docs): a `rolling3d` sweep on a crowned
/// base over creepages, with at most one other numeric key; or on a refinement ladder alone
/// ([`super::creep::is_ladder`]) at a lateral or spin creepage (one run a rung). The
/// creepages fitted are those that are not zero at every point (the summaries' `creepages`).
pub fn study_keys(points: &[SweepPoint], keys: &[String], varying: &[usize]) -> Option<KalkerKeys> {
    let crowned = points.iter().any(|p| {
        p.summary["kind"].as_str() == Some("rolling3d") && p.summary.get("hertz3d").is_some()
    });
    if !crowned {
        return None;
    }
    let values = |i: usize| -> Option<Vec<f64>> {
        points
            .iter()
            .map(|p| p.sets[i].value.trim_matches('"').parse::<f64>().ok())
            .collect()
    };
    let mut swept = false;
    let mut rung = None;
    for &i in varying {
        if CREEP_KEYS.contains(&keys[i].as_str()) {
            swept = true;
        } else if rung.is_none() && values(i).is_some() {
            rung = Some(i);
        } else if !rung.is_some_and(|r| follows(points, i, r)) {
            return None;
        }
    }
    if !swept {
        // A ladder alone: its rungs must be a refinement.
        let mut rungs: Vec<f64> = Vec::new();
        for v in values(rung?)? {
            if !rungs.contains(&v) {
                rungs.push(v);
            }
        }
        if !super::creep::is_ladder(&rungs) {
            return None;
        }
    }
    const NAMES: [&str; 3] = ["longitudinal", "lateral", "spin_per_m"];
    let creepages: Vec<usize> = (0..3)
        .filter(|&c| {
            points.iter().any(|p| {
                p.summary["creepages"][NAMES[c]]
                    .as_f64()
                    .is_some_and(|x| x != 0.0)
            })
        })
        .collect();
    // One run a rung fits a lateral or spin coefficient (no constant), not C11 (whose fit
    // takes the free-rolling offset): a ladder alone at a longitudinal creepage alone is
    // another study (the refinement's, [`super::slip_history`]).
    if !swept && !creepages.iter().any(|&c| c > 0) {
        return None;
    }
    (!creepages.is_empty()).then_some(KalkerKeys { creepages, rung })
}

/// Whether key `i` takes one value on each value of key `r` at every point: a key set with
/// each rung (`[sweep] ladder.with`, e.g. the coarse mesh a zone's pitch needs), part of the
/// rung rather than a key of its own.
fn follows(points: &[SweepPoint], i: usize, r: usize) -> bool {
    points.iter().all(|p| {
        points
            .iter()
            .filter(|q| q.sets[r].value == p.sets[r].value)
            .all(|q| q.sets[i].value == p.sets[i].value)
    })
}

/// One rung's fit.
#[derive(Debug, Clone, PartialEq)]
pub struct RungFit {
    /// The rung's value (NaN without a ladder).
    pub rung: f64,
    /// The points fitted.
    pub points: usize,
    /// The coefficients of [`COEFFICIENTS`] (NaN where the creepage does not vary).
    pub values: [f64; 5],
    /// The largest mean count of sliding nodes of the rung's runs.
    pub slip_nodes: f64,
    /// The mean count of nodes in contact.
    pub contact_nodes: f64,
    /// Hertz's `a / b` and Poisson's ratio of the runs.
    pub a_over_b: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// The largest `|Q| / (mu N)` or `|Q_y| / (mu N)` of the rung's runs.
    pub ratio: f64,
    /// The largest residual of the fits over the rung's points relative to the largest
    /// force fitted (0 for as many points as unknowns): how linear the response is.
    pub residual: f64,
}

/// A run's figures the fit reads.
struct Run {
    creepages: [f64; 3],
    forces: [f64; 3],
    g: f64,
    c: f64,
    a_over_b: f64,
    poisson: f64,
    slip: f64,
    contact: f64,
    uncoupled: bool,
    /// The larger of `|Q| / (mu N)` and `|Q_y| / (mu N)`.
    ratio: f64,
}

impl Run {
    fn of(p: &SweepPoint) -> Option<Self> {
        let s = &p.summary;
        let f = |ptr: &str| s.pointer(ptr).and_then(serde_json::Value::as_f64);
        let run = Run {
            creepages: [
                f("/creepages/longitudinal")?,
                f("/creepages/lateral")?,
                f("/creepages/spin_per_m")?,
            ],
            forces: [
                f("/steady/creep_force_N")?,
                f("/steady/lateral_force_N")?,
                f("/steady/spin_moment_N_m")?,
            ],
            g: f("/hertz3d/combined_shear_modulus_Pa")?,
            c: f("/hertz3d/c_m")?,
            a_over_b: f("/hertz3d/a_rolling_m")? / f("/hertz3d/b_lateral_m")?,
            poisson: f("/hertz3d/poisson").unwrap_or(f64::NAN),
            slip: f("/traction/mean_slip_nodes").unwrap_or(f64::NAN),
            contact: f("/traction/mean_stick_nodes").unwrap_or(f64::NAN)
                + f("/traction/mean_slip_nodes").unwrap_or(f64::NAN),
            // The twin, or two bodies (the wheel on its rail of one material).
            uncoupled: s["coupling"].as_str() == Some("uncoupled") || s["rail"].is_object(),
            ratio: f("/steady/traction_ratio")
                .unwrap_or(f64::NAN)
                .abs()
                .max(f("/steady/lateral_ratio").unwrap_or(f64::NAN).abs()),
        };
        Some(run)
    }
}

/// The least-squares solution of `x b = y` (`x` a row per point, `k` columns): `None` when
/// the normal equations are singular.
fn least_squares(x: &[Vec<f64>], y: &[f64]) -> Option<Vec<f64>> {
    let k = x.first()?.len();
    // The normal equations [X^T X | X^T y], by Gaussian elimination with partial pivoting.
    let mut a = vec![vec![0.0; k + 1]; k];
    for (row, &yi) in x.iter().zip(y) {
        for i in 0..k {
            for j in 0..k {
                a[i][j] += row[i] * row[j];
            }
            a[i][k] += row[i] * yi;
        }
    }
    let scale = (0..k).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    for col in 0..k {
        let piv = (col..k).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        if a[piv][col].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(col, piv);
        for r in 0..k {
            if r != col {
                let m = a[r][col] / a[col][col];
                for c in col..=k {
                    a[r][c] -= m * a[col][c];
                }
            }
        }
    }
    Some((0..k).map(|i| a[i][k] / a[i][i]).collect())
}

/// The creepages (indices into [`CREEP_KEYS`]) force `force` is fitted on, of those that
/// vary, and whether with a constant: the mirror about the wheel's mid-plane makes `Q` even
/// in `(eta, phi)` and `Q_y`, `M_z` odd (module docs), so `Q` takes a constant and `xi`,
/// `Q_y` and `M_z` take `eta` and `phi` and no constant.
fn regressors(force: usize, creepages: &[usize]) -> (bool, Vec<usize>) {
    let odd = force > 0;
    let terms = creepages
        .iter()
        .copied()
        .filter(|&c| (c > 0) == odd)
        .collect();
    (!odd, terms)
}

/// The fit of one rung's runs over the creepages `creepages` (indices into [`CREEP_KEYS`]):
/// each force on its [`regressors`] (a force whose runs are too few is left out: its
/// coefficients NaN); `None` without runs.
fn fit(rung: f64, runs: &[Run], creepages: &[usize]) -> Option<RungFit> {
    if runs.is_empty() {
        return None;
    }
    // Creepages scaled to their largest magnitude, for the normal equations' condition.
    let scale: [f64; 3] = std::array::from_fn(|c| {
        let m = runs
            .iter()
            .fold(0.0_f64, |m, r| m.max(r.creepages[c].abs()));
        if m > 0.0 {
            m
        } else {
            1.0
        }
    });
    let n = runs.len() as f64;
    let mean = |f: &dyn Fn(&Run) -> f64| runs.iter().map(f).sum::<f64>() / n;
    let (g, c) = (mean(&|r| r.g), mean(&|r| r.c));
    let mut slopes = [[f64::NAN; 3]; 3];
    let mut residual: f64 = 0.0;
    for force in 0..3 {
        let (constant, mut terms) = regressors(force, creepages);
        // A term with a constant needs two values of its creepage on the rung.
        terms.retain(|&t| !constant || runs.iter().any(|r| r.creepages[t] != runs[0].creepages[t]));
        if terms.is_empty() || runs.len() < terms.len() + usize::from(constant) {
            continue;
        }
        let x: Vec<Vec<f64>> = runs
            .iter()
            .map(|r| {
                constant
                    .then_some(1.0)
                    .into_iter()
                    .chain(terms.iter().map(|&t| r.creepages[t] / scale[t]))
                    .collect()
            })
            .collect();
        let y: Vec<f64> = runs.iter().map(|r| r.forces[force]).collect();
        let b = least_squares(&x, &y)?;
        let size = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (row, yi) in x.iter().zip(&y) {
            let pred: f64 = row.iter().zip(&b).map(|(xi, bi)| xi * bi).sum();
            if size > 0.0 {
                residual = residual.max((pred - yi).abs() / size);
            }
        }
        let first = usize::from(constant);
        for (j, &t) in terms.iter().enumerate() {
            slopes[t][force] = b[first + j] / scale[t];
        }
    }
    let mut values = [f64::NAN; 5];
    for (v, &(_, cr, force, sign, power, _)) in values.iter_mut().zip(&COEFFICIENTS) {
        *v = sign * slopes[cr][force] / (g * c.powi(power));
    }
    Some(RungFit {
        rung,
        points: runs.len(),
        values,
        slip_nodes: runs.iter().map(|r| r.slip).fold(f64::NAN, f64::max),
        contact_nodes: mean(&|r| r.contact),
        a_over_b: mean(&|r| r.a_over_b),
        poisson: mean(&|r| r.poisson),
        ratio: runs.iter().map(|r| r.ratio).fold(0.0, f64::max),
        residual,
    })
}

/// The study: a fit per rung, and the ladder's order and limit per coefficient.
pub struct Study {
    /// The ladder's key, if any.
    pub rung_key: Option<String>,
    /// The varying creepages (indices into [`CREEP_KEYS`]).
    pub creepages: Vec<usize>,
    /// A fit per rung, in the ladder's order.
    pub fits: Vec<RungFit>,
    /// Per coefficient, the observed order and the Richardson limit.
    pub limits: [(Option<f64>, Option<f64>); 5],
    /// Kalker's table at the finest rung's `nu` and `a/b` (`None` outside it).
    pub table: Option<[f64; 3]>,
    /// Whether every run is a pair of one material, the twin or the wheel on its elastic
    /// rail (the table's problem).
    pub uncoupled: bool,
}

impl Study {
    /// The study of the sweep's complete points.
    pub fn of(points: &[SweepPoint], keys: &KalkerKeys) -> Self {
        let rung_of = |p: &SweepPoint| {
            keys.rung.map_or(f64::NAN, |i| {
                p.sets[i]
                    .value
                    .trim_matches('"')
                    .parse()
                    .unwrap_or(f64::NAN)
            })
        };
        let mut rungs: Vec<f64> = Vec::new();
        for p in points {
            let r = rung_of(p);
            if !rungs.iter().any(|q| q.to_bits() == r.to_bits()) {
                rungs.push(r);
            }
        }
        super::creep::coarse_to_fine(&mut rungs, points, rung_of);
        let mut uncoupled = true;
        let fits: Vec<RungFit> = rungs
            .iter()
            .filter_map(|&r| {
                let runs: Vec<Run> = points
                    .iter()
                    .filter(|p| p.status.is_complete() && rung_of(p).to_bits() == r.to_bits())
                    .filter_map(Run::of)
                    .collect();
                uncoupled &= runs.iter().all(|r| r.uncoupled);
                fit(r, &runs, &keys.creepages)
            })
            .collect();
        let rung_values: Vec<f64> = fits.iter().map(|f| f.rung).collect();
        let mut limits = [(None, None); 5];
        if keys.rung.is_some() && super::creep::is_ladder(&rung_values) {
            for (k, l) in limits.iter_mut().enumerate() {
                let v: Vec<f64> = fits.iter().map(|f| f.values[k]).collect();
                let n = v.len();
                let monotone = n >= 3 && (v[n - 1] - v[n - 2]) * (v[n - 2] - v[n - 3]) > 0.0;
                if monotone {
                    *l = super::creep::order_and_limit(&rung_values, &v);
                }
            }
        }
        let table = fits
            .last()
            .and_then(|f| kalker_table(f.poisson, f.a_over_b));
        Study {
            rung_key: keys.rung.map(|i| points[0].sets[i].key.clone()),
            creepages: keys.creepages.clone(),
            fits,
            limits,
            table,
            uncoupled,
        }
    }

    /// The coefficients the sweep gives (indices into [`COEFFICIENTS`]).
    fn shown(&self) -> Vec<usize> {
        (0..COEFFICIENTS.len())
            .filter(|&k| self.creepages.contains(&COEFFICIENTS[k].1))
            .collect()
    }

    /// Kalker's value of coefficient `k`, if tabulated.
    pub fn reference(&self, k: usize) -> Option<f64> {
        Some(self.table?[COEFFICIENTS[k].5?])
    }

    /// The coefficient `k` on every rung, its order and limit, Kalker's value and the
    /// finest rung's and the limit's distances from it (relative).
    pub fn row(&self, k: usize) -> (Vec<f64>, Option<f64>, Option<f64>, Option<f64>) {
        let v = self.fits.iter().map(|f| f.values[k]).collect();
        (v, self.limits[k].0, self.limits[k].1, self.reference(k))
    }

    fn csv(&self) -> String {
        let mut out = record([
            "coefficient",
            "rung_key",
            "rung",
            "points",
            "value",
            "order",
            "limit",
            "kalker_table",
            "relative_error",
            "a_over_b",
            "poisson",
            "max_slip_nodes",
            "contact_nodes",
            "fit_residual",
            "uncoupled",
        ]);
        let fmt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6e}"));
        for k in self.shown() {
            let reference = self.reference(k);
            for f in &self.fits {
                let v = f.values[k];
                push_record(
                    &mut out,
                    [
                        COEFFICIENTS[k].0.to_string(),
                        self.rung_key.clone().unwrap_or_default(),
                        rung_label(f.rung),
                        f.points.to_string(),
                        format!("{v:.6e}"),
                        fmt(self.limits[k].0),
                        fmt(self.limits[k].1),
                        fmt(reference),
                        fmt(reference.map(|r| v / r - 1.0)),
                        format!("{:.6}", f.a_over_b),
                        format!("{}", f.poisson),
                        format!("{}", f.slip_nodes),
                        format!("{:.2}", f.contact_nodes),
                        format!("{:.3e}", f.residual),
                        self.uncoupled.to_string(),
                    ],
                );
            }
        }
        out
    }

    fn md(&self) -> String {
        let mut s = String::new();
        let finest = self.fits.last();
        let _ = writeln!(
            s,
            "# Kalker's linear creep coefficients\n\nThe steady creep forces fitted on each rung as linear functions of the creepages that vary (a constant for the free-rolling offset), their slopes as Kalker's `C = dF / (G c^k dxi)` (`G` the pair's combined modulus, `c = sqrt(a b)` of Hertz's ellipse at the run's normal force), against Kalker's Table E.3 (1990; Johnson's Table 8.1) at nu = {} and a/b = {:.4} of the finest rung.\n",
            finest.map_or(f64::NAN, |f| f.poisson),
            finest.map_or(f64::NAN, |f| f.a_over_b)
        );
        if !self.uncoupled {
            let _ = writeln!(
                s,
                "**Not the table's problem.** These runs are the elastic wheel on its rigid base (`rolling.coupling = \"coupled\"`): Kalker's table is the pair of one material, which `rolling.coupling = \"uncoupled\"` or an elastic rail (`[rail]`) poses. The coupled pair's full-adhesion coefficients do not converge (the bonded edge's oscillating singularity between dissimilar bodies); compare its creep curve with `validation/halfspace3d/coupled.py` instead.\n"
            );
        }
        let ratio = self.fits.iter().map(|f| f.ratio).fold(0.0, f64::max);
        if ratio > FULL_ADHESION {
            let _ = writeln!(
                s,
                "**Not full adhesion.** A run's creep force reaches {ratio:.3} of mu N (the table's theory is the limit of vanishing creepage: keep it below {FULL_ADHESION}, with small creepages or a large `contact.friction`): the slopes below are chords of the creep curve, not Kalker's coefficients.\n"
            );
        }
        let key = self.rung_key.as_deref().unwrap_or("rung");
        let _ = write!(s, "| {key} | points | slip nodes (max) / in contact |");
        let shown = self.shown();
        for &k in &shown {
            let _ = write!(s, " {} |", COEFFICIENTS[k].0);
        }
        let _ = write!(s, "\n|---:|---:|---:|");
        for _ in &shown {
            s.push_str("---:|");
        }
        s.push('\n');
        for f in &self.fits {
            let _ = write!(
                s,
                "| {} | {} | {:.2} / {:.1} |",
                rung_label(f.rung),
                f.points,
                f.slip_nodes,
                f.contact_nodes
            );
            for &k in &shown {
                let _ = write!(s, " {:.4} |", f.values[k]);
            }
            s.push('\n');
        }
        let opt = |x: Option<f64>, d: usize| x.map_or("-".to_string(), |v| format!("{v:.d$}"));
        let percent = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:+.2} %"));
        let mut line = |label: &str, cell: &dyn Fn(usize) -> String| {
            let _ = write!(s, "| {label} | | |");
            for &k in &shown {
                let _ = write!(s, " {} |", cell(k));
            }
            s.push('\n');
        };
        line("observed order", &|k| opt(self.limits[k].0, 2));
        line("Richardson limit", &|k| opt(self.limits[k].1, 4));
        line("Kalker's table", &|k| opt(self.reference(k), 3));
        line("finest rung's distance", &|k| {
            percent(
                self.reference(k)
                    .zip(finest)
                    .map(|(r, f)| 100.0 * (f.values[k] / r - 1.0)),
            )
        });
        line("limit's distance", &|k| {
            percent(
                self.reference(k)
                    .zip(self.limits[k].1)
                    .map(|(r, l)| 100.0 * (l / r - 1.0)),
            )
        });
        let residual = self.fits.iter().map(|f| f.residual).fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "\nThe fits' largest residual: {residual:.2e} of the largest force fitted (0 with as many points as unknowns). By the mirror about the wheel's mid-plane, Q is fitted on a constant and xi, Q_y and M_z on eta and phi without a constant. Orders and limits from the last three rungs where they converge monotonically at an order within the ladder's bounds (else '-')."
        );
        s
    }

    fn panel(&self) -> Panel {
        let key = self.rung_key.as_deref().unwrap_or("rung");
        let mut p = Panel::new(
            "Kalker's coefficients on the ladder, against his table",
            key.to_string(),
            "C / Kalker's table",
        );
        p.x_log = true;
        let x: Vec<f64> = self.fits.iter().map(|f| f.rung).collect();
        // Each rung on its own labelled tick (384 ... 1536 ended at an unlabelled 1600).
        p.x_ticks = x.clone();
        for k in self.shown() {
            // Each coefficient against its own table value, so that they share the axis.
            let (v, _, limit, Some(reference)) = self.row(k) else {
                continue;
            };
            let name = COEFFICIENTS[k].0;
            p.series.push(Series::new(
                format!("{name} (table {reference:.3})"),
                x.clone(),
                v.iter().map(|c| c / reference).collect(),
                SeriesStyle::LineMarkers,
            ));
            if let (Some(l), Some(&last)) = (limit, x.last()) {
                p.series.push(Series::new(
                    format!("{name}: Richardson limit {l:.3}"),
                    vec![last],
                    vec![l / reference],
                    SeriesStyle::Markers,
                ));
            }
        }
        p.hlines.push((1.0, "Kalker's table".into()));
        let no_limit: Vec<&str> = self
            .shown()
            .into_iter()
            .filter(|&k| self.reference(k).is_some() && self.limits[k].1.is_none())
            .map(|k| COEFFICIENTS[k].0)
            .collect();
        p.note = format!(
            "{}; the slopes of the steady forces against the creepages over G c^k, c of Hertz's ellipse at each run's normal force; a/b = {:.3}, nu = {}.{}",
            if self.uncoupled {
                "The pair of one material (the twin wheel, or the wheel on its rail), Kalker's problem"
            } else {
                "The coupled wheel on its rigid base: not Kalker's problem"
            },
            self.fits.last().map_or(f64::NAN, |f| f.a_over_b),
            self.fits.last().map_or(f64::NAN, |f| f.poisson),
            if no_limit.is_empty() {
                String::new()
            } else {
                format!(
                    " No Richardson limit for {}: the last three rungs do not converge monotonically at an order within bounds.",
                    no_limit.join(", ")
                )
            },
        );
        p
    }
}

/// A rung's value as the tables write it: `-` without a ladder.
fn rung_label(rung: f64) -> String {
    if rung.is_nan() {
        "-".into()
    } else {
        format!("{rung}")
    }
}

/// Writes the study (module docs) of the sweep's complete points; returns the files.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn coefficients(
    out: &Path,
    points: &[SweepPoint],
    keys: &KalkerKeys,
) -> Result<Vec<PathBuf>, SweepError> {
    let study = Study::of(points, keys);
    if study.fits.is_empty() {
        return Ok(Vec::new());
    }
    let write = |name: &str, text: String| super::write_text(out, name, &text);
    let mut files = vec![
        write("kalker.csv", study.csv())?,
        write("kalker.md", study.md())?,
    ];
    // The figure draws a ladder (two rungs or more of a numeric key) against the table.
    let drawn = study.shown().iter().any(|&k| study.reference(k).is_some());
    let panel = study.panel();
    let finite = panel
        .series
        .iter()
        .any(|s| s.y.iter().any(|y| y.is_finite()));
    if study.rung_key.is_some() && study.fits.len() >= 2 && drawn && finite {
        let png = out.join("kalker.png");
        panels(&png, &[panel], 1, 1, (1100, 750)).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep point of the 3D rolling on a crowned base with these creepages and forces.
    fn point(sets: &[(&str, f64)], creep: [f64; 3], forces: [f64; 3], c: f64) -> SweepPoint {
        use crate::run::sweep::PointStatus;
        use crate::scenario::overrides::Override;
        SweepPoint {
            sets: sets
                .iter()
                .map(|(k, v)| Override {
                    key: (*k).into(),
                    value: format!("{v}"),
                })
                .collect(),
            value: String::new(),
            dir: std::path::PathBuf::new(),
            summary: serde_json::json!({
                "kind": "rolling3d",
                "coupling": "uncoupled",
                "creepages": {"longitudinal": creep[0], "lateral": creep[1], "spin_per_m": creep[2]},
                "steady": {"creep_force_N": forces[0], "lateral_force_N": forces[1],
                           "spin_moment_N_m": forces[2], "traction_ratio": 0.004, "lateral_ratio": 0.004},
                "hertz3d": {"combined_shear_modulus_Pa": 1.64e11, "c_m": c, "a_rolling_m": c,
                            "b_lateral_m": c, "poisson": 0.25},
                "traction": {"mean_slip_nodes": 0.1, "mean_stick_nodes": 30.0},
            }),
            warnings: Vec::new(),
            status: PointStatus::Complete,
        }
    }

    /// Synthetic ladders whose coefficients converge to Kalker's table at second order,
    /// `C(h) = C_table (1 + 0.1 h^2)` (`h` the pitch relative to the coarsest rung), with a
    /// free-rolling offset on `Q`: the longitudinal sweep (two creepages a rung) and the
    /// lateral ladder alone (one run a rung) give the order 2 and the table as the limit.
    #[test]
    fn ladders_converge_to_the_table() {
        let (g, c) = (1.64e11, 2.5e-3);
        let table = kalker_table(0.25, 1.0).unwrap();
        let rungs = [384.0, 768.0, 1536.0];
        let at = |r: f64, k: usize| table[k] * (1.0 + 0.1 * (384.0 / r).powi(2));
        let keys = vec![
            "rolling.creepage".to_string(),
            "wheel.zone_sectors".to_string(),
        ];
        let mut pts = Vec::new();
        for xi in [-5e-4, 5e-4] {
            for r in rungs {
                let q = 300.0 + g * c * c * at(r, 0) * xi;
                pts.push(point(
                    &[("rolling.creepage", xi), ("wheel.zone_sectors", r)],
                    [xi, 0.0, 0.0],
                    [q, 0.0, 0.0],
                    c,
                ));
            }
        }
        let study_keys_of = |pts: &[SweepPoint], keys: &[String], varying: &[usize]| {
            study_keys(pts, keys, varying).expect("a Kalker study")
        };
        let k = study_keys_of(&pts, &keys, &[0, 1]);
        assert_eq!(k.creepages, vec![0]);
        let s = Study::of(&pts, &k);
        let (v, order, limit, reference) = s.row(0);
        assert!((v[2] / at(1536.0, 0) - 1.0).abs() < 1e-12, "{v:?}");
        assert!((order.unwrap() - 2.0).abs() < 1e-6, "{order:?}");
        assert!((limit.unwrap() / table[0] - 1.0).abs() < 1e-9, "{limit:?}");
        assert_eq!(reference, Some(table[0]));
        // The same ladder written finest first (`wheel.zone_sectors=1536,768,384`), the runs'
        // unknowns growing with the sectors: the same study, the finest rung last.
        let mut reversed: Vec<SweepPoint> = pts.iter().rev().cloned().collect();
        for p in &mut reversed {
            let sectors: f64 = p.sets[1].value.parse().unwrap();
            p.summary["dofs"] = (100.0 * sectors).into();
            p.summary["h_s"] = 2.5e-6.into();
        }
        let r = Study::of(&reversed, &k);
        let (vr, order_r, limit_r, _) = r.row(0);
        assert_eq!(
            (vr.to_vec(), order_r, limit_r),
            (v.to_vec(), order, limit),
            "a ladder written finest first"
        );
        let keys = vec![
            "rolling.lateral_creepage".to_string(),
            "wheel.zone_sectors".to_string(),
        ];
        let eta = 5e-4;
        let pts: Vec<SweepPoint> = rungs
            .iter()
            .map(|&r| {
                point(
                    &[("rolling.lateral_creepage", eta), ("wheel.zone_sectors", r)],
                    [0.0, eta, 0.0],
                    [
                        250.0,
                        -g * c * c * at(r, 1) * eta,
                        -g * c.powi(3) * at(r, 2) * eta,
                    ],
                    c,
                )
            })
            .collect();
        let k = study_keys_of(&pts, &keys, &[1]);
        assert_eq!(k.creepages, vec![1]);
        let s = Study::of(&pts, &k);
        for (coef, col) in [(1, 1), (2, 2)] {
            let (_, order, limit, _) = s.row(coef);
            assert!((order.unwrap() - 2.0).abs() < 1e-6, "{order:?}");
            assert!(
                (limit.unwrap() / table[col] - 1.0).abs() < 1e-9,
                "{limit:?}"
            );
        }
        assert!(s.row(0).0.iter().all(|v| v.is_nan()), "no C11 without xi");
        // Not a refinement: a ladder alone of 1, 3, 4 is no study.
        let odd: Vec<SweepPoint> = [1.0, 3.0, 4.0]
            .iter()
            .map(|&r| point(&[("wheel.zone_sectors", r)], [0.0, eta, 0.0], [0.0; 3], c))
            .collect();
        assert!(study_keys(&odd, &keys[1..], &[0]).is_none());
    }

    /// The shipped ladder of ratio sqrt(2), 768, 1088 and 1536 sectors, each rung with its
    /// own coarse mesh (`[sweep] ladder.with`: the key `wheel.mesh` follows the rung): a
    /// Kalker study whose order and limit are the power law's, at rungs of two ratios
    /// (1.4167 then 1.4118). A key that changes within a rung is no part of it: no study.
    #[test]
    fn a_ladder_with_its_coarse_meshes_converges_to_the_table() {
        use crate::scenario::overrides::Override;
        let (g, c) = (1.64e11, 2.5e-3);
        let table = kalker_table(0.25, 1.0).unwrap();
        let at = |r: f64| table[0] * (1.0 + 0.1 * (768.0 / r).powi(2));
        let keys: Vec<String> = ["rolling.creepage", "wheel.zone_sectors", "wheel.mesh"]
            .map(String::from)
            .to_vec();
        let mut pts = Vec::new();
        for xi in [-5e-4, 5e-4] {
            for (r, mesh) in [(768.0, 48), (1088.0, 68), (1536.0, 48)] {
                let mut p = point(
                    &[("rolling.creepage", xi), ("wheel.zone_sectors", r)],
                    [xi, 0.0, 0.0],
                    [300.0 + g * c * c * at(r) * xi, 0.0, 0.0],
                    c,
                );
                p.sets.push(Override {
                    key: "wheel.mesh".into(),
                    value: format!("[4, {mesh}, 2]"),
                });
                pts.push(p);
            }
        }
        let k = study_keys(&pts, &keys, &[0, 1, 2]).expect("a Kalker study");
        assert_eq!(k.rung, Some(1));
        let s = Study::of(&pts, &k);
        let (_, order, limit, _) = s.row(0);
        assert!((order.unwrap() - 2.0).abs() < 1e-6, "{order:?}");
        assert!((limit.unwrap() / table[0] - 1.0).abs() < 1e-9, "{limit:?}");
        pts[0].sets[2].value = "[4, 96, 2]".into();
        assert!(study_keys(&pts, &keys, &[0, 1, 2]).is_none());
    }

    /// An oscillating ladder (the rail's 4.457, 4.221, 4.280) has no limit, though its
    /// steps shrink; the wheel on its elastic rail (coupled, with `rail` in its summary)
    /// is the table's problem, the coupled wheel on the rigid base is not.
    #[test]
    fn an_oscillating_ladder_has_no_limit_and_the_rail_is_the_tables_problem() {
        let c = 2.6e-3;
        let g = 8.2e10;
        let keys = vec![
            "rolling.creepage".to_string(),
            "wheel.zone_sectors".to_string(),
        ];
        let ladder = |values: [f64; 3], rail: bool| {
            let mut pts = Vec::new();
            for xi in [-5e-4, 5e-4] {
                for (r, v) in [192.0, 384.0, 768.0].into_iter().zip(values) {
                    let mut p = point(
                        &[("rolling.creepage", xi), ("wheel.zone_sectors", r)],
                        [xi, 0.0, 0.0],
                        [-500.0 + g * c * c * v * xi, 0.0, 0.0],
                        c,
                    );
                    p.summary["hertz3d"]["combined_shear_modulus_Pa"] = g.into();
                    p.summary["coupling"] = "coupled".into();
                    if rail {
                        p.summary["rail"] = serde_json::json!({"length_m": 0.13});
                    }
                    pts.push(p);
                }
            }
            let k = study_keys(&pts, &keys, &[0, 1]).expect("a Kalker study");
            Study::of(&pts, &k)
        };
        let s = ladder([4.457, 4.221, 4.280], true);
        let (v, order, limit, _) = s.row(0);
        assert!((v[2] / 4.280 - 1.0).abs() < 1e-9, "{v:?}");
        assert_eq!((order, limit), (None, None));
        assert!(
            s.uncoupled,
            "the wheel on its rail is the pair of one material"
        );
        // A monotone ladder of the same rungs gives its limit.
        let m = ladder([4.457, 4.321, 4.290], true);
        assert!(m.row(0).1.is_some() && m.row(0).2.is_some());
        assert!(!ladder([4.457, 4.321, 4.290], false).uncoupled);
    }

    /// The least-squares fit recovers an exact linear law through more points than
    /// unknowns, and refuses points that do not span the creepages.
    #[test]
    fn least_squares_recovers_a_linear_law() {
        let pts = [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0), (0.5, 0.5)];
        let x: Vec<Vec<f64>> = pts.iter().map(|&(a, b)| vec![1.0, a, b]).collect();
        let y: Vec<f64> = pts.iter().map(|&(a, b)| 3.0 - 2.0 * a + 0.5 * b).collect();
        let b = least_squares(&x, &y).unwrap();
        for (got, want) in b.iter().zip([3.0, -2.0, 0.5]) {
            assert!((got - want).abs() < 1e-12, "{b:?}");
        }
        let flat: Vec<Vec<f64>> = pts.iter().map(|&(a, _)| vec![1.0, a, 2.0 * a]).collect();
        assert!(least_squares(&flat, &y).is_none());
    }
}
