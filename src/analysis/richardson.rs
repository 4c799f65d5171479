//! Richardson's extrapolation on a refinement ladder: the observed order of a figure from
//! three rungs of one refinement ratio, and the limit it extrapolates to. Used by the
//! convergence study (`softway converge`) and the creep ladder of a sweep.

/// The observed orders of `values` along the rungs `xs`: at rung `i >= 2`,
/// `p = ln|d0 / d1| / ln(x_i / x_{i-1})` with `d0`, `d1` the last two differences; `None`
/// where the differences do not shrink (`|d0 / d1| <= 1`) or one of them is zero.
pub fn observed_orders(xs: &[f64], values: &[f64]) -> Vec<Option<f64>> {
    (2..values.len())
        .map(|i| {
            let d0 = values[i - 1] - values[i - 2];
            let d1 = values[i] - values[i - 1];
            let r = (xs[i] / xs[i - 1]).ln().abs();
            let q = (d0 / d1).abs();
            (d0 != 0.0 && d1 != 0.0 && q.is_finite() && q > 1.0 && r > 0.0).then(|| q.ln() / r)
        })
        .collect()
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
        // Differences that grow give no order, and then no limit.
        let grow = [1.0, 1.1, 1.3];
        assert_eq!(observed_orders(&xs[..3], &grow), [None]);
        assert_eq!(extrapolate(&xs[..3], &grow, &[None]), None);
    }
}
