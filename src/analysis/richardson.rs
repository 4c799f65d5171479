//! Richardson's extrapolation on a refinement ladder: the observed order of a figure from
//! three rungs of one refinement ratio, and the limit it extrapolates to. Used by the
//! convergence study (`softway converge`) and the creep ladder of a sweep.

/// The observed orders of `values` along the rungs `xs`: at rung `i >= 2`,
/// `p = ln|d0 / d1| / ln(x_i / x_{i-1})` with `d0`, `d1` the last two differences (on rungs
/// whose two ratios differ, the root of the power law's own relation, [`order_of`]); `None`
/// where the differences do not shrink (`|d0 / d1| <= 1`) or one of them is zero.
pub fn observed_orders(xs: &[f64], values: &[f64]) -> Vec<Option<f64>> {
    (2..values.len())
        .map(|i| {
            let d0 = values[i - 1] - values[i - 2];
            let d1 = values[i] - values[i - 1];
            let r0 = (xs[i - 1] / xs[i - 2]).ln().abs();
            let r = (xs[i] / xs[i - 1]).ln().abs();
            let q = (d0 / d1).abs();
            (d0 != 0.0 && d1 != 0.0 && q.is_finite() && q > 1.0 && r > 0.0 && r0 > 0.0)
                .then(|| order_of(q, r0, r))
                .flatten()
        })
        .collect()
}

/// The order `p` at which `f = L + C h^p` changes by `d0` then `d1` (`q = d0 / d1`) over two
/// steps of `ln` ratios `r0` and `r` (`h` divided by `e^r0`, then `e^r`): `q = e^{r p}
/// (e^{r0 p} - 1) / (e^{r p} - 1)`, which is `e^{r p}` on a ladder of one ratio. A ladder
/// whose rungs' ratios differ a little (a zone's pitch 768, 1088, 1536 round the rim: 1.4167
/// then 1.4118) takes the root (bisection: the right side grows with `p`), not `ln q / r`.
pub fn order_of(q: f64, r0: f64, r: f64) -> Option<f64> {
    if (r0 - r).abs() <= 1e-12 * r {
        return Some(q.ln() / r);
    }
    let g = |p: f64| (r * p).exp() * (r0 * p).exp_m1() / (r * p).exp_m1() - q;
    // g(0+) = r0 / r - q; g grows with p.
    let (mut lo, mut hi) = (1e-9, 1.0);
    if g(lo) > 0.0 {
        return None;
    }
    while g(hi) < 0.0 {
        hi *= 2.0;
        if hi > 1e3 {
            return None;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The Richardson estimate of the limit from the last three rungs.
pub fn extrapolate(xs: &[f64], values: &[f64], orders: &[Option<f64>]) -> Option<f64> {
    let n = values.len();
    let p = (*orders.last()?)?;
    let r = (xs[n - 1] / xs[n - 2]).ln().abs().exp();
    let d = values[n - 1] - values[n - 2];
    Some(values[n - 1] + d / (r.powf(p) - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A figure `f(x) = L + C x^p` on a geometric ladder gives back `p` and `L`.
    #[test]
    fn a_power_law_gives_back_its_order_and_limit() {
        let xs = [0.4, 0.2, 0.1, 0.05];
        let (limit, c, p) = (3.0, 0.7, 1.5);
        let v: Vec<f64> = xs.iter().map(|x: &f64| limit + c * x.powf(p)).collect();
        let orders = observed_orders(&xs, &v);
        assert_eq!(orders.len(), 2);
        for o in &orders {
            assert!((o.unwrap() - p).abs() < 1e-12, "{o:?}");
        }
        let l = extrapolate(&xs, &v, &orders).unwrap();
        assert!((l - limit).abs() < 1e-12, "{l}");
        // Rungs at two ratios (a zone's sectors 768, 1088, 1536): the order and limit of
        // the power law itself, where `ln q / r` of the last ratio would miss them.
        let xs = [768.0, 1088.0, 1536.0];
        let v: Vec<f64> = xs.iter().map(|x: &f64| limit + c * x.powf(-p)).collect();
        let orders = observed_orders(&xs, &v);
        assert!((orders[0].unwrap() - p).abs() < 1e-9, "{orders:?}");
        let l = extrapolate(&xs, &v, &orders).unwrap();
        assert!((l - limit).abs() < 1e-12, "{l}");
        let naive = ((v[1] - v[0]) / (v[2] - v[1])).ln() / (1536.0f64 / 1088.0).ln();
        assert!((naive - p).abs() > 1e-2, "{naive}");
        // Differences that grow give no order, and then no limit.
        let grow = [1.0, 1.1, 1.3];
        assert_eq!(observed_orders(&xs[..3], &grow), [None]);
        assert_eq!(extrapolate(&xs[..3], &grow, &[None]), None);
    }
}
