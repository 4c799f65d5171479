//! Johnson's rolling shakedown: the Hertz pressure of a cylinder moved repeatedly over a
//! plane-strain elastic-perfectly-plastic half-space, quasi-statically, frictionless
//! (Johnson 1962; Merwin & Johnson 1963; Bower & Johnson 1989).
//!
//! # The load
//!
//! The cylinder's pressure $p(x) = p_0\sqrt{1 - ((x - x_c)/a)^2}$ on $|x - x_c| \le a$, its
//! total $P = \tfrac\pi2 p_0 a$ per unit length. Its consistent nodal loads on the top
//! edges ($f_i = -\int N_i\, p\, dx$, vertical) are integrated in closed form with
//! $s = (x - x_c)/a$: $\int\sqrt{1-s^2}\,ds = \tfrac12(s\sqrt{1-s^2} + \arcsin s)$ and
//! $\int s\sqrt{1-s^2}\,ds = -\tfrac13(1-s^2)^{3/2}$, so the square-root edge is exact
//! ([`hertz_loads_into`]).
//!
//! # The exact elastic field (McEwen 1949; Johnson, *Contact Mechanics*, 1985, §4.2)
//!
//! With the depth $z \ge 0$ and
//! $m^2 = \tfrac12[\sqrt{(a^2 - x^2 + z^2)^2 + 4x^2z^2} + (a^2 - x^2 + z^2)]$,
//! $n^2 = \tfrac12[\sqrt{(a^2 - x^2 + z^2)^2 + 4x^2z^2} - (a^2 - x^2 + z^2)]$
//! ($m \ge 0$, $n$ of the sign of $x$):
//! $$\sigma_x = -\frac{p_0}{a}\Big[m\Big(1 + \frac{z^2 + n^2}{m^2 + n^2}\Big) - 2z\Big],\quad
//!   \sigma_z = -\frac{p_0}{a}\, m\Big(1 - \frac{z^2 + n^2}{m^2 + n^2}\Big),\quad
//!   \tau_{xz} = -\frac{p_0}{a}\, n\,\frac{m^2 - z^2}{m^2 + n^2}$$
//! ([`mcewen`]; $\tau_{xz}$ here is the shear on the $x$, $z$ axes with $z$ pointing down
//! into the body, so that the FE's $\tau_{xy}$ with $y$ up is $-\tau_{xz}$), and in plane
//! strain $\sigma_y = \nu(\sigma_x + \sigma_z)$. First yield (von Mises) is where
//! $\sqrt{J_2}$ first reaches $k = \sigma_y/\sqrt3$: [`first_yield`].
//!
//! # The half-space ([`HalfSpace`])
//!
//! A rectangle of tri3 elements (the union-jack pattern of
//! [`crate::mesh::generators::rectangle`] on graded lines): uniform cells of size `h` in
//! the box $|x| \le L + 1.5a$, $0 \le z \le 2a$ under the path, growing geometrically by
//! `growth` per cell outside it to the half-width and depth `far` (both many `a`). The
//! bottom is held vertically, the sides horizontally (rollers). The test
//! `tests/shakedown.rs` checks that the boundary does not matter: the stresses under the
//! load change by less than 1% of $p_0$ (0.8% measured) from `far = 30 a` (the default) to
//! `far = 60 a`, and the FE stresses (h = a/8, the two triangles of a cell averaged) are
//! within 2.5% of $p_0$ of McEwen's under the load.
//!
//! # A pass ([`Shakedown::run_pass`])
//!
//! The pressure is put on at $x_c = -L$ in `ramp` equal increments, moved to $x_c = +L$ in
//! increments of `step` (default $a/10$, so $2L/\mathrm{step}$ moves), and taken off there
//! in `ramp` increments. Each increment is a static equilibrium
//! $K u = f_{ext} + f_p(u; s_0)$ on the elastic factor (one [`SparseLu`] of $K$, built
//! once) with the plastic pseudo-load $f_p$ of [`PlasticBody`] ([`InternalForce`]), by the
//! initial-stress iteration with Aitken's relaxation (as [`crate::model::Nonlinear`]):
//! stop when $|f_p(u_i) - f^i| \le$ `tol` $(|f_{int}(u_i)| + |f_p(u_i)|)$ (free dofs,
//! Euclidean norms). The J2 return is [`J2Material::update`] with no hardening, $k =
//! \sigma_y/\sqrt3$. No allocation inside the increment loop.
//!
//! What a pass reports ([`PassResult`]), over the elements of the central region
//! $|x| \le L - 2a$ (away from where the load is put on and taken off): the increase of the
//! equivalent plastic strain $\Delta\bar\varepsilon^p$ over the pass (largest and volume
//! integral), the net change of the plastic strain tensor over the pass (its equivalent
//! $\sqrt{\tfrac23\Delta\varepsilon^p:\Delta\varepsilon^p}$: equal to
//! $\Delta\bar\varepsilon^p$ for a strain that drifts one way, ratchetting; near zero for
//! a strain that goes and comes back, alternating plasticity), the equivalent plastic
//! strain, the surface's permanent horizontal shift at $x = 0$ and the residual
//! $\sigma_{xx}$ against depth at $x = 0$ once unloaded.

use super::{J2Material, PlasticBody, PointState, STATE_LEN};
use crate::assembly::{Assembler, Tri3Stiffness};
use crate::element::tri3::{self, ElementError, Tri3Geometry};
use crate::linalg::{set_identity_rows, LinalgError, SparseLu};
use crate::material::{Elastic, PlaneModel};
use crate::mesh::generators::{self, MeshError};
use crate::mesh::Cells;
use crate::model::InternalForce;

/// Aitken's relaxation factor bounds (as `crate::model::internal::AITKEN_BOUNDS`).
const AITKEN: (f64, f64) = (0.1, 20.0);

/// The exact elastic stresses `[sigma_x, sigma_z, tau_xz] / p0` of the Hertz line load of
/// half-width `a` centred at `x = 0`, at `x` and the depth `z >= 0` (module docs; McEwen).
pub fn mcewen(x: f64, z: f64, a: f64) -> [f64; 3] {
    let q = a * a - x * x + z * z;
    let r = (q * q + 4.0 * x * x * z * z).sqrt();
    let m = (0.5 * (r + q)).max(0.0).sqrt();
    let n = (0.5 * (r - q)).max(0.0).sqrt().copysign(x);
    let mn = m * m + n * n;
    if mn == 0.0 {
        // The contact edge on the surface.
        return [0.0; 3];
    }
    let w = (z * z + n * n) / mn;
    [
        -(m * (1.0 + w) - 2.0 * z) / a,
        -m * (1.0 - w) / a,
        -n * (m * m - z * z) / mn / a,
    ]
}

/// `sqrt(J2)` of the in-plane stresses `[sx, sz, txz]` with the plane-strain out-of-plane
/// `sy = nu (sx + sz)` (any units; the same back).
pub fn sqrt_j2_plane_strain(s: [f64; 3], nu: f64) -> f64 {
    let sy = nu * (s[0] + s[1]);
    (((s[0] - s[1]).powi(2) + (s[1] - sy).powi(2) + (sy - s[0]).powi(2)) / 6.0 + s[2] * s[2]).sqrt()
}

/// First yield of the exact elastic field (von Mises, plane strain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstYield {
    /// The largest `sqrt(J2) / p0` of the field.
    pub sqrt_j2_over_p0: f64,
    /// Its depth / `a` (on the axis `x = 0`).
    pub depth_over_a: f64,
    /// `p0 / k` at first yield: `1 / sqrt_j2_over_p0`.
    pub p0_over_k: f64,
}

/// First yield of [`mcewen`]'s field for Poisson's ratio `nu`: the largest `sqrt(J2)/p0` on
/// the axis (golden-section search over the depth, to 1e-10 a), which is the field's
/// largest (the test `tests/shakedown.rs` scans off the axis).
pub fn first_yield(nu: f64) -> FirstYield {
    let f = |z: f64| sqrt_j2_plane_strain(mcewen(0.0, z, 1.0), nu);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.05, 3.0);
    while hi - lo > 1e-10 {
        let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(c) > f(d) {
            hi = d;
        } else {
            lo = c;
        }
    }
    let z = 0.5 * (lo + hi);
    FirstYield {
        sqrt_j2_over_p0: f(z),
        depth_over_a: z,
        p0_over_k: 1.0 / f(z),
    }
}

/// Adds the consistent nodal loads of the Hertz pressure (`p0`, Pa, half-width `a`, m,
/// centre `xc`, m) on the top edges into `f` (N per m of thickness; downward, the `y` dof
/// `2 node + 1`): `top` lists the surface nodes in increasing `x`, `x` their abscissae.
/// Exact (module docs). No allocation.
pub fn hertz_loads_into(top: &[usize], x: &[f64], xc: f64, a: f64, p0: f64, f: &mut [f64]) {
    let f0 = |s: f64| 0.5 * (s * (1.0 - s * s).max(0.0).sqrt() + s.clamp(-1.0, 1.0).asin());
    let f1 = |s: f64| -(1.0 - s * s).max(0.0).powf(1.5) / 3.0;
    for k in 0..top.len().saturating_sub(1) {
        let (x1, x2) = (x[k], x[k + 1]);
        let s1 = ((x1 - xc) / a).max(-1.0);
        let s2 = ((x2 - xc) / a).min(1.0);
        if s2 <= s1 {
            continue;
        }
        let le = x2 - x1;
        let total = p0 * a * (f0(s2) - f0(s1));
        let second = p0 * a / le * ((xc - x1) * (f0(s2) - f0(s1)) + a * (f1(s2) - f1(s1)));
        f[2 * top[k] + 1] -= total - second;
        f[2 * top[k + 1] + 1] -= second;
    }
}

/// The inputs of a shakedown run. Lengths in m, stresses in Pa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShakedownConfig {
    /// `p0 / k`, with `k = sigma_y / sqrt(3)` the yield stress in shear.
    pub p0_over_k: f64,
    /// Contact half-width `a`, m (default 1e-3).
    pub a: f64,
    /// Elastic constants (default steel: 210 GPa, 0.3).
    pub elastic: Elastic,
    /// Uniaxial yield stress `sigma_y`, Pa (default 1 GPa; the results scale with it).
    pub yield_stress: f64,
    /// Cell size in the fine box, / `a` (default 1/8).
    pub h_over_a: f64,
    /// Half-length `L` of the path, / `a` (default 4).
    pub path_over_a: f64,
    /// Move of the load per increment, / `a` (default 0.1).
    pub step_over_a: f64,
    /// Half-width and depth of the half-space, / `a` (default 30).
    pub far_over_a: f64,
    /// Growth of the cells outside the fine box, per cell (default 1.25).
    pub growth: f64,
    /// Increments to put the load on and to take it off (default 4).
    pub ramp: usize,
    /// Tolerance of the initial-stress iteration (default 1e-9, module docs).
    pub tol: f64,
    /// Cap on the iterations of one increment (default 500).
    pub max_iterations: usize,
}

impl Default for ShakedownConfig {
    fn default() -> Self {
        Self {
            p0_over_k: 4.0,
            a: 1e-3,
            elastic: Elastic {
                young: 210e9,
                poisson: 0.3,
                density: 7850.0,
            },
            yield_stress: 1e9,
            h_over_a: 0.125,
            path_over_a: 4.0,
            step_over_a: 0.1,
            far_over_a: 30.0,
            growth: 1.25,
            ramp: 4,
            tol: 1e-9,
            max_iterations: 500,
        }
    }
}

/// Why a shakedown run cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum ShakedownError {
    /// A parameter outside its range.
    #[error("shakedown: {name} = {value} is not allowed; allowed: {allowed}")]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The mesh generator refused.
    #[error("shakedown mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A degenerate triangle.
    #[error("shakedown mesh: {0}")]
    Element(#[from] ElementError),
    /// The factorization failed.
    #[error("shakedown stiffness: {0}")]
    Linalg(#[from] LinalgError),
    /// An increment's iteration did not converge.
    #[error("shakedown: increment {increment} of pass {pass} did not converge in {iterations} iterations (residual {residual:e} of the scale)")]
    NotConverged {
        /// Pass (from 1).
        pass: usize,
        /// Increment within the pass (from 0).
        increment: usize,
        /// Iterations made.
        iterations: usize,
        /// Last relative residual.
        residual: f64,
    },
}

impl ShakedownConfig {
    /// Checks the ranges.
    ///
    /// # Errors
    /// [`ShakedownError::Parameter`] naming the first parameter out of range.
    pub fn validate(&self) -> Result<(), ShakedownError> {
        let check = |name, value: f64, ok: bool, allowed| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(ShakedownError::Parameter {
                    name,
                    value,
                    allowed,
                })
            }
        };
        let c = self;
        check(
            "p0_over_k",
            c.p0_over_k,
            c.p0_over_k >= 0.0 && c.p0_over_k <= 6.0,
            "0 to 6 (the plane-strain collapse is near 6.4)",
        )?;
        check("a", c.a, c.a > 0.0, "a positive length, m")?;
        check(
            "young",
            c.elastic.young,
            c.elastic.young > 0.0,
            "positive, Pa",
        )?;
        check(
            "poisson",
            c.elastic.poisson,
            c.elastic.poisson > -1.0 && c.elastic.poisson < 0.5,
            "-1 < nu < 0.5",
        )?;
        check(
            "yield_stress",
            c.yield_stress,
            c.yield_stress > 0.0,
            "positive, Pa",
        )?;
        check(
            "h_over_a",
            c.h_over_a,
            c.h_over_a >= 0.02 && c.h_over_a <= 0.5,
            "0.02 to 0.5",
        )?;
        check(
            "path_over_a",
            c.path_over_a,
            c.path_over_a >= 2.5 && c.path_over_a <= 20.0,
            "2.5 to 20 (the central region is |x| <= L - 2a)",
        )?;
        check(
            "step_over_a",
            c.step_over_a,
            c.step_over_a > 0.0 && c.step_over_a <= 0.5,
            "0 < step <= 0.5",
        )?;
        check(
            "far_over_a",
            c.far_over_a,
            c.far_over_a >= c.path_over_a + 4.0 && c.far_over_a <= 1000.0,
            "path_over_a + 4 to 1000",
        )?;
        check(
            "growth",
            c.growth,
            c.growth >= 1.0 && c.growth <= 2.0,
            "1 to 2",
        )?;
        check("ramp", c.ramp as f64, c.ramp >= 1, "at least 1")?;
        check("tol", c.tol, c.tol > 0.0 && c.tol < 1e-2, "0 < tol < 1e-2")?;
        check(
            "max_iterations",
            c.max_iterations as f64,
            c.max_iterations >= 1,
            "at least 1",
        )?;
        Ok(())
    }

    /// `k = sigma_y / sqrt(3)`, Pa.
    pub fn k(&self) -> f64 {
        self.yield_stress / 3f64.sqrt()
    }

    /// `p0`, Pa.
    pub fn p0(&self) -> f64 {
        self.p0_over_k * self.k()
    }

    /// The load moves of one pass (`2 L / step`, rounded).
    pub fn moves(&self) -> usize {
        (2.0 * self.path_over_a / self.step_over_a).round() as usize
    }

    /// Increments of one pass: `ramp` on, the moves, `ramp` off.
    pub fn increments_per_pass(&self) -> usize {
        2 * self.ramp + self.moves()
    }
}

/// Grid lines: uniform `h` on `[0, fine]`, then growing by `growth` to `far` (the last cell
/// stretched or shrunk to end there). Increasing, from 0.
fn graded_lines(h: f64, fine: f64, far: f64, growth: f64) -> Vec<f64> {
    let n_fine = (fine / h).round().max(1.0) as usize;
    let mut v: Vec<f64> = (0..=n_fine).map(|i| i as f64 * h).collect();
    let mut d = h;
    loop {
        d *= growth;
        let last = *v.last().expect("non-empty");
        if last + 1.5 * d >= far {
            v.push(far);
            break;
        }
        v.push(last + d);
    }
    v
}

/// The plane-strain half-space of a shakedown run: mesh, stiffness, its factor with the
/// rollers held (module docs).
pub struct HalfSpace {
    /// Node coordinates `[x, y]` (y up, the surface at `y = 0`), m.
    pub coords: Vec<f64>,
    /// Triangles (counter-clockwise).
    pub triangles: Vec<[usize; 3]>,
    /// Their geometry.
    pub geometry: Vec<Tri3Geometry>,
    /// Surface nodes in increasing `x`.
    pub top: Vec<usize>,
    /// Their `x`, m.
    pub top_x: Vec<f64>,
    /// Held dofs (true: held).
    pub fixed: Vec<bool>,
    /// The factor of `K` with the held rows and columns set to the identity.
    pub lu: SparseLu,
    /// The plane-strain `D`.
    pub d: [[f64; 3]; 3],
    /// Grid lines in `x` (m) and in depth (m, from the surface down).
    pub lines: (Vec<f64>, Vec<f64>),
}

impl HalfSpace {
    /// Builds the mesh and factors its stiffness.
    ///
    /// # Errors
    /// [`ShakedownError`] for bad parameters, a mesh or factor failure.
    pub fn new(c: &ShakedownConfig) -> Result<Self, ShakedownError> {
        c.validate()?;
        let (a, h) = (c.a, c.h_over_a * c.a);
        let half = graded_lines(h, (c.path_over_a + 1.5) * a, c.far_over_a * a, c.growth);
        let mut xs: Vec<f64> = half.iter().rev().map(|x| -x).collect();
        xs.extend_from_slice(&half[1..]);
        let depth = graded_lines(h, 2.0 * a, c.far_over_a * a, c.growth);
        let (nx, ny) = (xs.len() - 1, depth.len() - 1);
        let mut mesh = generators::rectangle(1.0, 1.0, nx, ny)?;
        // Row j of the rectangle (from the bottom) is the depth line ny - j.
        for (i, p) in mesh.coords.chunks_exact_mut(2).enumerate() {
            let (ix, jy) = (i % (nx + 1), i / (nx + 1));
            p[0] = xs[ix];
            p[1] = -depth[ny - jy];
        }
        let Cells::Tri3(triangles) = &mesh.cells else {
            unreachable!("rectangle gives triangles")
        };
        let triangles = triangles.clone();
        let geometry = triangles
            .iter()
            .map(|&t| tri3::geometry(&tri3::corners(&mesh, t)))
            .collect::<Result<Vec<_>, _>>()?;
        let d = PlaneModel::Strain.elasticity_matrix(&c.elastic);
        let asm = Assembler::new(&mesh);
        let mut k = asm.assemble(&Tri3Stiffness {
            geometry: &geometry,
            d: &d,
            thickness: 1.0,
        });
        let mut fixed = vec![false; mesh.n_dofs()];
        for &n in &mesh.node_sets["left"] {
            fixed[2 * n] = true;
        }
        for &n in &mesh.node_sets["right"] {
            fixed[2 * n] = true;
        }
        for &n in &mesh.node_sets["bottom"] {
            fixed[2 * n + 1] = true;
        }
        set_identity_rows(&asm.pattern, &mut k, &fixed);
        let lu = SparseLu::new(&asm.pattern, &k)?;
        let top = mesh.node_sets["top"].clone();
        let top_x = top.iter().map(|&n| mesh.coords[2 * n]).collect();
        Ok(Self {
            coords: mesh.coords,
            triangles,
            geometry,
            top,
            top_x,
            fixed,
            lu,
            d,
            lines: (xs, depth),
        })
    }

    /// Number of dofs.
    pub fn n_dofs(&self) -> usize {
        self.coords.len()
    }

    /// Centroid `[x, y]` of triangle `e`, m.
    pub fn centroid(&self, e: usize) -> [f64; 2] {
        let t = self.triangles[e];
        let c = |k: usize| (0..3).map(|i| self.coords[2 * t[i] + k]).sum::<f64>() / 3.0;
        [c(0), c(1)]
    }

    /// The elastic displacement under the load `f` (held dofs zeroed), in place.
    pub fn solve_in_place(&mut self, f: &mut [f64]) {
        for (v, &h) in f.iter_mut().zip(&self.fixed) {
            if h {
                *v = 0.0;
            }
        }
        self.lu.solve_in_place(f);
    }

    /// The elastic element stresses `[sxx, syy, txy]` (Pa) under the standing Hertz pressure
    /// `p0` at `xc` (allocates; for checks).
    pub fn standing_stresses(&mut self, xc: f64, a: f64, p0: f64) -> Vec<[f64; 3]> {
        let mut u = vec![0.0; self.n_dofs()];
        hertz_loads_into(&self.top, &self.top_x, xc, a, p0, &mut u);
        self.solve_in_place(&mut u);
        let mut s = vec![[0.0; 3]; self.triangles.len()];
        tri3::stresses_into(&self.geometry, &self.triangles, &self.d, &u, &mut s);
        s
    }
}

/// What one pass gives (module docs). Strains dimensionless, integrals in m^2 per m of
/// thickness.
#[derive(Debug, Clone, PartialEq)]
pub struct PassResult {
    /// Pass number, from 1.
    pub pass: usize,
    /// Largest increase of the equivalent plastic strain over the pass, central region.
    pub d_eq_max: f64,
    /// Its integral over the central region, m^2.
    pub d_eq_integral: f64,
    /// Largest equivalent of the net plastic strain change over the pass, central region.
    pub net_max: f64,
    /// Its integral over the central region, m^2.
    pub net_integral: f64,
    /// Largest equivalent plastic strain so far, central region.
    pub eq_max: f64,
    /// Elements of the central region that flowed during the pass.
    pub flowed: usize,
    /// The surface's permanent horizontal displacement at `x = 0` after the pass, m.
    pub surface_ux: f64,
    /// Initial-stress iterations over the pass.
    pub iterations: usize,
    /// Most iterations in one increment.
    pub max_iterations: usize,
    /// Residual `sigma_xx` (Pa) at `x = 0` once unloaded: `(depth of the cell centre, m,
    /// sigma_xx)`, one per row of cells of the column `0 <= x <= h`.
    pub residual_sxx: Vec<(f64, f64)>,
}

/// A shakedown run: the half-space, the plastic body and the buffers (module docs).
pub struct Shakedown {
    /// The inputs.
    pub config: ShakedownConfig,
    /// The half-space.
    pub space: HalfSpace,
    /// The plastic body (every triangle).
    pub body: PlasticBody,
    /// The committed plastic state.
    pub state: Vec<f64>,
    /// The displacement of the last increment, m.
    pub u: Vec<f64>,
    pass: usize,
    trial: Vec<f64>,
    at_pass_start: Vec<f64>,
    f_ext: Vec<f64>,
    f_cur: Vec<f64>,
    f_nl: Vec<f64>,
    f_int: Vec<f64>,
    r: Vec<f64>,
    r_prev: Vec<f64>,
    central: Vec<bool>,
    column: Vec<(usize, usize)>,
    centre_node: usize,
}

impl Shakedown {
    /// Builds the half-space and the plastic body.
    ///
    /// # Errors
    /// [`ShakedownError`] as [`HalfSpace::new`].
    pub fn new(config: ShakedownConfig) -> Result<Self, ShakedownError> {
        let space = HalfSpace::new(&config)?;
        let material = J2Material {
            elastic: config.elastic,
            yield_stress: config.yield_stress,
            isotropic: super::Isotropic {
                modulus: 0.0,
                voce_q: 0.0,
                voce_b: 0.0,
            },
            kinematic: super::Kinematic { c: 0.0, gamma: 0.0 },
        };
        let body = PlasticBody::new(
            material,
            PlaneModel::Strain,
            1.0,
            space.triangles.clone(),
            space.geometry.clone(),
        );
        let (a, h) = (config.a, config.h_over_a * config.a);
        let xc_max = (config.path_over_a - 2.0) * a;
        let central = (0..space.triangles.len())
            .map(|e| space.centroid(e)[0].abs() <= xc_max)
            .collect();
        // The column of cells 0 <= x <= h: both triangles of each quad, by row (from the
        // surface down). Rectangle's triangles are 2 per quad, quads row by row from the
        // bottom.
        let (xs, depth) = &space.lines;
        let nx = xs.len() - 1;
        let ny = depth.len() - 1;
        let i0 = xs
            .iter()
            .position(|&x| x >= -1e-9 * h)
            .expect("x = 0 is a grid line");
        let column = (0..ny)
            .rev()
            .map(|jy| {
                let q = i0 + jy * nx;
                (2 * q, 2 * q + 1)
            })
            .collect();
        let centre_node = space.top[i0];
        let n = space.n_dofs();
        let ns = body.state_len();
        Ok(Self {
            config,
            space,
            body,
            state: vec![0.0; ns],
            u: vec![0.0; n],
            pass: 0,
            trial: vec![0.0; ns],
            at_pass_start: vec![0.0; ns],
            f_ext: vec![0.0; n],
            f_cur: vec![0.0; n],
            f_nl: vec![0.0; n],
            f_int: vec![0.0; n],
            r: vec![0.0; n],
            r_prev: vec![0.0; n],
            central,
            column,
            centre_node,
        })
    }

    /// The static equilibrium under the Hertz pressure `p0` (Pa) at `xc` (m) from the
    /// committed state, by the initial-stress iteration (module docs); commits the state.
    /// Returns the iterations. No allocation.
    fn increment(&mut self, xc: f64, p0: f64, increment: usize) -> Result<usize, ShakedownError> {
        let c = &self.config;
        self.f_ext.fill(0.0);
        if p0 > 0.0 {
            hertz_loads_into(
                &self.space.top,
                &self.space.top_x,
                xc,
                c.a,
                p0,
                &mut self.f_ext,
            );
        }
        self.body.pseudo_load(&self.state, &mut self.f_cur);
        let mut omega = 1.0;
        let mut residual = f64::INFINITY;
        for it in 1..=c.max_iterations {
            for (u, (fe, fc)) in self.u.iter_mut().zip(self.f_ext.iter().zip(&self.f_cur)) {
                *u = fe + fc;
            }
            self.space.solve_in_place(&mut self.u);
            self.body.evaluate(
                &self.state,
                &self.u,
                &mut self.trial,
                &mut self.f_nl,
                &mut self.f_int,
            );
            let (mut rr, mut fi, mut fp) = (0.0, 0.0, 0.0);
            for i in 0..self.r.len() {
                self.r[i] = if self.space.fixed[i] {
                    0.0
                } else {
                    self.f_nl[i] - self.f_cur[i]
                };
                if !self.space.fixed[i] {
                    rr += self.r[i] * self.r[i];
                    fi += self.f_int[i] * self.f_int[i];
                    fp += self.f_nl[i] * self.f_nl[i];
                }
            }
            let scale = fi.sqrt() + fp.sqrt();
            residual = if scale > 0.0 { rr.sqrt() / scale } else { 0.0 };
            if residual <= c.tol {
                self.state.copy_from_slice(&self.trial);
                return Ok(it);
            }
            if it > 1 {
                let (mut num, mut den) = (0.0, 0.0);
                for (r, rp) in self.r.iter().zip(&self.r_prev) {
                    let dr = r - rp;
                    num += rp * dr;
                    den += dr * dr;
                }
                if den > 0.0 {
                    omega = (-omega * num / den).clamp(AITKEN.0, AITKEN.1);
                }
            }
            for (fc, r) in self.f_cur.iter_mut().zip(&self.r) {
                *fc += omega * r;
            }
            self.r_prev.copy_from_slice(&self.r);
        }
        Err(ShakedownError::NotConverged {
            pass: self.pass,
            increment,
            iterations: c.max_iterations,
            residual,
        })
    }

    /// One pass: the load put on at `-L`, moved to `+L`, taken off (module docs). One
    /// allocation (the result's profile), none in the increments.
    ///
    /// # Errors
    /// [`ShakedownError::NotConverged`] when an increment's iteration reaches its cap.
    pub fn run_pass(&mut self) -> Result<PassResult, ShakedownError> {
        self.pass += 1;
        self.at_pass_start.copy_from_slice(&self.state);
        let c = self.config;
        let (a, p0) = (c.a, c.p0());
        let l = c.path_over_a * a;
        let moves = c.moves();
        let (mut iterations, mut most) = (0, 0);
        for k in 0..c.increments_per_pass() {
            let (xc, p) = if k < c.ramp {
                (-l, p0 * (k + 1) as f64 / c.ramp as f64)
            } else if k < c.ramp + moves {
                let m = (k + 1 - c.ramp) as f64;
                (-l + 2.0 * l * m / moves as f64, p0)
            } else {
                let off = (k + 1 - c.ramp - moves) as f64;
                (l, p0 * (1.0 - off / c.ramp as f64))
            };
            let it = self.increment(xc, p, k)?;
            iterations += it;
            most = most.max(it);
        }
        Ok(self.pass_result(iterations, most))
    }

    fn pass_result(&self, iterations: usize, most: usize) -> PassResult {
        let mut out = PassResult {
            pass: self.pass,
            d_eq_max: 0.0,
            d_eq_integral: 0.0,
            net_max: 0.0,
            net_integral: 0.0,
            eq_max: 0.0,
            flowed: 0,
            surface_ux: self.u[2 * self.centre_node],
            iterations,
            max_iterations: most,
            residual_sxx: Vec::with_capacity(self.column.len()),
        };
        for e in 0..self.space.triangles.len() {
            if !self.central[e] {
                continue;
            }
            let s0 = PlasticBody::point(&self.at_pass_start, e);
            let s1 = PlasticBody::point(&self.state, e);
            let d_eq = s1.eq - s0.eq;
            let de = [0, 1, 2, 3].map(|i| s1.eps_p[i] - s0.eps_p[i]);
            let net = (2.0 / 3.0
                * (de[0] * de[0] + de[1] * de[1] + de[2] * de[2] + 2.0 * de[3] * de[3]))
                .sqrt();
            let area = self.space.geometry[e].area;
            out.d_eq_max = out.d_eq_max.max(d_eq);
            out.d_eq_integral += area * d_eq;
            out.net_max = out.net_max.max(net);
            out.net_integral += area * net;
            out.eq_max = out.eq_max.max(s1.eq);
            out.flowed += usize::from(d_eq > 0.0);
        }
        for &(e1, e2) in &self.column {
            let (s1, s2) = (self.sxx(e1), self.sxx(e2));
            let (a1, a2) = (self.space.geometry[e1].area, self.space.geometry[e2].area);
            let depth = -(self.space.centroid(e1)[1] + self.space.centroid(e2)[1]) / 2.0;
            out.residual_sxx
                .push((depth, (a1 * s1 + a2 * s2) / (a1 + a2)));
        }
        out
    }

    /// `sigma_xx` (Pa) of element `e` at the current displacement and committed state:
    /// `lambda tr(eps_e) + 2 mu eps_e,xx` with the elastic strain `eps - eps_p` (plane
    /// strain, `eps_zz = 0`).
    pub fn sxx(&self, e: usize) -> f64 {
        let el = &self.config.elastic;
        let (lam, mu) = (
            el.young * el.poisson / ((1.0 + el.poisson) * (1.0 - 2.0 * el.poisson)),
            el.young / (2.0 * (1.0 + el.poisson)),
        );
        let ue = tri3::element_displacements(&self.u, &self.space.triangles[e]);
        let eps = tri3::strain(&self.space.geometry[e], &ue);
        let st: PointState = PlasticBody::point(&self.state, e);
        let ee = [eps[0] - st.eps_p[0], eps[1] - st.eps_p[1], -st.eps_p[2]];
        lam * (ee[0] + ee[1] + ee[2]) + 2.0 * mu * ee[0]
    }

    /// The equivalent plastic strain of every element.
    pub fn equivalent_plastic_strain(&self) -> Vec<f64> {
        (0..self.space.triangles.len())
            .map(|e| self.state[e * STATE_LEN + 8])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The documented defaults, and the increments a pass of them makes.
    #[test]
    fn the_defaults_are_the_documented_ones() {
        let c = ShakedownConfig::default();
        assert_eq!(
            (c.a, c.elastic.young, c.elastic.poisson, c.yield_stress),
            (1e-3, 210e9, 0.3, 1e9)
        );
        assert_eq!(
            (
                c.h_over_a,
                c.path_over_a,
                c.step_over_a,
                c.far_over_a,
                c.growth
            ),
            (0.125, 4.0, 0.1, 30.0, 1.25)
        );
        assert_eq!((c.ramp, c.tol, c.max_iterations), (4, 1e-9, 500));
        assert!(c.validate().is_ok());
        assert_eq!((c.moves(), c.increments_per_pass()), (80, 88));
        assert!((c.p0() / c.k() - c.p0_over_k).abs() < 1e-15);
    }

    /// Uniform cells to the fine limit, then growing, ending exactly at `far`.
    #[test]
    fn graded_lines_are_uniform_then_grow_to_the_far_end() {
        let v = graded_lines(0.125, 2.0, 30.0, 1.25);
        assert_eq!(v[16], 2.0);
        assert!(v[..=16]
            .windows(2)
            .all(|w| (w[1] - w[0] - 0.125).abs() < 1e-12));
        assert!(v[16..v.len() - 1]
            .windows(3)
            .all(|w| (w[2] - w[1]) > (w[1] - w[0])));
        assert_eq!(*v.last().unwrap(), 30.0);
    }

    /// Each parameter out of range is refused by name.
    #[test]
    fn bad_parameters_are_named() {
        let bad = [
            ShakedownConfig {
                p0_over_k: f64::NAN,
                ..Default::default()
            },
            ShakedownConfig {
                h_over_a: 0.0,
                ..Default::default()
            },
            ShakedownConfig {
                far_over_a: 5.0,
                ..Default::default()
            },
        ];
        let names: Vec<_> = bad
            .iter()
            .map(|c| match c.validate() {
                Err(ShakedownError::Parameter { name, .. }) => name,
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(names, ["p0_over_k", "h_over_a", "far_over_a"]);
    }
}
