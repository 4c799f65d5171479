//! The spinning wheel's modes in its rotating frame: the state-space eigenproblem with the
//! Coriolis (gyroscopic) terms, forward and backward whirl, the zero-frequency modes
//! ([`spinning_analysis`]; the module docs of [`crate::modes`]).

use super::*;
/// Whirl direction of a mode of the spinning wheel, in the rotating frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Whirl {
    /// The material points orbit in the sense of the spin: frequency lowered by Coriolis.
    Forward,
    /// The material points orbit against the spin: frequency raised by Coriolis.
    Backward,
    /// Not one of a pair of equal rest frequencies (or no spin): no first-order splitting.
    Standing,
}

impl std::fmt::Display for Whirl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Whirl::Forward => "forward",
            Whirl::Backward => "backward",
            Whirl::Standing => "standing",
        })
    }
}

/// One mode of the spinning wheel (an eigenvalue pair `lambda`, `conj(lambda)`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SpinMode {
    /// Frequency in the rotating frame, `|Im lambda| / (2 pi)`, Hz (0 for a zero-frequency
    /// mode).
    pub frequency_hz: f64,
    /// Period `1 / f`, microseconds (infinite for a zero-frequency mode).
    pub period_us: f64,
    /// Growth rate `Re lambda`, 1/s (negative: decaying, positive: unstable).
    pub growth_rate: f64,
    /// Frequency of the rest mode this mode comes from (the largest share of its shape in
    /// the rest modes, by mass), Hz.
    pub rest_frequency_hz: f64,
    /// Index of that rest mode in the list of all rest modes of the model sorted by
    /// frequency, rigid modes included (`None` for a zero-frequency spinning mode).
    pub rest_index: Option<usize>,
    /// Whether that rest mode is one of a pair that whirls ([`super::paired`]).
    pub paired: bool,
    /// Forward or backward whirl of a split pair, or standing.
    pub whirl: Whirl,
    /// Normalised modal angular momentum `j = Im(phi^H (M_s (x) J) phi) / (phi^H M phi)`,
    /// in `[-1, 1]`; positive when the material points orbit counter-clockwise.
    pub angular_momentum: f64,
    /// `"elastic"`, `"rigid"` (a zero eigenvalue pair), `"overdamped"` or `"divergent"`
    /// (real eigenvalues).
    pub kind: String,
}

/// The full result of the spinning analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct SpinAnalysis {
    /// The zero-frequency modes, then the `count` lowest oscillating ones by frequency.
    pub modes: Vec<SpinMode>,
    /// Every eigenvalue `lambda = [Re, Im]` of the state-space problem, rad/s.
    pub eigenvalues: Vec<[f64; 2]>,
    /// Eigenvalues with `|lambda|` below this (rad/s) are counted as zero (rigid).
    pub zero_tolerance: f64,
    /// Frame angular velocity `Omega = -omega`, rad/s.
    pub omega_frame: f64,
}

impl SpinAnalysis {
    /// The largest `|Re lambda| / |Im lambda|` over the non-zero eigenvalues (infinite if one
    /// of them is real): 0 for a marginally stable undamped gyroscopic system.
    pub fn max_real_to_imag(&self) -> f64 {
        self.eigenvalues
            .iter()
            .filter(|l| l[0].hypot(l[1]) >= self.zero_tolerance)
            .map(|l| {
                if l[1] == 0.0 {
                    f64::INFINITY
                } else {
                    l[0].abs() / l[1].abs()
                }
            })
            .fold(0.0, f64::max)
    }
}

/// The `count` lowest modes of the spinning wheel in its rotating frame (after the
/// zero-frequency ones), see [`spinning_analysis`].
///
/// # Errors
/// As [`spinning_analysis`].
pub fn spinning_modes(model: &WheelModel, count: usize) -> Result<Vec<SpinMode>, ModesError> {
    spinning_analysis(model, count).map(|a| a.modes)
}

/// The quadratic eigenproblem `(K_eff + lambda C + lambda^2 M) phi = 0` of the wheel in its
/// rotating frame (module docs), with every eigenvalue.
///
/// `K_eff` and `C` are the model's ([`WheelModel::model`]): with `omega = 0` or without
/// the rotating frame they are the elastic stiffness and the external damping, and the
/// frequencies are the rest ones. The modes are matched to the rest modes by the mass
/// share of their shape, and the members of a split pair labelled forward / backward.
///
/// # Errors
/// [`ModesError::TooLarge`] past [`MAX_SPINNING_DOFS`] free dofs, and the errors of
/// [`natural_modes`].
pub fn spinning_analysis(model: &WheelModel, count: usize) -> Result<SpinAnalysis, ModesError> {
    let asm = &model.model.assembler;
    let n = asm.pattern.nrows();
    check_values(asm, &model.model.m, "mass")?;
    check_values(asm, &model.model.k, "stiffness")?;
    check_values(asm, &model.model.c, "damping")?;
    check_values(asm, &model.k_elastic, "stiffness")?;
    let free = FreeDofs::new(n, &model.fixed_dofs)?;
    free.check_size("spinning", MAX_SPINNING_DOFS)?;
    let par = faer::get_global_parallelism();
    let l = cholesky_mass(asm, &model.model.m, &free)?;

    // Rest modes in the same coordinates q = L^T u, for matching.
    let rest = RestModes::new(l.as_ref(), &free, asm, &model.k_elastic, par)?;
    let state = StateSpace::new(
        l.as_ref(),
        &free,
        asm,
        (&model.model.k, &model.model.c),
        par,
    )?;
    let eigenvalues = &state.eigenvalues;
    let lmax = eigenvalues
        .iter()
        .map(|l| l[0].hypot(l[1]))
        .fold(0.0, f64::max);
    let tol = ZERO_FREQUENCY_RATIO * lmax;
    let omega_frame = if model.spec.rotating_frame {
        -model.spec.omega
    } else {
        0.0
    };

    let mut modes = zero_frequency_modes(eigenvalues, tol);
    // Oscillating modes: Im lambda > 0, the lowest `count`.
    let mut osc: Vec<usize> = (0..eigenvalues.len())
        .filter(|&i| eigenvalues[i][1] >= tol)
        .collect();
    osc.sort_by(|&x, &y| eigenvalues[x][1].total_cmp(&eigenvalues[y][1]));
    osc.truncate(count);
    for &i in &osc {
        let z = state.eigenvector(i)?;
        // q = y1 / a (the scale does not matter for the ratios below).
        let qre = z.subrows(0, free.len()).to_owned();
        let (best, paired) = rest.nearest(qre.as_ref(), omega_frame);
        let wb = rest.w[best];
        let j = shape_angular_momentum(model, l.as_ref(), &free, qre, par);
        let whirl = if !paired || omega_frame == 0.0 || j == 0.0 {
            Whirl::Standing
        } else if j * omega_frame > 0.0 {
            Whirl::Forward
        } else {
            Whirl::Backward
        };
        let [re, im] = eigenvalues[i];
        let frequency_hz = im / (2.0 * std::f64::consts::PI);
        modes.push(SpinMode {
            frequency_hz,
            period_us: period_us(frequency_hz),
            growth_rate: re,
            rest_frequency_hz: wb / (2.0 * std::f64::consts::PI),
            rest_index: Some(best),
            paired,
            whirl,
            angular_momentum: j,
            kind: "elastic".to_string(),
        });
    }
    Ok(SpinAnalysis {
        modes,
        eigenvalues: state.eigenvalues,
        zero_tolerance: tol,
        omega_frame,
    })
}

/// The rest modes in the coordinates `q = L^T u` of the spinning analysis, which the
/// spinning modes are matched to.
struct RestModes {
    /// The eigendecomposition of the unit-scaled `L^-1 K L^-T` (`K` the elastic stiffness).
    evd: faer::linalg::solvers::SelfAdjointEigen<f64>,
    /// The circular frequencies, rad/s, increasing.
    w: Vec<f64>,
}

impl RestModes {
    /// The rest modes of the elastic stiffness `k_elastic` with the mass factor `l`.
    fn new(
        l: MatRef<'_, f64>,
        free: &FreeDofs,
        asm: &Assembler,
        k_elastic: &[f64],
        par: Par,
    ) -> Result<Self, ModesError> {
        let nf = free.len();
        let (rest, rest_scale) = unit_scaled(congruence(l, free.dense(asm, k_elastic), par, true));
        let rest = rest
            .self_adjoint_eigen(Side::Lower)
            .map_err(|_| ModesError::NoConvergence("self-adjoint"))?;
        let rest_w: Vec<f64> = (0..nf)
            .map(|i| (rest_scale * rest.S().column_vector()[i]).max(0.0).sqrt())
            .collect();
        Ok(Self {
            evd: rest,
            w: rest_w,
        })
    }

    /// The rest mode with the largest share `|X^T q|^2` of `q = [Re q, Im q]`, and whether
    /// it is one of a pair of (nearly) equal frequencies.
    fn nearest(&self, qre: MatRef<'_, f64>, omega_frame: f64) -> (usize, bool) {
        let nf = self.w.len();
        // Share of each rest mode: |X^T q|^2.
        let proj = self.evd.U().transpose() * qre;
        let best = (0..nf)
            .max_by(|&x, &y| {
                let px = proj[(x, 0)].powi(2) + proj[(x, 1)].powi(2);
                let py = proj[(y, 0)].powi(2) + proj[(y, 1)].powi(2);
                px.total_cmp(&py)
            })
            .unwrap_or(0);
        let wb = self.w[best];
        let near = |k: usize| super::paired(wb, self.w[k], omega_frame);
        let paired = (best > 0 && near(best - 1)) || (best + 1 < nf && near(best + 1));
        (best, paired)
    }
}

/// The quadratic eigenproblem in `q = L^T u` as a state-space one,
/// `B = [[0, a I], [-K~/a, -C~]]` for the state `[a q, lambda q]`, unit-scaled and solved.
struct StateSpace {
    /// `K~ = L^-1 K_eff L^-T`.
    kt: Mat<f64>,
    /// `C~ = L^-1 C L^-T`.
    ct: Mat<f64>,
    /// The scale `a = sqrt(max K~_ii)` of the state's first half (1 for a zero `K~`).
    a: f64,
    /// `B / scale`.
    big: Mat<f64>,
    /// `max |B_ij|`.
    scale: f64,
    /// The eigendecomposition of `B / scale`.
    evd: faer::linalg::solvers::Eigen<f64>,
    /// Every eigenvalue `lambda = [Re, Im]` of `B`, rad/s.
    eigenvalues: Vec<[f64; 2]>,
}

impl StateSpace {
    /// The state-space problem of the stiffness and damping values `(k, c)` with the mass
    /// factor `l`.
    fn new(
        l: MatRef<'_, f64>,
        free: &FreeDofs,
        asm: &Assembler,
        (k, c): (&[f64], &[f64]),
        par: Par,
    ) -> Result<Self, ModesError> {
        let nf = free.len();
        let kt = congruence(l, free.dense(asm, k), par, true);
        let ct = congruence(l, free.dense(asm, c), par, false);
        let a = (0..nf).map(|i| kt[(i, i)]).fold(0.0, f64::max).sqrt();
        let a = if a > 0.0 { a } else { 1.0 };
        let mut big = Mat::<f64>::zeros(2 * nf, 2 * nf);
        for i in 0..nf {
            big[(i, nf + i)] = a;
        }
        for j in 0..nf {
            for i in 0..nf {
                big[(nf + i, j)] = -kt[(i, j)] / a;
                big[(nf + i, nf + j)] = -ct[(i, j)];
            }
        }
        let (big, scale) = unit_scaled(big);
        let evd = big
            .eigen()
            .map_err(|_| ModesError::NoConvergence("nonsymmetric"))?;
        let s = evd.S().column_vector();
        let eigenvalues: Vec<[f64; 2]> = (0..2 * nf)
            .map(|i| [scale * s[i].re, scale * s[i].im])
            .collect();
        Ok(Self {
            kt,
            ct,
            a,
            big,
            scale,
            evd,
            eigenvalues,
        })
    }

    /// The eigenvector of eigenvalue `i`, `[a q, lambda q]`, as real and imaginary columns;
    /// recomputed on the pencil when faer's is inaccurate.
    fn eigenvector(&self, i: usize) -> Result<Mat<f64>, ModesError> {
        let (nf, a, scale) = (self.kt.nrows(), self.a, self.scale);
        let s = self.evd.S().column_vector();
        let u = self.evd.U();
        // The eigenvector [a q, lambda q] as real and imaginary columns.
        let mut z = Mat::<f64>::zeros(2 * nf, 2);
        for r in 0..2 * nf {
            z[(r, 0)] = u[(r, i)].re;
            z[(r, 1)] = u[(r, i)].im;
        }
        // faer 0.24 returns inaccurate eigenvectors for (nearly) repeated eigenvalues, e.g.
        // the pairs of equal frequencies without spin: those are recomputed by inverse
        // iteration on the quadratic pencil from faer's vector.
        if state_residual(self.big.as_ref(), z.as_ref(), s[i]) > MAX_RESIDUAL {
            let lambda = faer::c64::new(self.eigenvalues[i][0], self.eigenvalues[i][1]);
            let q = refine_on_pencil(&self.kt, &self.ct, lambda, z.subrows(0, nf));
            for r in 0..nf {
                let x = faer::c64::new(q[(r, 0)], q[(r, 1)]);
                let y = lambda * x / scale;
                (z[(r, 0)], z[(r, 1)]) = (a / scale * x.re, a / scale * x.im);
                (z[(nf + r, 0)], z[(nf + r, 1)]) = (y.re, y.im);
            }
            check_residual(
                "nonsymmetric",
                state_residual(self.big.as_ref(), z.as_ref(), s[i]),
            )?;
        }
        Ok(z)
    }
}

/// The zero-frequency modes among `eigenvalues` (`|Im lambda| < tol`): the rigid pairs,
/// then the real ones one by one.
pub(super) fn zero_frequency_modes(eigenvalues: &[[f64; 2]], tol: f64) -> Vec<SpinMode> {
    let mut modes = Vec::new();
    // Zero-frequency eigenvalues: rigid pairs, then real ones one by one.
    let zero: Vec<usize> = (0..eigenvalues.len())
        .filter(|&i| eigenvalues[i][1].abs() < tol)
        .collect();
    let rigid: Vec<usize> = zero
        .iter()
        .copied()
        .filter(|&i| eigenvalues[i][0].abs() < tol)
        .collect();
    for pair in rigid.chunks(2) {
        let growth = pair
            .iter()
            .map(|&i| eigenvalues[i][0])
            .fold(f64::NEG_INFINITY, f64::max);
        modes.push(zero_mode(growth, "rigid"));
    }
    for &i in zero.iter().filter(|&&i| eigenvalues[i][0].abs() >= tol) {
        let re = eigenvalues[i][0];
        modes.push(zero_mode(
            re,
            if re < 0.0 { "overdamped" } else { "divergent" },
        ));
    }
    modes
}

/// The angular momentum of the shape `u = L^-T q` of `q = [Re q, Im q]` (its real and
/// imaginary parts, on every dof of `model`).
fn shape_angular_momentum(
    model: &WheelModel,
    l: MatRef<'_, f64>,
    free: &FreeDofs,
    mut qre: Mat<f64>,
    par: Par,
) -> f64 {
    let asm = &model.model.assembler;
    let n = asm.pattern.nrows();
    // Shape u = L^-T q (real and imaginary parts), then its angular momentum.
    solve_upper_triangular_in_place(l.transpose(), qre.as_mut(), par);
    let mut ure = vec![0.0; n];
    let mut uim = vec![0.0; n];
    for (f, &dof) in free.dofs.iter().enumerate() {
        ure[dof] = qre[(f, 0)];
        uim[dof] = qre[(f, 1)];
    }
    angular_momentum(asm, &model.model.m, &ure, &uim, model.mesh.dim)
}

/// `max_i |(B z - s z)_i| / |z|` for the complex vector `z` given as the columns
/// `[Re z, Im z]`.
fn state_residual(big: MatRef<'_, f64>, z: MatRef<'_, f64>, s: faer::c64) -> f64 {
    let bz = big * z;
    let mut res = 0.0_f64;
    for r in 0..z.nrows() {
        let (zr, zi) = (z[(r, 0)], z[(r, 1)]);
        res = res.max((bz[(r, 0)] - s.re * zr + s.im * zi).abs());
        res = res.max((bz[(r, 1)] - s.re * zi - s.im * zr).abs());
    }
    res / z.norm_l2().max(f64::MIN_POSITIVE)
}

/// Two steps of inverse iteration on the pencil `P(mu) = K~ + mu C~ + mu^2 I`, `mu` the
/// eigenvalue `lambda` shifted by `1e-10 |lambda|`, from `q0 = [Re q, Im q]`; returns the
/// refined `q` in the same form.
fn refine_on_pencil(
    kt: &Mat<f64>,
    ct: &Mat<f64>,
    lambda: faer::c64,
    q0: MatRef<'_, f64>,
) -> Mat<f64> {
    use faer::linalg::solvers::Solve;
    let nf = kt.nrows();
    let mu = lambda + faer::c64::new(0.0, 1e-10 * lambda.norm());
    let mu2 = mu * mu;
    let mut p = Mat::<faer::c64>::zeros(nf, nf);
    for j in 0..nf {
        for i in 0..nf {
            p[(i, j)] = faer::c64::new(kt[(i, j)] + mu.re * ct[(i, j)], mu.im * ct[(i, j)]);
        }
        p[(j, j)] += mu2;
    }
    let lu = p.partial_piv_lu();
    let mut x = Mat::<faer::c64>::from_fn(nf, 1, |r, _| faer::c64::new(q0[(r, 0)], q0[(r, 1)]));
    for _ in 0..2 {
        x = lu.solve(&x);
        let norm = x.norm_l2();
        if norm > 0.0 && norm.is_finite() {
            x *= faer::Scale(faer::c64::new(1.0 / norm, 0.0));
        }
    }
    Mat::<f64>::from_fn(
        nf,
        2,
        |r, c| if c == 0 { x[(r, 0)].re } else { x[(r, 0)].im },
    )
}

fn zero_mode(growth_rate: f64, kind: &str) -> SpinMode {
    SpinMode {
        frequency_hz: 0.0,
        period_us: f64::INFINITY,
        growth_rate,
        rest_frequency_hz: 0.0,
        rest_index: None,
        paired: false,
        whirl: Whirl::Standing,
        angular_momentum: 0.0,
        kind: kind.to_string(),
    }
}

/// Classifies a zero-frequency shape by a least-squares fit of the rigid motions
/// (translations, and in 2D the rotation about the centroid of the nodes).
pub(super) fn rigid_kind(mesh: &Mesh, u: &[f64]) -> &'static str {
    let dim = mesh.dim;
    let nn = mesh.n_nodes();
    if nn == 0 || u.len() != dim * nn {
        return "zero-energy mechanism";
    }
    let norm2: f64 = u.iter().map(|v| v * v).sum();
    if dim != 2 {
        let mean = u.iter().sum::<f64>() / nn as f64;
        let res: f64 = u.iter().map(|v| (v - mean).powi(2)).sum();
        return if res <= 1e-6 * norm2 {
            "rigid translation"
        } else {
            "zero-energy mechanism"
        };
    }
    let c = mesh
        .points()
        .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
    let c = [c[0] / nn as f64, c[1] / nn as f64];
    // Orthogonal basis: tx, ty, rotation about the centroid (orthogonal to both).
    let (mut tx, mut ty, mut rot, mut r2) = (0.0, 0.0, 0.0, 0.0);
    for (i, p) in mesh.points().enumerate() {
        let (x, y) = (p[0] - c[0], p[1] - c[1]);
        tx += u[2 * i];
        ty += u[2 * i + 1];
        rot += -y * u[2 * i] + x * u[2 * i + 1];
        r2 += x * x + y * y;
    }
    let t2 = (tx * tx + ty * ty) / nn as f64;
    let rot2 = if r2 > 0.0 { rot * rot / r2 } else { 0.0 };
    if norm2 - t2 - rot2 > 1e-6 * norm2 {
        "zero-energy mechanism"
    } else if rot2 >= 1e-6 * norm2 {
        "rigid rotation"
    } else {
        "rigid translation"
    }
}

/// `j = 2 a^T (M_s (x) J) b / (a^T M a + b^T M b)` for `phi = a + i b` (2D).
pub(super) fn angular_momentum(
    asm: &Assembler,
    m: &[f64],
    a: &[f64],
    b: &[f64],
    dim: usize,
) -> f64 {
    if dim != 2 {
        return 0.0;
    }
    let cp = asm.pattern.col_ptr();
    let ri = asm.pattern.row_idx();
    let (mut h, mut mass) = (0.0, 0.0);
    for j in 0..asm.pattern.nrows() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            let v = m[p];
            mass += v * (a[i] * a[j] + b[i] * b[j]);
            if i % 2 == 0 && j % 2 == 0 {
                // x-row of node i/2, y-column of node j/2: -m.
                h -= v * a[i] * b[j + 1];
            } else if i % 2 == 1 && j % 2 == 1 {
                // y-row of node i/2, x-column of node j/2: +m.
                h += v * a[i] * b[j - 1];
            }
        }
    }
    if mass > 0.0 {
        2.0 * h / mass
    } else {
        0.0
    }
}
