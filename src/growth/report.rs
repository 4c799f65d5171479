//! What a study writes, after every pass (each file rewritten whole, atomically) and at the
//! end: `passes.csv`, `bands.csv`, `orders.csv` (periodic profiles), `profile.csv`,
//! `spectrum.png`, `growth_rate.png`, `profile.png`, `orders.png` (periodic) and
//! `summary.json` ([`GrowthSummary`]). Everything is computed from the [`StudyState`]
//! alone, so a resumed study writes the same numbers.

use super::spectrum::{band_levels, bands, order_amplitudes, slope, Band};
use super::{GrowthConfig, GrowthError, StudyState};
use crate::output::csv::{push_record, record};
use crate::output::files::write_atomic;
use serde::Serialize;
use softway_plot::{line_plot, panels, sig, Panel, Series, SeriesStyle};
use std::path::{Path, PathBuf};

mod figures;
use figures::plot_all;

/// A band's figures.
#[derive(Debug, Clone, Serialize)]
pub struct BandFigures {
    /// Centre wavelength, m.
    pub centre_wavelength_m: f64,
    /// `V / lambda_c`, Hz.
    pub frequency_hz: f64,
    /// Orders (or DFT lines) in the band: first and last.
    pub orders: (usize, usize),
    /// Level of the initial profile, dB re 1 um.
    pub level_initial_db: f64,
    /// Level of the last profile, dB re 1 um.
    pub level_final_db: f64,
    /// Growth rate over the passes (least-squares slope), dB per 1e5 real passes.
    pub rate_db_per_1e5: f64,
}

/// A polygon order's figures (periodic profiles).
#[derive(Debug, Clone, Serialize)]
pub struct OrderFigures {
    /// Harmonics per revolution.
    pub order: usize,
    /// Wavelength on the surface, m.
    pub wavelength_m: f64,
    /// `V / lambda`, Hz.
    pub frequency_hz: f64,
    /// Amplitude of the initial profile, m.
    pub amplitude_initial_m: f64,
    /// Amplitude of the last profile, m.
    pub amplitude_final_m: f64,
    /// Growth rate over the passes (least-squares slope of `20 log10 A`), dB per 1e5 real
    /// passes.
    pub rate_db_per_1e5: f64,
    /// Growth rate of the last pass alone, dB per 1e5 real passes.
    pub rate_last_db_per_1e5: f64,
}

/// `summary.json` of a study.
#[derive(Debug, Clone, Serialize)]
pub struct GrowthSummary {
    /// Simulated passes finished.
    pub passes: usize,
    /// Real passes they stand for.
    pub real_passes: f64,
    /// `N_w`.
    pub passes_per_pass: f64,
    /// Rolling speed, m/s.
    pub speed_m_s: f64,
    /// The profile's length (one period of a periodic one), m.
    pub length_m: f64,
    /// Samples.
    pub samples: usize,
    /// Periodic (a wheel's rim).
    pub periodic: bool,
    /// Moving-average width of the wear, m (0: none), and its samples.
    pub smoothing_m: f64,
    /// Samples of the moving average.
    pub smoothing_samples: usize,
    /// The wear's low-pass wavelength, m (0: none): the fastest growth is sought at or
    /// above it.
    pub cutoff_m: f64,
    /// RMS of the reference wear pattern (the smooth surface's, one simulated pass), m.
    pub reference_wear_rms_m: Option<f64>,
    /// RMS roughness, initial and final, m.
    pub rms_initial_m: f64,
    /// Final RMS roughness, m.
    pub rms_final_m: f64,
    /// Uniform loss (radius or height worn evenly), m, over all real passes.
    pub uniform_loss_m: f64,
    /// The band of the largest growth rate: the fastest growth, or the slowest decay when
    /// every band decays (its rate is then negative).
    pub fastest_band: Option<BandFigures>,
    /// The order of the largest growth rate (periodic profiles): the fastest growth, or the
    /// slowest decay when every order decays.
    pub fastest_order: Option<OrderFigures>,
    /// Every band.
    pub bands: Vec<BandFigures>,
    /// Every order (periodic profiles).
    pub orders: Vec<OrderFigures>,
    /// The last pass's scalars.
    pub last_pass: Vec<(String, f64)>,
    /// Mean wall-clock time of a pass over those run, s.
    pub mean_pass_wall_s: f64,
    /// SHA-256 of the scenario text.
    pub scenario_sha256: String,
    /// The study stopped before the passes it was asked for (a signal; while it runs, the
    /// files written after each pass say `true` until the last pass is in, so that a study
    /// killed outright is not taken for a finished one). [`summary`] gives `false`: the
    /// state alone does not know the target ([`write_all`] sets it).
    pub interrupted: bool,
}

/// The figures of a state: bands and orders with their levels per profile.
struct Figures {
    bands: Vec<Band>,
    levels: Vec<Vec<f64>>,
    amplitudes: Vec<Vec<f64>>,
    real: Vec<f64>,
    length: f64,
}

fn figures(state: &StudyState, config: &GrowthConfig) -> Figures {
    let profiles = state.profiles();
    let n = state.n;
    let length = n as f64 * state.dx.0[0];
    let b = bands(n, length);
    let amplitudes: Vec<Vec<f64>> = profiles.iter().map(|z| order_amplitudes(z)).collect();
    let levels = amplitudes.iter().map(|a| band_levels(a, &b)).collect();
    let real = (0..profiles.len())
        .map(|p| p as f64 * config.passes_per_pass)
        .collect();
    Figures {
        bands: b,
        levels,
        amplitudes,
        real,
        length,
    }
}

/// The fewest periods of a band's wavelength an open profile must hold for the band to be
/// the fastest-growing one ([`summary`]).
pub const OPEN_MIN_PERIODS: f64 = 8.0;

/// Whether each band holds a level the passes can grow from: within 180 dB of the initial
/// profile's loudest band (an empty band's level, e.g. -285 dB, follows the rounding
/// errors). The others have no rate and are not drawn.
fn held_bands(f: &Figures) -> Vec<bool> {
    let l_max = f.levels[0]
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max);
    f.levels[0]
        .iter()
        .map(|&l| l.is_finite() && l > l_max - 180.0)
        .collect()
}

/// A level or a rate in dB for the tables: four decimals, or an empty cell where there is
/// none (an empty band's level of -inf dB, the rate of a band or an order the initial
/// profile does not hold): the tables held `-inf` and `NaN` cells there.
fn cell(db: f64) -> String {
    if db.is_finite() {
        format!("{db:.4}")
    } else {
        String::new()
    }
}

/// The summary of a state (module docs).
pub fn summary(state: &StudyState, config: &GrowthConfig, speed: f64) -> GrowthSummary {
    let f = figures(state, config);
    let per_1e5 = 1e5;
    let last = f.levels.len() - 1;
    // Likewise a band 180 dB below the initial profile's loudest.
    let held_band = held_bands(&f);
    let band_figs: Vec<BandFigures> = f
        .bands
        .iter()
        .enumerate()
        .map(|(j, b)| {
            let held = held_band[j];
            let y: Vec<f64> = f
                .levels
                .iter()
                .map(|l| if held { l[j] } else { f64::NAN })
                .collect();
            BandFigures {
                centre_wavelength_m: b.centre,
                frequency_hz: speed / b.centre,
                orders: (b.k_first, b.k_last),
                level_initial_db: y[0],
                level_final_db: y[last],
                rate_db_per_1e5: slope(&f.real, &y) * per_1e5,
            }
        })
        .collect();
    // An order the initial profile does not hold (below 1e-9 of its largest amplitude)
    // has no rate: its level would follow the rounding errors.
    let a_max = f.amplitudes[0].iter().cloned().fold(0.0, f64::max);
    let orders: Vec<OrderFigures> = if state.periodic {
        (1..=f.amplitudes[0].len())
            .map(|k| {
                let held = f.amplitudes[0][k - 1] > 1e-9 * a_max;
                let y: Vec<f64> = f
                    .amplitudes
                    .iter()
                    .map(|a| {
                        if held {
                            20.0 * a[k - 1].log10()
                        } else {
                            f64::NAN
                        }
                    })
                    .collect();
                let last_rate = if last >= 1 {
                    (y[last] - y[last - 1]) / config.passes_per_pass * per_1e5
                } else {
                    f64::NAN
                };
                let lambda = f.length / k as f64;
                OrderFigures {
                    order: k,
                    wavelength_m: lambda,
                    frequency_hz: speed / lambda,
                    amplitude_initial_m: f.amplitudes[0][k - 1],
                    amplitude_final_m: f.amplitudes[last][k - 1],
                    rate_db_per_1e5: slope(&f.real, &y) * per_1e5,
                    rate_last_db_per_1e5: last_rate,
                }
            })
            .collect()
    } else {
        Vec::new()
    };
    // On an open profile (a rail) a band counts for the fastest growth when the record
    // holds at least OPEN_MIN_PERIODS of its wavelength (a longer one's rate is the ends').
    let longest = if state.periodic {
        f64::INFINITY
    } else {
        f.length / OPEN_MIN_PERIODS
    };
    let fastest_band = band_figs
        .iter()
        .filter(|b| {
            b.rate_db_per_1e5.is_finite()
                && b.centre_wavelength_m >= config.cutoff_m
                && b.centre_wavelength_m <= longest
        })
        .max_by(|a, b| a.rate_db_per_1e5.total_cmp(&b.rate_db_per_1e5))
        .cloned();
    let fastest_order = orders
        .iter()
        .filter(|o| o.rate_db_per_1e5.is_finite() && o.wavelength_m >= config.cutoff_m)
        .max_by(|a, b| a.rate_db_per_1e5.total_cmp(&b.rate_db_per_1e5))
        .cloned();
    let profiles = state.profiles();
    let walls: Vec<f64> = state.passes.iter().map(|p| p.wall_s).collect();
    GrowthSummary {
        passes: state.passes.len(),
        real_passes: state.passes.len() as f64 * config.passes_per_pass,
        passes_per_pass: config.passes_per_pass,
        speed_m_s: speed,
        length_m: f.length,
        samples: state.n,
        periodic: state.periodic,
        smoothing_m: config.smoothing_m,
        smoothing_samples: super::spectrum::window_samples(state.dx.0[0], config.smoothing_m),
        cutoff_m: config.cutoff_m,
        reference_wear_rms_m: state.reference.as_ref().map(|r| super::spectrum::rms(&r.0)),
        rms_initial_m: super::spectrum::rms(profiles[0]),
        rms_final_m: super::spectrum::rms(profiles[profiles.len() - 1]),
        uniform_loss_m: state.uniform_loss(),
        fastest_band,
        fastest_order,
        bands: band_figs,
        orders,
        last_pass: state
            .passes
            .last()
            .map(|p| {
                p.scalar_names
                    .iter()
                    .cloned()
                    .zip(p.scalar_values.0.iter().copied())
                    .collect()
            })
            .unwrap_or_default(),
        mean_pass_wall_s: if walls.is_empty() {
            0.0
        } else {
            walls.iter().sum::<f64>() / walls.len() as f64
        },
        scenario_sha256: state.scenario_sha256.clone(),
        interrupted: false,
    }
}

fn write(path: &Path, text: &str) -> Result<(), GrowthError> {
    write_atomic(path, text.as_bytes()).map_err(|e| GrowthError::output(path, e))
}

/// Writes every file of the study into `out` (module docs); returns their paths. With
/// `plots` false the PNGs are left out; `interrupted` goes into `summary.json`
/// ([`GrowthSummary::interrupted`]).
///
/// # Errors
/// [`GrowthError::Output`].
pub fn write_all(
    out: &Path,
    state: &StudyState,
    config: &GrowthConfig,
    speed: f64,
    (plots, interrupted): (bool, bool),
) -> Result<Vec<PathBuf>, GrowthError> {
    let s = GrowthSummary {
        interrupted,
        ..summary(state, config, speed)
    };
    let f = figures(state, config);
    let mut files = Vec::new();
    let mut put = |name: &str, text: String| -> Result<(), GrowthError> {
        let p = out.join(name);
        write(&p, &text)?;
        files.push(p);
        Ok(())
    };
    // passes.csv
    let names: Vec<String> = state
        .passes
        .first()
        .map(|p| p.scalar_names.clone())
        .unwrap_or_default();
    let mut t = record(
        ["pass", "real_passes", "rms_m", "uniform_loss_m", "wall_s"]
            .into_iter()
            .chain(names.iter().map(String::as_str)),
    );
    let mut loss = 0.0;
    for (p, rec) in state.passes.iter().enumerate() {
        loss += rec.uniform_loss.0[0];
        let mut cells = vec![
            format!("{p}"),
            format!("{:e}", (p + 1) as f64 * config.passes_per_pass),
            format!("{:e}", super::spectrum::rms(&rec.z.0)),
            format!("{loss:e}"),
            format!("{:.4}", rec.wall_s),
        ];
        cells.extend(rec.scalar_values.0.iter().map(|v| format!("{v:e}")));
        push_record(&mut t, &cells);
    }
    put("passes.csv", t)?;
    // bands.csv
    let mut head: Vec<String> = [
        "centre_wavelength_m",
        "frequency_hz",
        "first_order",
        "last_order",
    ]
    .map(String::from)
    .to_vec();
    head.extend((0..f.levels.len()).map(|p| format!("level_after_{p}_passes_db")));
    head.push("rate_db_per_1e5".into());
    let mut t = record(&head);
    for (j, b) in s.bands.iter().enumerate() {
        let mut cells = vec![
            format!("{:e}", b.centre_wavelength_m),
            format!("{:e}", b.frequency_hz),
            format!("{}", b.orders.0),
            format!("{}", b.orders.1),
        ];
        cells.extend(f.levels.iter().map(|l| cell(l[j])));
        cells.push(cell(b.rate_db_per_1e5));
        push_record(&mut t, &cells);
    }
    put("bands.csv", t)?;
    // orders.csv
    if state.periodic {
        let mut head: Vec<String> = ["order", "wavelength_m", "frequency_hz"]
            .map(String::from)
            .to_vec();
        head.extend((0..f.amplitudes.len()).map(|p| format!("amplitude_after_{p}_passes_m")));
        head.extend(["rate_db_per_1e5", "rate_last_db_per_1e5"].map(String::from));
        let mut t = record(&head);
        for o in &s.orders {
            let mut cells = vec![
                format!("{}", o.order),
                format!("{:e}", o.wavelength_m),
                format!("{:e}", o.frequency_hz),
            ];
            cells.extend(f.amplitudes.iter().map(|a| format!("{:e}", a[o.order - 1])));
            cells.push(cell(o.rate_db_per_1e5));
            cells.push(cell(o.rate_last_db_per_1e5));
            push_record(&mut t, &cells);
        }
        put("orders.csv", t)?;
    }
    // profile.csv
    let profiles = state.profiles();
    let (z0, zl) = (profiles[0], profiles[profiles.len() - 1]);
    let wear_last = state.passes.last().map(|p| p.wear.0.as_slice());
    let mut t = record(["x_m", "z_initial_m", "z_m", "wear_last_pass_m"]);
    for i in 0..state.n {
        push_record(
            &mut t,
            [
                state.x0.0[0] + i as f64 * state.dx.0[0],
                z0[i],
                zl[i],
                wear_last.map(|w| w[i]).unwrap_or(0.0),
            ]
            .map(|x| format!("{x:e}")),
        );
    }
    put("profile.csv", t)?;
    let json = serde_json::to_string_pretty(&s).map_err(|e| GrowthError::output(out, e))?;
    put("summary.json", json)?;
    if plots {
        files.extend(plot_all(out, state, &s, &f)?);
    }
    Ok(files)
}
