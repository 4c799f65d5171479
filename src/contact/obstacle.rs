//! Rigid obstacles as supporting half-spaces.
//!
//! At time `t` an obstacle presents, near a point `x`, the admissible half-space
//! `g(x) = n . x - c >= 0` with the unit normal `n` pointing into the admissible side
//! (away from the obstacle). `g` is the gap, m. The normal velocity of the obstacle's surface
//! at `x` is `w = dc/dt - dn/dt . x`: a node stays on the surface when `n . v = w`.
//!
//! Points and normals are [`Vector`]s of three components whatever the dimension of the
//! model: a 1D or 2D model leaves the trailing components zero, so the same obstacles, pairs
//! and contact rows serve 1D, 2D and (with a 3D element and mesh reader) 3D models.

use std::f64::consts::PI;

/// A point or direction, m (three components; unused trailing components are zero).
pub type Vector = [f64; 3];

/// `a . b`.
pub fn dot(a: Vector, b: Vector) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The admissible half-space `n . x - c >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpace {
    /// Unit normal into the admissible side.
    pub normal: Vector,
    /// Offset `c`, m.
    pub offset: f64,
}

impl HalfSpace {
    /// The gap `n . x - c` (negative: penetration), m.
    pub fn gap(&self, x: Vector) -> f64 {
        dot(self.normal, x) - self.offset
    }
}

/// A rigid obstacle whose surface may move in time.
pub trait Obstacle: Send + Sync + std::fmt::Debug {
    /// The supporting half-space at time `t` (s) near the point `x` (m).
    fn half_space(&self, t: f64, x: Vector) -> HalfSpace;

    /// Normal velocity of the surface at `x` and time `t`, m/s: `dc/dt - dn/dt . x`.
    /// The default differentiates [`Obstacle::half_space`] numerically.
    fn surface_normal_velocity(&self, t: f64, x: Vector) -> f64 {
        let dt = 1e-7 * (1.0 + t.abs()).min(1.0) * self.time_scale();
        let a = self.half_space(t - dt, x);
        let b = self.half_space(t + dt, x);
        let cdot = (b.offset - a.offset) / (2.0 * dt);
        let mut ndot = [0.0; 3];
        for c in 0..3 {
            ndot[c] = (b.normal[c] - a.normal[c]) / (2.0 * dt);
        }
        cdot - dot(ndot, x)
    }

    /// The half-space at time `t` when it is the same near every point (a plane, a wall, the
    /// rotating base: a straight boundary), so that the gaps of many nodes need it once
    /// ([`crate::contact::pair::gaps_into`]); `None` (the default) for a curved obstacle.
    fn uniform_half_space(&self, _t: f64) -> Option<HalfSpace> {
        None
    }

    /// A characteristic time of the obstacle's motion, s (for numerical differentiation).
    fn time_scale(&self) -> f64 {
        1.0
    }

    /// Tangential velocity of the surface's material points at `x` and time `t`, m/s,
    /// along the 2D tangent `t = (-n_y, n_x)` (the normal turned by +90 degrees; see
    /// [`tangent_2d`]). Friction acts on the slip `t . v - w_t`. The half-space alone does
    /// not show a sliding of the surface along itself, so the default is 0 (fixed planes and
    /// walls); an obstacle whose surface moves along itself overrides it
    /// ([`RotatingLine`]).
    fn surface_tangential_velocity(&self, _t: f64, _x: Vector) -> f64 {
        0.0
    }

    /// The velocity of the surface's material points at `x` and time `t` along the surface,
    /// m/s, as a vector (3D friction takes its part along each tangent). The default is the
    /// plane's [`Obstacle::surface_tangential_velocity`] along [`tangent_2d`] of the normal
    /// at `x`: 0 for fixed planes and walls.
    fn surface_velocity(&self, t: f64, x: Vector) -> Vector {
        let w = self.surface_tangential_velocity(t, x);
        if w == 0.0 {
            return [0.0; 3];
        }
        let tg = tangent_2d(self.half_space(t, x).normal);
        [w * tg[0], w * tg[1], w * tg[2]]
    }

    /// Seen from a frame turned by `angle` (rad, counter-clockwise) about the origin: the
    /// obstacle turns by `-angle` ([`crate::simulation::Relocation`]). Returns `false` for an
    /// obstacle that cannot (the default): only [`RotatingLine`] can.
    fn turn_frame(&mut self, _angle: f64) -> bool {
        false
    }
}

/// The 2D tangent of a unit normal: `n` turned by +90 degrees (counter-clockwise),
/// `t = (-n_y, n_x)`. For a floor (`n = (0, 1)`) it is `(-1, 0)`: a tangential force or
/// velocity reported along it is positive towards `-x`.
pub fn tangent_2d(n: Vector) -> Vector {
    [-n[1], n[0], 0.0]
}

/// A fixed plane (a wall in 1D: `normal = [-1, 0]` for a wall on the right of the body).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// The half-space.
    pub half_space: HalfSpace,
}

/// A fixed wall in 1D at `position` (m), the body on the side `side` (-1: the body is on
/// the left, `x <= position`; +1: on the right).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    /// Position of the wall, m.
    pub position: f64,
    /// Side of the admissible region: -1 (left of the wall) or +1 (right of it).
    pub side: f64,
}

impl Obstacle for Plane {
    fn half_space(&self, _t: f64, _x: Vector) -> HalfSpace {
        self.half_space
    }
    fn uniform_half_space(&self, _t: f64) -> Option<HalfSpace> {
        Some(self.half_space)
    }
    fn surface_normal_velocity(&self, _t: f64, _x: Vector) -> f64 {
        0.0
    }
}

impl Obstacle for Wall {
    fn half_space(&self, _t: f64, _x: Vector) -> HalfSpace {
        HalfSpace {
            normal: [self.side, 0.0, 0.0],
            offset: self.side * self.position,
        }
    }
    fn uniform_half_space(&self, t: f64) -> Option<HalfSpace> {
        Some(self.half_space(t, [0.0; 3]))
    }
    fn surface_normal_velocity(&self, _t: f64, _x: Vector) -> f64 {
        0.0
    }
}

/// The flattening program of the rolling wheel: `d(t)` rises from 0 to `depth` over
/// `[0, settle_time]` as `depth (1 - cos(pi t / settle_time)) / 2` (zero velocity at both
/// ends), then stays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flattening {
    /// Final flattening `d`, m.
    pub depth: f64,
    /// Duration of the settling ramp, s.
    pub settle_time: f64,
}

impl Flattening {
    /// `d(t)`, m.
    pub fn at(&self, t: f64) -> f64 {
        if self.settle_time <= 0.0 || t >= self.settle_time {
            self.depth
        } else if t <= 0.0 {
            0.0
        } else {
            self.depth * 0.5 * (1.0 - (PI * t / self.settle_time).cos())
        }
    }

    /// `d'(t)`, m/s.
    pub fn rate(&self, t: f64) -> f64 {
        if self.settle_time <= 0.0 || t >= self.settle_time || t <= 0.0 {
            0.0
        } else {
            self.depth * 0.5 * PI / self.settle_time * (PI * t / self.settle_time).sin()
        }
    }

    /// `d''(t)`, m/s^2 (0 outside the ramp; the ramp's ends are jumps of `d''`).
    pub fn accel(&self, t: f64) -> f64 {
        if self.settle_time <= 0.0 || t >= self.settle_time || t <= 0.0 {
            0.0
        } else {
            let w = PI / self.settle_time;
            self.depth * 0.5 * w * w * (w * t).cos()
        }
    }
}

/// The rigid base of the rolling wheel seen in the wheel's rotating frame: a straight line
/// at distance `radius - d(t)` from `centre`, turning about `centre` at `omega` rad/s
/// (counter-clockwise positive). At angle `theta = theta0 + omega t` the outward direction
/// from the centre to the base is `e = (sin theta, -cos theta)` (`theta = 0`: base below the
/// wheel), the admissible side is `e . (x - centre) <= radius - d(t)`.
///
/// **The base's material.** The line is the rail's surface, which in the laboratory
/// translates along itself under the axle at the speed `V = omega rho (1 - xi)`
/// (`rho = radius - d(t)` the rolling radius, `xi` the creepage). Seen in the wheel's frame,
/// which turns at `-omega` (the wheel spins clockwise so that the base turns at `+omega`),
/// its material point at `x` moves with `V t_b + omega e_z x (x - centre)`, `t_b` the unit
/// vector along the line in the direction of the rail's travel. At `xi = 0` the rail's
/// material under the axle is at rest in the wheel's frame: rolling without slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotatingLine {
    /// Centre of rotation (the wheel's axle), m.
    pub centre: Vector,
    /// Undeformed radius `R`, m.
    pub radius: f64,
    /// Angular speed of the base in the wheel's frame, rad/s.
    pub omega: f64,
    /// Initial angle, rad.
    pub theta0: f64,
    /// Flattening program.
    pub flattening: Flattening,
    /// Longitudinal creepage `xi = (omega rho - V) / (omega rho)`, dimensionless: the
    /// rim's rolling speed `omega rho` against the rail's speed `V` under the axle. `xi > 0`:
    /// the rim runs faster than the rail (a driven wheel, traction forward on the wheel);
    /// `xi < 0`: braked; 0: free rolling.
    pub creepage: f64,
}

impl RotatingLine {
    /// Angle of the base at time `t`, rad.
    pub fn angle(&self, t: f64) -> f64 {
        self.theta0 + self.omega * t
    }

    /// Unit vector from the centre towards the base at time `t`.
    pub fn direction(&self, t: f64) -> Vector {
        let th = self.angle(t);
        [th.sin(), -th.cos(), 0.0]
    }
}

impl Obstacle for RotatingLine {
    fn half_space(&self, t: f64, _x: Vector) -> HalfSpace {
        let e = self.direction(t);
        let rho = self.radius - self.flattening.at(t);
        HalfSpace {
            normal: [-e[0], -e[1], 0.0],
            offset: -rho - e[0] * self.centre[0] - e[1] * self.centre[1],
        }
    }

    fn uniform_half_space(&self, t: f64) -> Option<HalfSpace> {
        Some(self.half_space(t, [0.0; 3]))
    }

    fn surface_normal_velocity(&self, t: f64, x: Vector) -> f64 {
        // w = -rho' + e' . (x - centre), e' = omega (cos th, sin th).
        let th = self.angle(t);
        let ed = [self.omega * th.cos(), self.omega * th.sin()];
        self.flattening.rate(t) + ed[0] * (x[0] - self.centre[0]) + ed[1] * (x[1] - self.centre[1])
    }

    /// The rail's material velocity (type docs) along the tangent `t = (-n_y, n_x)`. With
    /// `n = -e`, `t = (-cos th, -sin th)`, which is the direction of the rail's travel
    /// (at `th = 0`, below the wheel, the base turns towards `+x` in the wheel's frame, so the
    /// rail travels towards `-x` in the axle's frame). The rotation field contributes
    /// `t . (omega e_z x (x - centre)) = -omega e . (x - centre)`, the translation
    /// `V = omega rho (1 - xi)`:
    /// `w_t = omega rho (1 - xi) - omega e . (x - centre)`,
    /// which on the base (`e . (x - centre) = rho`) is `-xi omega rho`: zero in free rolling.
    fn turn_frame(&mut self, angle: f64) -> bool {
        if self.centre[0] != 0.0 || self.centre[1] != 0.0 {
            return false;
        }
        self.theta0 -= angle;
        true
    }

    fn surface_tangential_velocity(&self, t: f64, x: Vector) -> f64 {
        let e = self.direction(t);
        let rho = self.radius - self.flattening.at(t);
        self.omega * rho * (1.0 - self.creepage)
            - self.omega * (e[0] * (x[0] - self.centre[0]) + e[1] * (x[1] - self.centre[1]))
    }
}

/// The rotating base in 3D: [`RotatingLine`]'s plane, the wheel's axle along `z` (the
/// plane contains it), whose material also slides across the rolling direction and turns
/// about the normal: the longitudinal, lateral and spin creepages of a 3D wheel rolling in
/// its own frame (the paper's rotating frame, §4, with the base's material moving through
/// it).
///
/// With `V = omega rho` the rim's rolling speed, `e` the unit vector from the axle to the
/// base ([`RotatingLine::direction`]), `n = -e` the base's outward normal, `t_b` the
/// direction of the base's travel (`tangent_2d(n)`) and `p0 = centre + rho e` the point of
/// the base under the axle, a point of the wheel at rest in the frame at `x` slides on the
/// base's material at
/// `s(x) = V (xi t_b + eta e_z + phi n x (x - p0))`
/// (`xi` [`RotatingLine::creepage`], `eta` [`RotatingBase::lateral`], `phi`
/// [`RotatingBase::spin`]): the base's material moves at `w = -s` there
/// ([`Obstacle::surface_velocity`]). With `eta = phi = 0` it is [`RotatingLine`] extended
/// along the axle.
///
/// **A crowned base.** With [`RotatingBase::crown`] `= Some(R_c)` the base is not a plane
/// but a cylinder of radius `R_c` along `t_b`, its crest the plane's line under the axle at
/// the height `centre[2]` along the axle (a rail head's crown under a cylindrical wheel:
/// the contact patch is Hertz's ellipse). Its axis passes through `a = p0 + R_c e`; at a
/// point `x`, with `r` the part of `x - a` across `t_b`, the gap is `|r| - R_c` and the
/// normal `r / |r|`. The cylinder turns about the axle with the plane and its material
/// moves as the plane's does: the rail's translation `omega rho (1 - xi)` along `t_b`, the
/// frame's rotation `omega e_z x (x - centre)` and the lateral and spin terms, of which the
/// friction takes the part along the local tangents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotatingBase {
    /// The plane, its turning, flattening and longitudinal creepage `xi`.
    pub line: RotatingLine,
    /// Lateral creepage `eta`, dimensionless: the wheel's rigid slip along `+z` over `V`.
    pub lateral: f64,
    /// Spin creepage `phi`, 1/m: the wheel's rigid turning about the base's outward normal
    /// relative to the base, over `V`.
    pub spin: f64,
    /// The crown's radius across the rolling direction, m (`None`: a plane; type docs).
    pub crown: Option<f64>,
}

/// The 3D base's frame at an instant ([`RotatingBase::frame`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaseFrame {
    /// The point of the base under the axle, `p0 = centre + rho e`, m.
    pub p0: Vector,
    /// The base's outward normal `n = -e` (toward the axle).
    pub normal: Vector,
    /// The direction of the base's travel `t_b` (`tangent_2d(n)`); the wheel rolls over
    /// the base along `-t_b`.
    pub travel: Vector,
    /// The axle's height over the base, `rho = radius - flattening`, m.
    pub rho: f64,
}

impl RotatingBase {
    /// The base's point under the axle, its normal and its direction of travel at `t`
    /// (the type's docs).
    pub fn frame(&self, t: f64) -> BaseFrame {
        let l = &self.line;
        let e = l.direction(t);
        let rho = l.radius - l.flattening.at(t);
        let normal = [-e[0], -e[1], 0.0];
        BaseFrame {
            p0: [
                l.centre[0] + rho * e[0],
                l.centre[1] + rho * e[1],
                l.centre[2],
            ],
            normal,
            travel: tangent_2d(normal),
            rho,
        }
    }
}

impl RotatingBase {
    /// The crowned base's outward normal at `x` and the gap there (type docs), at `t`.
    fn crowned(&self, t: f64, x: Vector, rc: f64) -> (Vector, f64) {
        let f = self.frame(t);
        let e = [-f.normal[0], -f.normal[1], 0.0];
        let a = [f.p0[0] + rc * e[0], f.p0[1] + rc * e[1], f.p0[2]];
        let d = [x[0] - a[0], x[1] - a[1], x[2] - a[2]];
        let along = dot(d, f.travel);
        let r = [
            d[0] - along * f.travel[0],
            d[1] - along * f.travel[1],
            d[2] - along * f.travel[2],
        ];
        let len = dot(r, r).sqrt();
        if len > 0.0 {
            ([r[0] / len, r[1] / len, r[2] / len], len - rc)
        } else {
            (f.normal, -rc)
        }
    }
}

impl Obstacle for RotatingBase {
    fn half_space(&self, t: f64, x: Vector) -> HalfSpace {
        match self.crown {
            None => self.line.half_space(t, x),
            Some(rc) => {
                let (normal, gap) = self.crowned(t, x, rc);
                HalfSpace {
                    normal,
                    offset: dot(normal, x) - gap,
                }
            }
        }
    }

    fn uniform_half_space(&self, t: f64) -> Option<HalfSpace> {
        match self.crown {
            None => self.line.uniform_half_space(t),
            Some(_) => None,
        }
    }

    fn surface_normal_velocity(&self, t: f64, x: Vector) -> f64 {
        match self.crown {
            None => self.line.surface_normal_velocity(t, x),
            Some(rc) => {
                // The surface turns about the axle at omega and comes towards it at the
                // flattening's rate: v = omega e_z x (x - centre) - d' e.
                let (n, _) = self.crowned(t, x, rc);
                let l = &self.line;
                let e = l.direction(t);
                let (rx, ry) = (x[0] - l.centre[0], x[1] - l.centre[1]);
                let d_rate = l.flattening.rate(t);
                let v = [
                    -l.omega * ry - d_rate * e[0],
                    l.omega * rx - d_rate * e[1],
                    0.0,
                ];
                dot(n, v)
            }
        }
    }

    fn turn_frame(&mut self, angle: f64) -> bool {
        self.line.turn_frame(angle)
    }

    fn time_scale(&self) -> f64 {
        self.line.time_scale()
    }

    fn surface_tangential_velocity(&self, t: f64, x: Vector) -> f64 {
        self.line.surface_tangential_velocity(t, x)
    }

    fn surface_velocity(&self, t: f64, x: Vector) -> Vector {
        let f = self.frame(t);
        let (n, tb) = (f.normal, f.travel);
        let v = self.line.omega * f.rho;
        let r = [x[0] - f.p0[0], x[1] - f.p0[1], x[2] - f.p0[2]];
        // n x r, n in the plane of the wheel.
        let nr = [n[1] * r[2], -n[0] * r[2], n[0] * r[1] - n[1] * r[0]];
        let (eta, phi) = (self.lateral, self.spin);
        // The rail's translation and the frame's rotation: on a plane only the part along
        // t_b is tangential; on a crown the rotation's part along the plane's normal has a
        // share along the crown's local tangent too (type docs).
        let carried = match self.crown {
            None => {
                let w_t = self.line.surface_tangential_velocity(t, x);
                [w_t * tb[0], w_t * tb[1], 0.0]
            }
            Some(_) => {
                let l = &self.line;
                let u = v * (1.0 - l.creepage);
                let (rx, ry) = (x[0] - l.centre[0], x[1] - l.centre[1]);
                [u * tb[0] - l.omega * ry, u * tb[1] + l.omega * rx, 0.0]
            }
        };
        [
            carried[0] - v * phi * nr[0],
            carried[1] - v * phi * nr[1],
            -v * eta - v * phi * nr[2],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 3D base's material velocity: with no lateral or spin creepage it is the line's
    /// along its tangent; the rigid slip of a point of the wheel at rest, `-w`, is
    /// `V (xi t_b + eta e_z + phi n x (x - p0))`, in the base's plane, whatever the
    /// point's height along the axle.
    #[test]
    fn the_3d_base_slides_by_the_three_creepages() {
        let mut line = settling_base();
        line.creepage = 0.004;
        let t = 1.3e-3;
        let e = line.direction(t);
        let rho = line.radius - line.flattening.at(t);
        let v = line.omega * rho;
        let n = [-e[0], -e[1], 0.0];
        let tb = tangent_2d(n);
        let p0 = [
            line.centre[0] + rho * e[0],
            line.centre[1] + rho * e[1],
            0.0,
        ];
        let plain = RotatingBase {
            line,
            lateral: 0.0,
            spin: 0.0,
            crown: None,
        };
        let base = RotatingBase {
            line,
            lateral: -0.003,
            spin: 0.7,
            crown: None,
        };
        for (along, lateral) in [(0.0, 0.0), (2e-3, -1e-3), (-1.5e-3, 4e-3)] {
            // A point on the base: `along` t_b from p0, `lateral` along z.
            let x = [p0[0] + along * tb[0], p0[1] + along * tb[1], lateral];
            let w0 = plain.surface_velocity(t, x);
            let w1 = line.surface_tangential_velocity(t, x);
            for c in 0..3 {
                assert!((w0[c] - w1 * tb[c]).abs() < 1e-12, "{w0:?} {w1}");
            }
            let w = base.surface_velocity(t, x);
            assert!(dot(w, n).abs() < 1e-12, "{w:?} not in the plane");
            let s = [-w[0], -w[1], -w[2]];
            // n x (x - p0) = along (n x t_b) + lateral (n x e_z); n x t_b = e_z x ... by hand:
            let r = [x[0] - p0[0], x[1] - p0[1], x[2] - p0[2]];
            let nr = [
                n[1] * r[2] - n[2] * r[1],
                n[2] * r[0] - n[0] * r[2],
                n[0] * r[1] - n[1] * r[0],
            ];
            for c in 0..3 {
                let ez = [0.0, 0.0, 1.0][c];
                let want = v * (0.004 * tb[c] - 0.003 * ez + 0.7 * nr[c]);
                assert!((s[c] - want).abs() < 1e-12 * v, "{c}: {s:?}");
            }
        }
    }

    /// The crowned base: on its crest line it is the plane (gap and normal); a point `g`
    /// above the plane and `dz` off the crest is `sqrt((R_c + g)^2 + dz^2) - R_c` above the
    /// crown, whose normal there leans by `atan(dz / (R_c + g))` along the axle; the surface's
    /// normal velocity is the numerical derivative of its half-space; its material's
    /// velocity is the plane's along `t_b` and the rail's translation and the frame's
    /// rotation projected on the local tangents.
    #[test]
    fn the_crowned_base_is_a_cylinder_along_the_travel() {
        let line = RotatingLine {
            centre: [0.0, 0.0, 0.005],
            ..settling_base()
        };
        let rc = 0.08;
        let plane = RotatingBase {
            line,
            lateral: 0.0,
            spin: 0.0,
            crown: None,
        };
        let crown = RotatingBase {
            crown: Some(rc),
            ..plane
        };
        assert!(crown.uniform_half_space(0.0).is_none());
        #[derive(Debug)]
        struct Numeric(RotatingBase);
        impl Obstacle for Numeric {
            fn half_space(&self, t: f64, x: Vector) -> HalfSpace {
                self.0.half_space(t, x)
            }
            fn time_scale(&self) -> f64 {
                1e-3
            }
        }
        for t in [0.0007, 0.0025] {
            let f = plane.frame(t);
            let on = |along: f64, dz: f64, up: f64| -> Vector {
                std::array::from_fn(|c| {
                    f.p0[c] + along * f.travel[c] + dz * [0.0, 0.0, 1.0][c] + up * f.normal[c]
                })
            };
            for (along, dz) in [(0.0, 0.0), (1.5e-3, 0.0), (-2e-3, 3e-3), (1e-3, -4e-3)] {
                let x = on(along, dz, 1e-5);
                let (hp, hc) = (plane.half_space(t, x), crown.half_space(t, x));
                // 1e-5 above the plane, the plane's gap.
                let up = hp.gap(x);
                assert!((up - 1e-5).abs() < 1e-12, "{up}");
                let rr = ((rc + up).powi(2) + dz * dz).sqrt();
                assert!((hc.gap(x) - (rr - rc)).abs() < 1e-12, "{} {rr}", hc.gap(x));
                let lean = dot(hc.normal, [0.0, 0.0, 1.0]);
                assert!((lean - dz / rr).abs() < 1e-12, "{lean}");
                if dz == 0.0 {
                    for c in 0..3 {
                        assert!((hc.normal[c] - hp.normal[c]).abs() < 1e-12);
                    }
                }
                let a = crown.surface_normal_velocity(t, x);
                let b = Numeric(crown).surface_normal_velocity(t, x);
                assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "{t}: {a} vs {b}");
                // The material's velocity along t_b is the plane's; across, on the crest,
                // nothing.
                let (wp, wc) = (plane.surface_velocity(t, x), crown.surface_velocity(t, x));
                assert!(
                    (dot(wp, f.travel) - dot(wc, f.travel)).abs() < 1e-9,
                    "{wp:?} {wc:?}"
                );
                let [_, t2] = crate::contact::pair::tangent_basis(3, hc.normal);
                if dz == 0.0 {
                    assert!(dot(wc, t2).abs() < 1e-9, "{wc:?}");
                }
            }
        }
    }

    /// A base turning at 300 rad/s about an off-origin centre, still settling.
    fn settling_base() -> RotatingLine {
        RotatingLine {
            centre: [0.01, -0.02, 0.0],
            radius: 0.1,
            omega: 300.0,
            theta0: 0.3,
            flattening: Flattening {
                depth: 1e-3,
                settle_time: 2e-3,
            },
            creepage: 0.0,
        }
    }

    #[test]
    fn rotating_line_rate_matches_numerical_derivative() {
        let line = settling_base();
        #[derive(Debug)]
        struct Numeric(RotatingLine);
        impl Obstacle for Numeric {
            fn half_space(&self, t: f64, x: Vector) -> HalfSpace {
                self.0.half_space(t, x)
            }
            fn time_scale(&self) -> f64 {
                1e-3
            }
        }
        let x = [0.03, -0.09, 0.0];
        for t in [0.0005, 0.0011, 0.003] {
            let a = line.surface_normal_velocity(t, x);
            let b = Numeric(line).surface_normal_velocity(t, x);
            assert!((a - b).abs() < 1e-6 * (1.0 + a.abs()), "{a} vs {b}");
        }
    }

    /// The tangential velocity of the base is the rail's: in the axle's (non-rotating)
    /// frame the rail translates at `V = omega rho (1 - xi)` along itself; transformed into
    /// the wheel's frame (turning at `-omega`) by `v_w = R(omega t) (v_lab - (-omega) e_z x
    /// r_lab)`, computed here in the laboratory and rotated, independently of the method.
    #[test]
    fn rotating_line_tangential_velocity_is_the_rails() {
        for xi in [0.0, 0.01, -0.003] {
            let line = RotatingLine {
                creepage: xi,
                ..settling_base()
            };
            for t in [0.0005, 0.003] {
                let th = line.angle(t);
                let rho = line.radius - line.flattening.at(t);
                // A point of the wheel's frame, seen in the lab: rotate by -th (the frame
                // has turned by -th since t = 0 relative to the lab, where the base is fixed
                // below the axle).
                let x = [0.03, -0.09, 0.0];
                let r = [x[0] - line.centre[0], x[1] - line.centre[1]];
                let (s, c) = (-th).sin_cos();
                let r_lab = [c * r[0] - s * r[1], s * r[0] + c * r[1]];
                // Lab: the rail below the axle travels towards -x at V; the frame spins at
                // -omega, so a point fixed in the lab moves in the frame with +omega e_z x r.
                let v = rho * line.omega * (1.0 - xi);
                let v_lab_rel = [-v + line.omega * -r_lab[1], line.omega * r_lab[0]];
                // Back to the wheel's frame (rotate by +th).
                let (s, c) = th.sin_cos();
                let v_w = [
                    c * v_lab_rel[0] - s * v_lab_rel[1],
                    s * v_lab_rel[0] + c * v_lab_rel[1],
                    0.0,
                ];
                let tg = tangent_2d(line.half_space(t, x).normal);
                let expect = dot(tg, v_w);
                let got = line.surface_tangential_velocity(t, x);
                assert!(
                    (got - expect).abs() < 1e-12 * (1.0 + expect.abs()),
                    "xi {xi} t {t}: {got} vs {expect}"
                );
                // On the base itself: -xi omega rho (free rolling: no slip).
                let e = line.direction(t);
                let on = [
                    line.centre[0] + rho * e[0] + 0.004 * e[1],
                    line.centre[1] + rho * e[1] - 0.004 * e[0],
                    0.0,
                ];
                let w = line.surface_tangential_velocity(t, on);
                assert!((w + xi * line.omega * rho).abs() < 1e-12, "{w}");
            }
        }
    }

    #[test]
    fn base_below_the_wheel_at_angle_zero() {
        let line = RotatingLine {
            centre: [0.0; 3],
            radius: 0.1,
            omega: 1.0,
            theta0: 0.0,
            flattening: Flattening {
                depth: 0.001,
                settle_time: 0.0,
            },
            creepage: 0.0,
        };
        let hs = line.half_space(0.0, [0.0; 3]);
        assert!((hs.gap([0.0, -0.099, 0.0]) - 0.0).abs() < 1e-15);
        assert!(hs.gap([0.0; 3]) > 0.0);
        assert!(hs.gap([0.0, -0.1, 0.0]) < 0.0);
    }
}
