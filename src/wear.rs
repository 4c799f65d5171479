//! Wear laws: the depth a contact point loses per second from its normal force, its
//! tangential (friction) force and its slip speed, over the area it stands for.
//!
//! Every law here turns one [`ContactSample`] (a node's force over its tributary area, its
//! slip speed, the rolling speed) into a rate of worn depth, m/s
//! ([`WearLaw::depth_rate`]); the pass driver ([`crate::growth`]) sums it over the steps of a
//! pass. The slip speed of a node is its frictional power over its friction force,
//! `v_s = P_slip / |T|` ([`crate::model::PairState::slip_power`]); a node in stick has
//! `v_s = 0` and wears nothing under any of these laws.
//!
//! **Archard** ([`Archard`]): the worn volume `dV = k N ds / H` (`k` dimensionless, `N` the
//! normal force, `ds` the sliding distance, `H` the hardness, Pa; J. F. Archard, J. Appl.
//! Phys. 24 (1953) 981). Per unit area and time: `dz/dt = k p v_s / H` with `p = N / A`.
//! With a **Jendel wear map** ([`JendelMap`]) `k` depends on the contact pressure and the
//! sliding speed, in four regions (T. Jendel, "Prediction of wheel profile wear -
//! comparisons with field measurements", Wear 253 (2002) 89-99, Fig. 3, after Olofsson and
//! Telliskivi's map for R7/UIC60 steels): `p > 0.8 H`: `k1 = 300-400 e-4` (seizure);
//! otherwise `v_s <= 0.2 m/s`: `k2 = 1-10 e-4` (mild), `0.2 < v_s <= 0.7 m/s`:
//! `k3 = 30-40 e-4` (severe), `v_s > 0.7 m/s`: `k4 = 1-10 e-4` (mild). The defaults
//! ([`JendelMap::DRY`]) are the middles of those ranges: 350e-4, 5.5e-4, 35e-4, 5.5e-4.
//! Those ranges are as the map is quoted in the wheel-wear literature that follows
//! Jendel; the primary paper was not at hand to check them: set your own with `wear.k1` ..
//! `wear.k4`.
//!
//! **Frictional power, linear** ([`FrictionalPower`]): the worn mass per unit area is
//! proportional to the frictional work per unit area, `dm/dt = k_f T v_s / A`, depth rate
//! `dm/dt / rho` (the energy form of the `T gamma` index, as in J. C. O. Nielsen, "Numerical
//! prediction of rail roughness growth on tangent railway tracks", J. Sound Vib. 267 (2003)
//! 537-548, where the wear is proportional to the frictional power density). `k_f` in kg/J;
//! the default 5.3e-9 kg/J is the slope of the USFD law's mild regime below (5.3
//! ug/(m mm^2) per N/mm^2 = 5.3e-9 kg/(N m)), so the two laws agree in that regime.
//!
//! **USFD** ([`Usfd`], University of Sheffield; R. Lewis and R. S. Dwyer-Joyce, Proc. IMechE
//! J 218 (2004) 467-478; as used by F. Braghin, R. Lewis, R. S. Dwyer-Joyce and S. Bruni,
//! "A mathematical model to predict railway wheel profile evolution due to wear", Wear 261
//! (2006) 1253-1264, for R8T wheel steel against UIC60 900A rail): the wear rate `W` in
//! ug of material per metre rolled per mm^2 of contact, against the wear index per area
//! `x = T gamma / A` in N/mm^2 (`gamma = v_s / V` the slip over the rolling speed):
//! ```text
//! W = 5.3 x              x < 10.4      (K1, mild)
//! W = 55.0               10.4 <= x <= 77.2  (K2, severe: constant, not 55 x)
//! W = 61.9 x - 4778.7    x > 77.2      (K3, catastrophic)
//! ```
//! The severe regime is a constant (5.3 x 10.4 = 55.1: continuous with the mild line);
//! writing it `55 x`, or the catastrophic one `61.9 x` without its offset, is the slip some
//! public implementations carry (they give 10 to 60 times too much wear there). The
//! published catastrophic line starts from about zero at 77.2 (61.9 x 77.2 - 4778.7 =
//! -0.02): the published fit, kept as published and floored at 0, with the drop from 55 at
//! the boundary left as in the source (it is above any slip this solver's wheel sees:
//! `tests`). These coefficients are as the wheel-wear literature quotes them; the search
//! tools of this work did not reach the papers' tables, so check them against your copy.
//! Depth rate: `W 1e-3 V / rho` m/s (`W` ug/(m mm^2) = 1e-3 kg/m^3, times the metres rolled
//! per second, over the density).

use serde::{Deserialize, Serialize};

/// What a wear law reads at one contact point in one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSample {
    /// Normal force, N (>= 0).
    pub normal_force: f64,
    /// Magnitude of the tangential (friction) force, N.
    pub tangential_force: f64,
    /// Slip speed, m/s (>= 0): the frictional power over the friction force.
    pub slip_speed: f64,
    /// The area the point stands for, m^2 (its tributary length times the thickness).
    pub area: f64,
    /// Rolling speed, m/s (> 0): the USFD law's metres rolled.
    pub rolling_speed: f64,
}

/// Archard's law with a constant coefficient or a Jendel map (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Archard {
    /// Dimensionless wear coefficient (used without a map).
    pub k: f64,
    /// Hardness of the worn surface, Pa.
    pub hardness: f64,
    /// `k` by pressure and sliding speed instead of the constant `k`.
    pub map: Option<JendelMap>,
}

/// Jendel's wear map (module docs): four dimensionless coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JendelMap {
    /// `p > 0.8 H` (seizure).
    pub k1: f64,
    /// `v_s <= 0.2 m/s` (mild).
    pub k2: f64,
    /// `0.2 < v_s <= 0.7 m/s` (severe).
    pub k3: f64,
    /// `v_s > 0.7 m/s` (mild).
    pub k4: f64,
}

impl JendelMap {
    /// The middles of Jendel's dry ranges (module docs).
    pub const DRY: Self = Self {
        k1: 350e-4,
        k2: 5.5e-4,
        k3: 35e-4,
        k4: 5.5e-4,
    };
    /// Pressure boundary of the seizure region, times the hardness.
    pub const SEIZURE_PRESSURE: f64 = 0.8;
    /// Sliding-speed boundaries, m/s.
    pub const SPEEDS: (f64, f64) = (0.2, 0.7);

    /// The coefficient at pressure `p` (Pa), hardness `h` (Pa) and sliding speed `v` (m/s).
    pub fn k(&self, p: f64, h: f64, v: f64) -> f64 {
        if p > Self::SEIZURE_PRESSURE * h {
            self.k1
        } else if v <= Self::SPEEDS.0 {
            self.k2
        } else if v <= Self::SPEEDS.1 {
            self.k3
        } else {
            self.k4
        }
    }
}

/// The linear frictional-power law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrictionalPower {
    /// Worn mass per frictional energy, kg/J.
    pub k_mass: f64,
}

impl FrictionalPower {
    /// The default coefficient, kg/J (the USFD mild slope, module docs).
    pub const DEFAULT_K_MASS: f64 = 5.3e-9;
}

/// The USFD three-regime law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Usfd {
    /// Mild slope, ug/(m mm^2) per N/mm^2.
    pub k1: f64,
    /// Mild/severe boundary, N/mm^2.
    pub x1: f64,
    /// Severe rate, ug/(m mm^2).
    pub k2: f64,
    /// Severe/catastrophic boundary, N/mm^2.
    pub x2: f64,
    /// Catastrophic slope, ug/(m mm^2) per N/mm^2.
    pub k3: f64,
    /// Catastrophic offset, ug/(m mm^2) (subtracted).
    pub c3: f64,
}

impl Usfd {
    /// R8T wheel steel against UIC60 900A (Braghin et al. 2006; module docs).
    pub const R8T: Self = Self {
        k1: 5.3,
        x1: 10.4,
        k2: 55.0,
        x2: 77.2,
        k3: 61.9,
        c3: 4778.7,
    };

    /// The wear rate `W(x)`, ug/(m mm^2), at the wear index per area `x = T gamma / A`,
    /// N/mm^2 (floored at 0).
    pub fn rate(&self, x: f64) -> f64 {
        let w = if x < self.x1 {
            self.k1 * x
        } else if x <= self.x2 {
            self.k2
        } else {
            self.k3 * x - self.c3
        };
        w.max(0.0)
    }
}

/// A wear law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "law")]
pub enum WearLaw {
    /// `dV = k N ds / H`.
    Archard(Archard),
    /// Worn mass proportional to the frictional work.
    FrictionalPower(FrictionalPower),
    /// USFD's three regimes of `T gamma / A`.
    Usfd(Usfd),
}

impl WearLaw {
    /// Checks the coefficients: a one-line error naming the coefficient and what is
    /// allowed.
    ///
    /// # Errors
    /// The message.
    pub fn check(&self) -> Result<(), String> {
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("wear.{name} = {v}: must be finite and > 0"))
            }
        };
        let nonneg = |name: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(format!("wear.{name} = {v}: must be finite and >= 0"))
            }
        };
        match self {
            WearLaw::Archard(a) => {
                pos("hardness", a.hardness)?;
                match &a.map {
                    None => nonneg("k", a.k),
                    Some(m) => {
                        nonneg("k1", m.k1)?;
                        nonneg("k2", m.k2)?;
                        nonneg("k3", m.k3)?;
                        nonneg("k4", m.k4)
                    }
                }
            }
            WearLaw::FrictionalPower(f) => nonneg("k_mass", f.k_mass),
            WearLaw::Usfd(u) => {
                nonneg("k1", u.k1)?;
                pos("x1", u.x1)?;
                nonneg("k2", u.k2)?;
                if !(u.x2.is_finite() && u.x2 > u.x1) {
                    return Err(format!(
                        "wear.x2 = {}: must be finite and above wear.x1 = {}",
                        u.x2, u.x1
                    ));
                }
                nonneg("k3", u.k3)?;
                if u.c3.is_finite() {
                    Ok(())
                } else {
                    Err(format!("wear.c3 = {}: must be finite", u.c3))
                }
            }
        }
    }

    /// Rate of worn depth at the sample, m/s (>= 0), for a material of density `density`
    /// (kg/m^3; the mass-based laws).
    pub fn depth_rate(&self, s: &ContactSample, density: f64) -> f64 {
        if s.area <= 0.0 || s.slip_speed <= 0.0 || s.normal_force <= 0.0 {
            return 0.0;
        }
        match self {
            WearLaw::Archard(a) => {
                let p = s.normal_force / s.area;
                let k = match &a.map {
                    None => a.k,
                    Some(m) => m.k(p, a.hardness, s.slip_speed),
                };
                k * p * s.slip_speed / a.hardness
            }
            WearLaw::FrictionalPower(f) => {
                f.k_mass * s.tangential_force.abs() * s.slip_speed / s.area / density
            }
            WearLaw::Usfd(u) => {
                if s.rolling_speed <= 0.0 {
                    return 0.0;
                }
                let t_gamma = s.tangential_force.abs() * s.slip_speed / s.rolling_speed;
                // N per m^2 -> N per mm^2.
                let x = t_gamma / s.area * 1e-6;
                u.rate(x) * 1e-3 * s.rolling_speed / density
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block of area `a` under `n` sliding at `v` for `steps` steps of `h`: the worn
    /// volume is `k N s / H` (s = v steps h) to 1e-6.
    #[test]
    fn archard_block_loses_k_n_s_over_h() {
        let (k, hard, n, v, a, h, steps) = (2.5e-4, 2.6e9, 1.3e4, 0.37, 4e-5, 1e-4, 12_345);
        let law = WearLaw::Archard(Archard {
            k,
            hardness: hard,
            map: None,
        });
        law.check().unwrap();
        let s = ContactSample {
            normal_force: n,
            tangential_force: 0.3 * n,
            slip_speed: v,
            area: a,
            rolling_speed: 10.0,
        };
        let depth: f64 = (0..steps).map(|_| law.depth_rate(&s, 7800.0) * h).sum();
        let volume = depth * a;
        let exact = k * n * (v * h * steps as f64) / hard;
        assert!(
            (volume / exact - 1.0).abs() < 1e-6,
            "{volume:e} against {exact:e}"
        );
    }

    /// The Jendel map picks its region by pressure and sliding speed.
    #[test]
    fn jendel_regions() {
        let m = JendelMap::DRY;
        let h = 3e9;
        assert_eq!(m.k(0.81 * h, h, 0.1), m.k1);
        assert_eq!(m.k(0.5 * h, h, 0.1), m.k2);
        assert_eq!(m.k(0.5 * h, h, 0.5), m.k3);
        assert_eq!(m.k(0.5 * h, h, 1.0), m.k4);
    }

    /// The frictional-power laws: the worn depth of a varying history equals the integral
    /// of their rate of `T gamma / A`, the USFD law's piecewise pieces included.
    #[test]
    fn frictional_power_depth_is_the_integral_of_t_gamma() {
        let rho = 7850.0;
        let (a, vroll, h) = (2e-5, 30.0, 1e-6);
        // T gamma / A sweeps 0 .. 150 N/mm^2 through the three USFD regimes.
        let steps = 30_000;
        let sample = |i: usize| {
            let x = 150.0 * i as f64 / steps as f64; // N/mm^2
            let t = 1e4; // N
            let v = x * 1e6 * a * vroll / t; // slip speed giving that T gamma / A
            (
                x,
                ContactSample {
                    normal_force: 4e4,
                    tangential_force: -t,
                    slip_speed: v,
                    area: a,
                    rolling_speed: vroll,
                },
            )
        };
        let fp = WearLaw::FrictionalPower(FrictionalPower { k_mass: 5.3e-9 });
        let us = WearLaw::Usfd(Usfd::R8T);
        let (mut d_fp, mut d_us) = (0.0, 0.0);
        let (mut work, mut usfd_mass) = (0.0, 0.0);
        for i in 0..steps {
            let (x, s) = sample(i);
            d_fp += fp.depth_rate(&s, rho) * h;
            d_us += us.depth_rate(&s, rho) * h;
            // Independent sums: the frictional work per area, and the USFD mass per area
            // (W ug/(m mm^2) over V h metres = W V h 1e-3 kg/m^2) from the published law.
            work += s.tangential_force.abs() * s.slip_speed / a * h;
            let w = if x < 10.4 {
                5.3 * x
            } else if x <= 77.2 {
                55.0
            } else {
                (61.9 * x - 4778.7).max(0.0)
            };
            usfd_mass += w * vroll * h * 1e-3;
        }
        let exact_fp = 5.3e-9 * work / rho;
        assert!(
            (d_fp / exact_fp - 1.0).abs() < 1e-9,
            "{d_fp:e} {exact_fp:e}"
        );
        let exact_us = usfd_mass / rho;
        assert!(
            (d_us / exact_us - 1.0).abs() < 1e-9,
            "{d_us:e} {exact_us:e}"
        );
        // In the mild regime the linear law and USFD agree (same slope).
        let (_, s) = sample(steps / 30); // x = 5 N/mm^2
        let (a1, b1) = (fp.depth_rate(&s, rho), us.depth_rate(&s, rho));
        assert!((a1 / b1 - 1.0).abs() < 1e-12, "{a1:e} {b1:e}");
    }

    /// The USFD law: continuous at the mild/severe boundary, constant across the severe
    /// regime.
    #[test]
    fn usfd_regimes() {
        let u = Usfd::R8T;
        assert!((u.rate(10.4 - 1e-9) - u.rate(10.4)).abs() < 0.2);
        assert_eq!(u.rate(20.0), u.rate(70.0));
        assert!((u.rate(100.0) - (6190.0 - 4778.7)).abs() < 1e-9);
    }

    /// Bad coefficients: a one-line error naming the key.
    #[test]
    fn check_names_the_key() {
        let e = WearLaw::Archard(Archard {
            k: 1e-4,
            hardness: 0.0,
            map: None,
        })
        .check()
        .unwrap_err();
        assert!(e.contains("wear.hardness"), "{e}");
        let mut u = Usfd::R8T;
        u.x2 = 5.0;
        assert!(WearLaw::Usfd(u).check().unwrap_err().contains("wear.x2"));
    }
}
