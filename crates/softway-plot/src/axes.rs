//! Axes: ranges, data → pixel scales, number formatting and ticks.

use crate::style::text_w;

/// Data → pixel mapping of one axis.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scale {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
    pub(crate) log: bool,
    /// Pixel of `lo` and of `hi`.
    pub(crate) p_lo: f64,
    pub(crate) p_hi: f64,
}

impl Scale {
    fn frac(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            // Halved to stay finite for ranges close to ±f64::MAX.
            (0.5 * v - 0.5 * self.lo) / (0.5 * self.hi - 0.5 * self.lo)
        }
    }
    pub(crate) fn px(&self, v: f64) -> f64 {
        self.p_lo + self.frac(v) * (self.p_hi - self.p_lo)
    }
}

pub(crate) fn valid(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

pub(crate) fn is_const(lo: f64, hi: f64) -> bool {
    hi - lo <= 1e-12 * lo.abs().max(hi.abs())
}

/// Data extent → axis range: 5 % margins; constant data gets some width.
pub(crate) fn auto_range(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    if log {
        let (a, b) = (lo.log10(), hi.log10());
        let (a, b) = if b - a < 1e-9 {
            (a - 0.5, b + 0.5)
        } else {
            let m = 0.05 * (b - a);
            (a - m, b + m)
        };
        (10f64.powf(a), 10f64.powf(b))
    } else if is_const(lo, hi) {
        let c = 0.5 * (lo + hi);
        let h = if c == 0.0 { 1.0 } else { 0.1 * c.abs() };
        (c - h, c + h)
    } else {
        let m = 0.05 * hi - 0.05 * lo;
        ((lo - m).max(f64::MIN), (hi + m).min(f64::MAX))
    }
}

/// A user range if usable, else the automatic range of the data extent.
pub(crate) fn resolve_range(
    user: Option<(f64, f64)>,
    data: Option<(f64, f64)>,
    log: bool,
) -> Option<(f64, f64)> {
    if let Some((a, b)) = user {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        if valid(a, log) && valid(b, log) {
            let degenerate = if log {
                b / a < 1.0 + 1e-9
            } else {
                is_const(a, b)
            };
            return Some(if degenerate {
                auto_range(a, b, log)
            } else {
                (a, b)
            });
        }
    }
    data.map(|(a, b)| auto_range(a, b, log))
}

pub(crate) fn extend(r: &mut Option<(f64, f64)>, v: f64) {
    *r = Some(match *r {
        None => (v, v),
        Some((a, b)) => (a.min(v), b.max(v)),
    });
}

fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            c => c,
        })
        .collect()
}

/// Replaces a leading hyphen by a typographic minus sign.
fn fix_minus(s: String) -> String {
    match s.strip_prefix('-') {
        Some(r) => format!("−{r}"),
        None => s,
    }
}

fn trim_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Smallest number of decimals that represents `x` (a tick step) exactly.
fn decimals_needed(x: f64) -> usize {
    let x = x.abs();
    for d in 0..=12 {
        let s = x * 10f64.powi(d);
        if (s - s.round()).abs() <= 1e-6 * s.max(1.0) {
            return d as usize;
        }
    }
    12
}

/// `v` with `d` decimals, no negative zero, typographic minus.
fn fmt_fixed(v: f64, d: usize) -> String {
    let s = format!("{v:.d$}");
    let zero = s
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.');
    if zero {
        s.trim_start_matches('-').to_string()
    } else {
        fix_minus(s)
    }
}

/// Short general-purpose formatting (up to 6 significant digits), with
/// powers of ten for very large or small magnitudes.
fn fmt_general(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let d = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        return fix_minus(trim_zeros(format!("{v:.d$}")));
    }
    fmt_pow(v)
}

/// `v` rounded to `sig` significant digits (at least 1) for a title, a legend or a note:
/// plain decimals from 10⁻³ to below 10⁶ with trailing zeros dropped (`72.5`, `300`,
/// `0.0125`), else `m×10ⁿ` (`8.4×10⁶`); a typographic minus; `0` for zero; non-finite
/// values as Rust prints them.
pub(crate) fn fmt_sig(v: f64, sig: usize) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    if v == 0.0 {
        return "0".into();
    }
    let sig = sig.clamp(1, 17) as i32;
    // Rounded first, so that 999.96 to 4 digits gives 1000 and not 999.96 -> "1000.0".
    let e = v.abs().log10().floor() as i32;
    let r: f64 = format!("{:.*e}", (sig - 1) as usize, v)
        .parse()
        .unwrap_or(v);
    let e = if r.abs() >= 10f64.powi(e + 1) {
        e + 1
    } else {
        e
    };
    if (-3..6).contains(&e) {
        let d = (sig - 1 - e).max(0) as usize;
        return fix_minus(trim_zeros(format!("{r:.d$}")));
    }
    let m = trim_zeros(format!("{:.*}", (sig - 1) as usize, r / 10f64.powi(e)));
    format!("{}×10{}", fix_minus(m), superscript(e))
}

/// `m×10ⁿ` (or `10ⁿ`) formatting.
fn fmt_pow(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    let mut e = a.log10().floor() as i32;
    let mut m = v / 10f64.powi(e);
    if (m.abs() * 1000.0).round() >= 10_000.0 {
        e += 1;
        m = v / 10f64.powi(e);
    }
    let ms = trim_zeros(format!("{m:.3}"));
    match ms.as_str() {
        "1" => format!("10{}", superscript(e)),
        "-1" => format!("−10{}", superscript(e)),
        _ => format!("{}×10{}", fix_minus(ms), superscript(e)),
    }
}

/// Labels for equally spaced linear ticks, with a common power-of-ten
/// factor (returned separately, e.g. `×10⁻³`) for very large or small
/// magnitudes.
fn format_linear(values: &[f64], step: f64) -> (Vec<String>, Option<String>) {
    let m = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let e = if m > 0.0 && !(1e-2..1e5).contains(&m) {
        m.log10().floor() as i32
    } else {
        0
    };
    let f = 10f64.powi(e);
    let d = decimals_needed(step / f);
    let labels = values.iter().map(|v| fmt_fixed(v / f, d)).collect();
    (labels, (e != 0).then(|| format!("×10{}", superscript(e))))
}

#[derive(Debug, Default, Clone)]
pub(crate) struct Ticks {
    pub(crate) major: Vec<(f64, String)>,
    pub(crate) minor: Vec<f64>,
    /// Common factor of the labels, e.g. `×10⁻³`.
    pub(crate) offset: Option<String>,
}

impl Ticks {
    pub(crate) fn max_label_w(&self, fs: f64) -> f64 {
        self.major
            .iter()
            .map(|(_, l)| text_w(l, fs))
            .fold(0.0, f64::max)
    }
}

/// Minimal pixel distance between tick labels.
fn tick_need(labels: &[String], fs: f64, horizontal: bool) -> f64 {
    if horizontal {
        labels.iter().map(|l| text_w(l, fs)).fold(0.0, f64::max) + 1.2 * fs
    } else {
        2.2 * fs
    }
}

pub(crate) fn linear_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Ticks {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite() && len_px > 0.0) {
        return Ticks::default();
    }
    let max_n = if horizontal { 9 } else { 8 };
    let mut e = (span / 20.0).log10().floor() as i32;
    let mut fallback: Option<Ticks> = None;
    for _ in 0..10 {
        let p = 10f64.powi(e);
        for m in [1.0, 2.0, 2.5, 5.0] {
            let step = m * p;
            let k0 = (lo / step - 1e-9).ceil();
            let k1 = (hi / step + 1e-9).floor();
            if !(k0.is_finite() && k1.is_finite()) {
                continue;
            }
            let nf = if k1 >= k0 { k1 - k0 + 1.0 } else { 0.0 };
            if nf > max_n as f64 {
                continue;
            }
            let n = nf as usize;
            let values: Vec<f64> = (0..n)
                .map(|i| {
                    let v = (k0 + i as f64) * step;
                    if v.abs() < step * 1e-9 {
                        0.0
                    } else {
                        v
                    }
                })
                .collect();
            let (labels, offset) = format_linear(&values, step);
            let spacing = step / span * len_px;
            let fits = spacing >= tick_need(&labels, fs, horizontal);
            let t = Ticks {
                major: values.into_iter().zip(labels).collect(),
                minor: Vec::new(),
                offset,
            };
            if fits {
                return t;
            }
            if fallback.is_none() || n >= 1 {
                fallback = Some(t);
            }
        }
        e += 1;
    }
    fallback.unwrap_or_default()
}

fn log_label(v: f64, pow: bool) -> String {
    if pow {
        fmt_pow(v)
    } else {
        fmt_general(v)
    }
}

fn log_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Ticks {
    if !(lo > 0.0 && hi > lo && hi.is_finite() && len_px > 0.0) {
        return Ticks::default();
    }
    let (l0, l1) = (lo.log10(), hi.log10());
    let k0 = (l0 - 1e-9).ceil() as i32;
    let k1 = (l1 + 1e-9).floor() as i32;
    let (dec, sub) = (
        || decade_ticks(lo, hi, len_px, fs, horizontal),
        || sub_decade_ticks(lo, hi, len_px, fs, horizontal),
    );
    // With three or more decades label (some of) the decades; over a
    // shorter range prefer 1-2-5 style values, which say more.
    let t = if k1 - k0 >= 2 {
        dec().or_else(sub)
    } else {
        sub().or_else(dec)
    };
    t.unwrap_or_else(|| linear_ticks(lo, hi, len_px, fs, horizontal))
}

fn in_log_range(v: f64, lo: f64, hi: f64) -> bool {
    v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9)
}

/// Log-axis labels: plain numbers when all values lie in `plain`, else
/// powers of ten.
fn log_labels(vals: &[f64], plain: std::ops::Range<f64>) -> Vec<String> {
    let pow = vals.iter().any(|&v| !plain.contains(&v));
    vals.iter().map(|&v| log_label(v, pow)).collect()
}

/// Every `stride`-th decade as major ticks, the rest (or 2…9) as minor.
fn decade_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Option<Ticks> {
    let (l0, l1) = (lo.log10(), hi.log10());
    let k0 = (l0 - 1e-9).ceil() as i32;
    let k1 = (l1 + 1e-9).floor() as i32;
    let px_per_dec = len_px / (l1 - l0);
    for stride in 1..=(k1 - k0).max(1) {
        let ks: Vec<i32> = (k0..=k1).filter(|k| k.rem_euclid(stride) == 0).collect();
        if ks.len() < 2 {
            return None;
        }
        let vals: Vec<f64> = ks.iter().map(|&k| 10f64.powi(k)).collect();
        let labels = log_labels(&vals, 1e-2..1e4);
        if ks.len() <= 10 && f64::from(stride) * px_per_dec >= tick_need(&labels, fs, horizontal) {
            let mut minor = Vec::new();
            if stride == 1 {
                if px_per_dec >= 2.5 * fs {
                    for k in (k0 - 1)..=k1 {
                        for m in 2..=9 {
                            let v = f64::from(m) * 10f64.powi(k);
                            if in_log_range(v, lo, hi) {
                                minor.push(v);
                            }
                        }
                    }
                }
            } else {
                minor = (k0..=k1)
                    .filter(|k| k.rem_euclid(stride) != 0)
                    .map(|k| 10f64.powi(k))
                    .collect();
            }
            return Some(Ticks {
                major: vals.into_iter().zip(labels).collect(),
                minor,
                offset: None,
            });
        }
    }
    None
}

/// Ticks at m·10ᵏ for m in a 1-2-5 style set, densest set that fits.
fn sub_decade_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Option<Ticks> {
    let (l0, l1) = (lo.log10(), hi.log10());
    let px = |v: f64| (v.log10() - l0) / (l1 - l0) * len_px;
    let multiples = |set: &[f64]| {
        let mut vals = Vec::new();
        for k in (l0.floor() as i32 - 1)..=(l1.ceil() as i32) {
            for &m in set {
                let v = m * 10f64.powi(k);
                if in_log_range(v, lo, hi) {
                    vals.push(v);
                }
            }
        }
        vals
    };
    const ALL: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    let sets: [&[f64]; 5] = [
        &ALL,
        &[1.0, 2.0, 3.0, 5.0],
        &[1.0, 2.0, 5.0],
        &[1.0, 3.0],
        &[1.0],
    ];
    for set in sets {
        let vals = multiples(set);
        if vals.len() < 2 || vals.len() > 10 {
            continue;
        }
        let labels = log_labels(&vals, 1e-3..1e5);
        let min_gap = vals
            .windows(2)
            .map(|w| px(w[1]) - px(w[0]))
            .fold(f64::INFINITY, f64::min);
        if min_gap >= tick_need(&labels, fs, horizontal) {
            let minor = if set.len() < ALL.len() {
                multiples(&ALL)
                    .into_iter()
                    .filter(|v| !vals.iter().any(|w| (v / w - 1.0).abs() < 1e-9))
                    .collect()
            } else {
                Vec::new()
            };
            return Some(Ticks {
                major: vals.into_iter().zip(labels).collect(),
                minor,
                offset: None,
            });
        }
    }
    None
}

/// Labelled ticks at the given values `at` (module docs of [`crate::Panel::x_ticks`]), the
/// automatic ticks `auto` as minor ones; `None` when a value is outside `[lo, hi]` (or not
/// positive on a log axis) or two labels would not fit apart.
pub(crate) fn given_ticks(
    at: &[f64],
    (lo, hi): (f64, f64),
    log: bool,
    len_px: f64,
    (fs, horizontal): (f64, bool),
    auto: Ticks,
) -> Option<Ticks> {
    let mut vals: Vec<f64> = at.to_vec();
    vals.sort_by(f64::total_cmp);
    vals.dedup();
    let inside = |v: f64| v.is_finite() && v >= lo && v <= hi && (!log || v > 0.0);
    if vals.is_empty()
        || !vals.iter().all(|&v| inside(v))
        || hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater)
    {
        return None;
    }
    let px = |v: f64| {
        if log {
            (v.log10() - lo.log10()) / (hi.log10() - lo.log10()) * len_px
        } else {
            (v - lo) / (hi - lo) * len_px
        }
    };
    let labels: Vec<String> = vals.iter().map(|&v| fmt_general(v)).collect();
    let gap = vals
        .windows(2)
        .map(|w| px(w[1]) - px(w[0]))
        .fold(f64::INFINITY, f64::min);
    if gap < tick_need(&labels, fs, horizontal) {
        return None;
    }
    // A minor tick a hair from a labelled one reads as a misplaced tick: left out.
    let near = |v: f64| vals.iter().any(|&w| (px(v) - px(w)).abs() < 0.03 * len_px);
    let minor = auto
        .major
        .iter()
        .map(|(v, _)| *v)
        .chain(auto.minor)
        .filter(|&v| !near(v))
        .collect();
    Some(Ticks {
        major: vals.into_iter().zip(labels).collect(),
        minor,
        offset: None,
    })
}

pub(crate) fn make_ticks(
    lo: f64,
    hi: f64,
    log: bool,
    len_px: f64,
    fs: f64,
    horizontal: bool,
) -> Ticks {
    if log {
        log_ticks(lo, hi, len_px, fs, horizontal)
    } else {
        linear_ticks(lo, hi, len_px, fs, horizontal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tick-label font size used by the tests: 20 px, 2× super-sampled.
    const FS: f64 = 40.0;

    /// Issue 48: `omega = 72.46376811594203 rad/s` in a title.
    #[test]
    fn significant_digits_for_titles() {
        assert_eq!(fmt_sig(72.463_768_115_942_03, 3), "72.5");
        assert_eq!(fmt_sig(300.0, 3), "300");
        assert_eq!(fmt_sig(839_812.0, 4), "839800");
        assert_eq!(fmt_sig(0.6, 3), "0.6");
        assert_eq!(fmt_sig(0.012_54, 3), "0.0125");
        assert_eq!(fmt_sig(999.96, 4), "1000");
        assert_eq!(fmt_sig(-47.746, 3), "−47.7");
        assert_eq!(fmt_sig(1.242e-5, 3), "1.24×10⁻⁵");
        assert_eq!(fmt_sig(8.4e6, 3), "8.4×10⁶");
        assert_eq!(fmt_sig(9.9996e5, 3), "1×10⁶");
        assert_eq!(fmt_sig(0.0, 3), "0");
        assert_eq!(fmt_sig(f64::NAN, 3), "NaN");
        assert_eq!(fmt_sig(5.0, 0), "5");
    }

    #[test]
    fn formatting() {
        let (l, o) = format_linear(&[0.1, 0.2, 0.30000000000000004], 0.1);
        assert_eq!(l, vec!["0.1", "0.2", "0.3"]);
        assert!(o.is_none());
        let (l, _) = format_linear(&[-0.5, -0.0, 0.5], 0.5);
        assert_eq!(l, vec!["−0.5", "0.0", "0.5"]);
        let (l, o) = format_linear(&[0.0, 5e-4, 1e-3], 5e-4);
        assert_eq!(l, vec!["0.0", "0.5", "1.0"]);
        assert_eq!(o.as_deref(), Some("×10⁻³"));
        let (l, o) = format_linear(&[1e5, 1.25e5, 1.5e5], 2.5e4);
        assert_eq!(l, vec!["1.00", "1.25", "1.50"]);
        assert_eq!(o.as_deref(), Some("×10⁵"));
        assert_eq!(fmt_general(0.01), "0.01");
        assert_eq!(fmt_general(1e-5), "10⁻⁵");
        assert_eq!(fmt_general(2.5e7), "2.5×10⁷");
        assert_eq!(fmt_pow(1.0), "10⁰");
        let t = linear_ticks(0.0, 0.3, 800.0, 20.0, true);
        assert!(t.major.iter().all(|(_, l)| l.len() <= 4), "{:?}", t.major);
        let t = log_ticks(1e-6, 1e-1, 800.0, 20.0, true);
        assert!(t.major.len() >= 3);
        let t = log_ticks(2.0, 8.0, 800.0, 20.0, true);
        assert!(t.major.len() >= 2, "{:?}", t.major);
    }

    /// A ladder's rungs as the labelled ticks of a log axis, the automatic ticks as minor
    /// ones; refused when a rung leaves the range or two labels would overlap.
    #[test]
    fn given_ticks_label_a_ladders_rungs_or_give_way() {
        let (lo, hi) = (349.0, 2000.0);
        let auto = log_ticks(lo, hi, 1600.0, FS, true);
        let t = given_ticks(
            &[1536.0, 384.0, 768.0],
            (lo, hi),
            true,
            1600.0,
            (FS, true),
            auto.clone(),
        )
        .expect("three rungs fit");
        let labels: Vec<&str> = t.major.iter().map(|(_, l)| l.as_str()).collect();
        assert_eq!(labels, ["384", "768", "1536"]);
        assert!(
            t.minor.iter().any(|&v| (v - 1000.0).abs() < 1e-9),
            "{:?}",
            t.minor
        );
        assert!(given_ticks(
            &[384.0, 2500.0],
            (lo, hi),
            true,
            1600.0,
            (FS, true),
            auto.clone()
        )
        .is_none());
        assert!(given_ticks(&[1000.0, 1001.0], (lo, hi), true, 1600.0, (FS, true), auto).is_none());
    }

    /// `step` is 1, 2, 2.5 or 5 times a power of ten.
    fn is_nice(step: f64) -> bool {
        let p = 10f64.powf(step.log10().floor());
        [1.0, 2.0, 2.5, 5.0, 10.0]
            .iter()
            .any(|m| (step / p - m).abs() < 1e-9 * m)
    }

    /// The label as a number (typographic minus read back).
    fn label_value(l: &str) -> f64 {
        l.replace('−', "-").parse().unwrap()
    }

    #[test]
    fn linear_ticks_have_nice_steps_covering_the_range() {
        let ranges = [
            (0.0, 1.0),
            (-3.7, 12.2),
            (0.013, 0.0171),
            (-2.5e-7, 7.1e-7),
            (1.0e6, 4.3e6),
            (99.0, 101.0),
            (-1e-3, -2e-4),
        ];
        for (lo, hi) in ranges {
            for (len_px, horizontal) in [(400.0, false), (1600.0, false), (1600.0, true)] {
                let t = linear_ticks(lo, hi, len_px, FS, horizontal);
                let what = format!("[{lo}, {hi}] over {len_px} px: {:?}", t.major);
                let v: Vec<f64> = t.major.iter().map(|(v, _)| *v).collect();
                assert!((2..=9).contains(&v.len()), "{what}");
                let step = v[1] - v[0];
                assert!(step > 0.0 && is_nice(step), "step {step}, {what}");
                for w in v.windows(2) {
                    assert!((w[1] - w[0] - step).abs() <= 1e-6 * step, "{what}");
                }
                for x in &v {
                    let k = x / step;
                    assert!((k - k.round()).abs() < 1e-6, "{x} off the step, {what}");
                }
                // Inside the range, and no room left for another tick at
                // either end.
                let (first, last) = (v[0], v[v.len() - 1]);
                let eps = 1e-9 * step;
                assert!(first >= lo - eps && first - lo < step + eps, "{what}");
                assert!(last <= hi + eps && hi - last < step + eps, "{what}");
                // The labels fit and tell the ticks apart.
                let labels: Vec<String> = t.major.iter().map(|(_, l)| l.clone()).collect();
                assert!(step / (hi - lo) * len_px >= tick_need(&labels, FS, horizontal));
                let mut distinct = labels.clone();
                distinct.dedup();
                assert_eq!(distinct.len(), labels.len(), "{what}");
            }
        }
    }

    #[test]
    fn common_factor_for_tiny_and_huge_values() {
        for (lo, hi, factor, e) in [
            (0.0, 3e-6, "×10⁻⁶", -6),
            (-4e-3, 1e-3, "×10⁻³", -3),
            (2.0e8, 7.5e8, "×10⁸", 8),
            (-1.2e5, 1.0e5, "×10⁵", 5),
        ] {
            let t = linear_ticks(lo, hi, 1600.0, FS, true);
            assert_eq!(t.offset.as_deref(), Some(factor), "{:?}", t.major);
            for (v, l) in &t.major {
                // Short labels that, times the factor, give the tick value.
                assert!(l.chars().count() <= 5, "{l:?}");
                let x = label_value(l) * 10f64.powi(e);
                assert!((x - v).abs() <= 1e-9 * (hi - lo), "{l} vs {v}");
            }
        }
        for (lo, hi) in [(0.0, 1.0), (-50.0, 3000.0), (0.02, 0.09), (1e4, 9e4)] {
            let t = linear_ticks(lo, hi, 1600.0, FS, true);
            assert!(t.offset.is_none(), "[{lo}, {hi}]: {:?}", t.offset);
            for (v, l) in &t.major {
                assert!((label_value(l) - v).abs() <= 1e-9 * (hi - lo), "{l} vs {v}");
            }
        }
    }

    #[test]
    fn log_ticks_are_powers_of_ten() {
        for (lo, hi) in [(1e-6, 1e2), (3e-3, 2e4), (1e-12, 1.0), (0.5, 2e3)] {
            for horizontal in [true, false] {
                let t = log_ticks(lo, hi, 800.0, FS, horizontal);
                let what = format!("[{lo}, {hi}]: {:?}", t.major);
                assert!(t.major.len() >= 2, "{what}");
                assert!(t.offset.is_none(), "{what}");
                for (v, l) in &t.major {
                    let e = v.log10().round() as i32;
                    assert_eq!(*v, 10f64.powi(e), "{what}");
                    assert!(in_log_range(*v, lo, hi), "{what}");
                    assert!(
                        *l == fmt_general(*v) || *l == format!("10{}", superscript(e)),
                        "label {l:?} of {v}"
                    );
                }
                for m in &t.minor {
                    assert!(in_log_range(*m, lo, hi), "minor {m}, {what}");
                    assert!(!t.major.iter().any(|(v, _)| v == m), "minor {m}, {what}");
                }
            }
        }
        // Three decades within 10⁻²..10⁴: plain labels.
        let t = log_ticks(1.0, 1000.0, 800.0, FS, true);
        let labels: Vec<&str> = t.major.iter().map(|(_, l)| l.as_str()).collect();
        assert_eq!(labels, ["1", "10", "100", "1000"]);
        // Beyond: powers of ten.
        let t = log_ticks(1e-9, 1e-3, 800.0, FS, false);
        assert!(
            t.major.iter().all(|(_, l)| l.starts_with("10")),
            "{:?}",
            t.major
        );
    }
}
