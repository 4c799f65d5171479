//! A panel's checks before it is drawn: its data finite and in order, its ranges, an axis
//! set by one isolated point.

use super::*;

pub(crate) fn validate_panel(p: &Panel) -> Res<()> {
    for (i, s) in p.series.iter().enumerate() {
        if s.x.len() != s.y.len() {
            return Err(Fail::Draw(format!(
                "series {i} ({:?}) has {} x values but {} y values",
                s.label,
                s.x.len(),
                s.y.len()
            )));
        }
    }
    let any = p.series.iter().any(|s| {
        s.x.iter()
            .zip(&s.y)
            .any(|(&x, &y)| valid(x, p.x_log) && valid(y, p.y_log))
    });
    if any {
        Ok(())
    } else if p.series.is_empty() {
        Err(Fail::Empty("the panel has no series".into()))
    } else {
        Err(Fail::Empty(format!(
            "no series of panel {:?} has a finite{} point",
            p.title,
            if p.x_log || p.y_log {
                " (positive on log axes)"
            } else {
                ""
            }
        )))
    }
}

/// Axis ranges of a panel (x, y).
pub(super) fn panel_ranges(p: &Panel) -> Res<((f64, f64), (f64, f64))> {
    let mut dx = None;
    for s in &p.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if valid(x, p.x_log) && valid(y, p.y_log) {
                extend(&mut dx, x);
            }
        }
    }
    let xr = resolve_range(p.x_range, dx, p.x_log)
        .ok_or_else(|| Fail::Empty("no finite data".into()))?;
    let mut dy = None;
    for s in &p.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if valid(x, p.x_log) && valid(y, p.y_log) && x >= xr.0 && x <= xr.1 {
                extend(&mut dy, y);
            }
        }
    }
    for (y, _) in &p.hlines {
        if valid(*y, p.y_log) {
            extend(&mut dy, *y);
        }
    }
    let yr = resolve_range(p.y_range, dy, p.y_log)
        .or_else(|| resolve_range(None, dx.map(|_| (1.0, 1.0)), p.y_log))
        .ok_or_else(|| Fail::Empty("no finite data".into()))?;
    Ok((xr, yr))
}

/// An automatic axis range set by one isolated point (issue 48: one empty band at
/// -285 dB flattened every real curve of a spectrum to a line): the description of that
/// point, when the points at one end of the data, at most one per series, stand apart from
/// all others by more than three quarters of the data's extent, in decades on a log axis
/// (the others squeezed into a quarter of the axis), and the others vary by more than 5 %
/// of their size (a shape the point flattens; a flat sequence after a first transient
/// hides nothing). Series of fewer than eight points are not judged (a convergence
/// ladder's few rungs).
pub(super) fn isolated_extreme(p: &Panel, xr: (f64, f64)) -> Option<String> {
    let t = |v: f64| if p.y_log { v.log10() } else { v };
    // (value on the axis, series, x)
    type P = (f64, usize, f64);
    let mut pts: Vec<P> = Vec::new();
    for (i, s) in p.series.iter().enumerate() {
        let here: Vec<(f64, usize, f64)> =
            s.x.iter()
                .zip(&s.y)
                .filter(|(&x, &y)| valid(x, p.x_log) && valid(y, p.y_log) && x >= xr.0 && x <= xr.1)
                .map(|(&x, &y)| (t(y), i, x))
                .collect();
        if here.len() >= 8 {
            pts.extend(here);
        }
    }
    if pts.len() < 8 {
        return None;
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let span = pts[pts.len() - 1].0 - pts[0].0;
    if !(span > 0.0 && span.is_finite()) {
        return None;
    }
    // Each end: the cluster within 1 % of the extent of the extreme, then the gap to the
    // next point.
    let ends: [(Vec<&P>, &str); 2] = [
        (pts.iter().collect(), "lowest"),
        (pts.iter().rev().collect(), "highest"),
    ];
    for (ordered, which) in ends {
        let first = ordered[0].0;
        let k = ordered
            .iter()
            .take_while(|q| (q.0 - first).abs() <= 0.01 * span)
            .count();
        if k >= ordered.len() - 1 {
            continue;
        }
        let gap = (ordered[k].0 - ordered[k - 1].0).abs();
        let mut per_series = vec![0usize; p.series.len()];
        for q in &ordered[..k] {
            per_series[q.1] += 1;
        }
        // What the others would show on their own axis: a shape (a variation of more than
        // 5 % of their size; on a log axis of a factor 1.05) the isolated point flattens. A
        // first pass's transient above a flat sequence hides nothing.
        let (a, b) = (ordered[k].0, ordered[ordered.len() - 1].0);
        let rest = (b - a).abs();
        let hides = if p.y_log {
            rest > 1.05f64.log10()
        } else {
            rest > 0.05 * a.abs().max(b.abs())
        };
        if gap > 0.75 * span && hides && per_series.iter().all(|&n| n <= 1) {
            let q = ordered[0];
            let y = if p.y_log { 10f64.powf(q.0) } else { q.0 };
            return Some(format!(
                "the y range of panel {:?} is set by one isolated point, the {which} \
                 (series {:?} at x = {}, y = {}): leave it out of the range or set the range",
                p.title,
                p.series[q.1].label,
                crate::axes::fmt_sig(q.2, 4),
                crate::axes::fmt_sig(y, 4)
            ));
        }
    }
    None
}
