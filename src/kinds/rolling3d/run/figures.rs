//! The 3D rolling run's figure (`rolling3d.png`): the creep forces, the normal force and the
//! last step's patch along the rolling direction ([`super`]'s module docs).

use super::{PatchNode, Rolling3dFiles};
use crate::output::plot::{sig, Panel, Series, SeriesStyle};

impl Rolling3dFiles {
    /// The figure's panels (module docs).
    pub(super) fn panels(&self) -> Vec<Panel> {
        let t: Vec<f64> = self.series.iter().map(|r| 1e3 * r[0]).collect();
        let settle = (
            0.0,
            1e3 * self.settled,
            "flattening and settling".to_string(),
        );
        let mut creep = Panel::new("Creep forces on the wheel", "time t [ms]", "force / (mu N)");
        creep.series.push(Series::new(
            "Q / (mu N), along the rolling direction",
            t.clone(),
            self.series.iter().map(|r| r[2]).collect(),
            SeriesStyle::Line,
        ));
        creep.series.push(Series::new(
            "Q_y / (mu N), along the axle",
            t.clone(),
            self.series.iter().map(|r| r[3]).collect(),
            SeriesStyle::Dashed,
        ));
        if self.steady_ratio.is_finite() {
            creep.hlines.push((
                self.steady_ratio,
                format!("steady Q / (mu N) = {}", sig(self.steady_ratio, 4)),
            ));
        }
        creep.vspans.push(settle.clone());
        // The axis holds the rolling after the settling; the start-up's swings under a
        // small normal force may run off it.
        let after: Vec<f64> = self
            .series
            .iter()
            .filter(|r| r[0] >= self.settled)
            .flat_map(|r| [r[2], r[3]])
            .filter(|x| x.is_finite())
            .chain(
                [0.0, self.steady_ratio]
                    .into_iter()
                    .filter(|x| x.is_finite()),
            )
            .collect();
        if self.mu > 0.0 && after.len() > 2 {
            let lo = after.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = after.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let pad = 0.2 * (hi - lo) + 0.05;
            creep.y_range = Some((lo - pad, hi + pad));
            creep.note = "The axis is that of the rolling after the settling.".into();
        }
        if self.mu <= 0.0 {
            creep.note = "Frictionless: no creep force.".into();
        }
        let mut normal = Panel::new("Normal force", "time t [ms]", "N [kN]");
        normal.series.push(Series::new(
            "N",
            t,
            self.series.iter().map(|r| 1e-3 * r[1]).collect(),
            SeriesStyle::Line,
        ));
        normal.vspans.push(settle);
        let mut patch = Panel::new(
            "The patch at the last step, along the rolling direction",
            "s [mm] (the wheel's travel over the base: +)",
            "stress [MPa]",
        );
        let all_layers: Vec<usize> = {
            let mut l: Vec<usize> = self.patch.iter().map(|p| p.layer).collect();
            l.dedup();
            l
        };
        // The mid layer (or the first), whose pressure and traction are drawn; the others'
        // pressures as thin lines: the loaded ones, and of many (a wide wheel) at most three
        // on the side z > 0.
        let mid = all_layers.get(all_layers.len() / 2).copied().unwrap_or(0);
        let loaded = |l: usize| self.patch.iter().any(|p| p.layer == l && p.pressure > 0.0);
        let mut layers: Vec<usize> = all_layers
            .iter()
            .copied()
            .filter(|&l| l == mid || loaded(l))
            .collect();
        if layers.len() > 5 {
            let side: Vec<usize> = layers.iter().copied().filter(|&l| l > mid).collect();
            let picks = 3.min(side.len());
            let mut kept = vec![mid];
            kept.extend((0..picks).map(|i| side[(i + 1) * side.len() / (picks + 1)]));
            layers = kept;
        }
        if let Some((a, p0)) = self.hertz {
            let n = 81;
            let s: Vec<f64> = (0..n)
                .map(|i| 1e3 * a * (-1.0 + 2.0 * i as f64 / (n - 1) as f64))
                .collect();
            let p: Vec<f64> = s
                .iter()
                .map(|x| 1e-6 * p0 * (1.0 - (1e-3 * x / a).powi(2)).max(0.0).sqrt())
                .collect();
            patch.series.push(Series::new(
                "Hertz's pressure at z = 0",
                s,
                p,
                SeriesStyle::LineMarkers,
            ));
        }
        for &l in &layers {
            let row: Vec<&PatchNode> = self.patch.iter().filter(|p| p.layer == l).collect();
            let s: Vec<f64> = row.iter().map(|p| 1e3 * p.s).collect();
            let z = row.first().map_or(0.0, |p| 1e3 * p.z);
            if l != mid {
                patch.series.push(Series::new(
                    format!("p, layer at z = {} mm", sig(z, 3)),
                    s,
                    row.iter().map(|p| 1e-6 * p.pressure).collect(),
                    SeriesStyle::Dashed,
                ));
                continue;
            }
            patch.series.push(Series::new(
                format!("p, layer at z = {} mm", sig(z, 3)),
                s.clone(),
                row.iter().map(|p| 1e-6 * p.pressure).collect(),
                SeriesStyle::Line,
            ));
            if self.mu > 0.0 {
                // Above mu = 1 the bound would set the scale and flatten the rest.
                if self.mu <= 1.0 {
                    patch.series.push(Series::new(
                        if self.falling {
                            "mu_s p (the bound at rest; sliding lowers it)"
                        } else {
                            "mu p (the bound)"
                        },
                        s.clone(),
                        row.iter().map(|p| 1e-6 * self.mu * p.pressure).collect(),
                        SeriesStyle::Dashed,
                    ));
                }
                let pick = |sl: bool| -> (Vec<f64>, Vec<f64>) {
                    row.iter()
                        .filter(|p| p.pressure > 0.0 && p.sliding == sl)
                        .map(|p| (1e3 * p.s, 1e-6 * p.traction.hypot(p.lateral)))
                        .unzip()
                };
                let (ss, qs) = pick(true);
                let (sk, qk) = pick(false);
                patch
                    .series
                    .push(Series::new("|q|, sliding", ss, qs, SeriesStyle::Markers));
                patch
                    .series
                    .push(Series::new("|q|, sticking", sk, qk, SeriesStyle::Markers));
                patch.series.push(Series::new(
                    "q along the rolling direction",
                    s,
                    row.iter().map(|p| 1e-6 * p.traction).collect(),
                    SeriesStyle::Line,
                ));
            }
        }
        patch.note = format!(
            "Each node's force over its share of the rim (pitch x layer width; slice {} mm thick).{}",
            sig(1e3 * self.thickness, 3),
            if self.mu > 1.0 {
                format!(
                    " The bound mu p (mu = {}) is off the scale and not drawn.",
                    sig(self.mu, 3)
                )
            } else {
                String::new()
            }
        );
        vec![creep, normal, patch]
    }
}
