//! Natural frequencies and mode shapes of the wheel, at rest and spinning
//! (DESIGN §5: `softway modes`).
//!
//! Both analyses are dense: the matrices restricted to the free degrees of freedom are
//! copied into dense `faer` matrices, so they are meant for the paper's meshes (a few
//! thousand dofs). Larger models are refused up front with [`ModesError::TooLarge`]
//! ([`MAX_DENSE_DOFS`], [`MAX_SPINNING_DOFS`]) instead of running for hours.
//!
//! ## At rest ([`natural_modes`])
//!
//! On the free dofs (the supported dofs removed), the undamped free vibration
//! `u = phi cos(w t)` of `M u'' + K u = 0` gives the generalized symmetric eigenproblem
//! $$K \varphi = \omega^2 M \varphi .$$
//! With the Cholesky factor `M = L L^T` it becomes the standard symmetric problem
//! $$\tilde K q = \omega^2 q,\qquad \tilde K = L^{-1} K L^{-T},\qquad \varphi = L^{-T} q,$$
//! solved by `faer`'s self-adjoint eigensolver. `K` is the elastic stiffness
//! ([`WheelModel::k_elastic`]), without the rotating-frame terms. Frequencies are
//! `f = omega / (2 pi)` (Hz), periods `T = 1 / f` (reported in microseconds).
//!
//! A mode whose `omega` is below [`ZERO_FREQUENCY_RATIO`] times the highest `omega` of the
//! model is a zero-frequency (rigid) mode: it is listed with `frequency_hz = 0` and an
//! infinite period, classified by its shape (`"rigid rotation"`, `"rigid translation"` or
//! `"zero-energy mechanism"`), and not counted among the elastic modes asked for.
//!
//! ## Spinning ([`spinning_modes`], [`spinning_analysis`])
//!
//! In the wheel's rotating frame ([`crate::frame`]) the motion about the spinning
//! equilibrium obeys `M u'' + C u' + K_eff u = 0`, with `C = G` (+ the external damping, if
//! any), `G = 2 Omega (M_s (x) J)` skew-symmetric (Coriolis) and
//! `K_eff = K + K_sigma - Omega^2 M`. With `u = phi e^{lambda t}` this is the quadratic
//! eigenproblem
//! $$\big(K_{\rm eff} + \lambda C + \lambda^2 M\big)\varphi = 0 .$$
//! It is solved in the state-space form of size `2n`: with `q = L^T u`,
//! `\tilde K = L^{-1} K_eff L^{-T}`, `\tilde C = L^{-1} C L^{-T}` and `z = [a q, q']`,
//! $$z' = A z,\qquad A = \begin{pmatrix} 0 & a I \\ -\tilde K / a & -\tilde C \end{pmatrix},$$
//! where the scale `a = sqrt(max diag K~)` balances the two blocks (the eigenvalues do not
//! depend on it). `faer`'s dense real eigensolver gives the `2n` eigenvalues `lambda`; the
//! frequency in the rotating frame is `|Im lambda| / (2 pi)` and `Re lambda` is the growth
//! rate (negative: decaying). Without damping, with `K_eff` positive semi-definite, the
//! gyroscopic system is marginally stable: every `lambda` is imaginary.
//!
//! **Splitting of paired modes.** A disk has pairs of equal rest frequencies (modes with
//! `n >= 1` waves around the circumference, `cos n theta` and `sin n theta`). Premultiplying
//! the quadratic problem by `phi^H` at `lambda = i omega` gives
//! $$\omega^2 m + 2\Omega h\,\omega - k = 0,\qquad m = \varphi^H M \varphi,\quad
//!   h = \operatorname{Im}\varphi^H (M_s\otimes J)\varphi,\quad k = \varphi^H K_{\rm eff}\varphi,$$
//! so a mode whose material points orbit (in the rotating frame) in the sense of the frame
//! rotation (`Omega h > 0`, **forward** whirl) is lowered by about `Omega h / m`, and the
//! opposite one (**backward** whirl) raised by as much: the pair splits linearly in
//! `Omega`. The normalized modal angular momentum `j = h / m` lies in `[-1, 1]`
//! ([`SpinMode::angular_momentum`]).
//!
//! ## Numerical notes
//!
//! - The dense eigensolvers of faer 0.24 are scale-sensitive: on the wheel's
//!   `L^-1 K L^-T` (entries ~1e12) the self-adjoint solver returned eigenvectors with
//!   relative residuals of 1e-3 (the eigenvalues alone were right). Every matrix is
//!   therefore scaled to unit max-norm before the eigensolver, and every reported
//!   eigenpair is checked (`max |A z - lambda z| / |z| <= 1e-8` on the scaled matrix,
//!   [`ModesError::Inaccurate`] otherwise).
//! - The nonsymmetric solver returns wrong eigenvectors for repeated eigenvalues (the
//!   pairs of equal frequencies of the disk without spin): such eigenvectors are recomputed
//!   by two steps of inverse iteration on the pencil `K~ + mu C~ + mu^2 I` (complex LU).
//! - `faer`'s `generalized_eigen` (QZ) panicked on the wheel's `(K, M)` (integer overflow
//!   in `qz_real`), hence the Cholesky reduction.
//!
//! ## The paper's wheel (study in `tests/modes.rs`, consistent mass, plane stress)
//!
//! Lowest elastic frequencies, Hz (`n`: waves around the rim; pairs listed once):
//!
//! | support \ rings                    | 12      | 18      | 24      | 30      |
//! |-------------------------------------|---------|---------|---------|---------|
//! | pinned, `n = 1` (artefact)          | 4587.4  | 4352.2  | 4205.5  | 4101.3  |
//! | pinned = free disk, `n = 2`         | 11895.7 | 11868.4 | 11858.7 | 11854.2 |
//! | pinned, second `n = 1`              | 15057.0 | 14884.1 | 14792.1 | 14732.5 |
//! | pinned = free disk, `n = 0`         | 17516.6 | 17502.2 | 17497.1 | 17494.8 |
//!
//! With the centre pinned, every mode with `n != 1` is exactly a mode of the free disk (it
//! does not move the centre); the `n = 1` pairs push the disk against the pin, whose
//! stiffness vanishes under refinement: the lowest pair falls as `1 / f^2 ~ ln(rings)`
//! with 70-76 % of its strain energy within 2.5 cm of the pin, an artefact of the mesh.
//! A hub clamp converges (1 cm hub on 10 / 20 / 30 rings, where the hub circle is a ring:
//! torsion `n = 0` 1486.8 / 1464.9 / 1456.4 Hz, `n = 1` 6451.9 / 6417.0 / 6407.2 Hz,
//! `n = 2` 12294.2 / 12219.8 / 12202.2 Hz), but the clamped radius is that of the outermost
//! ring inside the hub radius: 1 cm clamps ring 1 (8.33 mm) of the 12-ring mesh and only
//! 5.56 mm on 18 rings, and the hub modes follow it.
//!
//! The paper's "first eigenform, period about 80 us" is the ovalisation pair `n = 2`:
//! 84.1 us on the paper's mesh (pinned or free; 84.4 us converged), 82.3 us with the
//! 8.33 mm hub of the 12-ring mesh, 82.0 us with a true 1 cm hub. The lowest modes of the
//! supported wheel are others (pinned: the `n = 1` artefact, 218 us; hub: torsion about
//! the hub, 811 us, and `n = 1`, 162 us).
//!
//! [`WheelModel::k_elastic`]: crate::wheel::WheelModel::k_elastic

use std::path::{Path, PathBuf};

use faer::linalg::solvers::LltError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatRef, Par, Side};

use crate::assembly::Assembler;
use crate::mesh::Mesh;
use crate::output::vtk::{write_vtu, Field, PvdWriter, VtkError};
use crate::wheel::WheelModel;

/// Largest number of free dofs accepted by the dense rest analysis ([`natural_modes`]):
/// about 300 MB per dense matrix at this size (measured on 2 cores: 936 dofs, the paper's
/// 12-ring disk, 0.5 s; 3600 dofs, 24 rings, 20 s; 5580 dofs, 30 rings, about 1 min).
pub const MAX_DENSE_DOFS: usize = 6000;

/// Largest number of free dofs accepted by the dense spinning analysis
/// ([`spinning_modes`]), whose state-space matrix has twice as many rows and is solved by
/// the slower nonsymmetric eigensolver (measured on 2 cores: 936 dofs, 12 rings, 17 s;
/// 2040 dofs, 18 rings, 2.7 min).
pub const MAX_SPINNING_DOFS: usize = 2100;

/// A mode is of zero frequency when its circular frequency is below this fraction of the
/// highest one of the model.
pub const ZERO_FREQUENCY_RATIO: f64 = 1e-6;

/// Two rest frequencies closer than this relative difference form a pair (a degenerate
/// eigenvalue, e.g. the `cos n theta` / `sin n theta` modes of a disk).
pub const PAIR_TOLERANCE: f64 = 1e-6;

/// One natural mode at rest.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Mode {
    /// Natural frequency `f = omega / (2 pi)`, Hz (0 for a rigid mode).
    pub frequency_hz: f64,
    /// Period `1 / f`, microseconds (infinite for a rigid mode).
    pub period_us: f64,
    /// The mode shape over all dofs of the model (node-major, `dim` per node), zero on the
    /// fixed dofs, normalised so that `max |u| = 1`, the largest component positive.
    #[serde(skip)]
    pub shape: Vec<f64>,
    /// `"elastic"`, `"rigid rotation"`, `"rigid translation"`, `"zero-energy mechanism"`
    /// or `"negative stiffness"` (a divergent mode of an indefinite stiffness).
    pub kind: String,
    /// For a disk ([`natural_modes`]): the number of waves `n` around the circumference
    /// (nodal diameters), the dominant term of a Fourier analysis of the rim displacement
    /// (`0`: breathing or torsion, `1`: translation of the disk against its support, `2`:
    /// ovalisation, ...). `None` for other models or a mode that does not move the rim.
    pub wavenumber: Option<usize>,
}

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
    /// Whether that rest mode is one of a pair of equal frequencies ([`PAIR_TOLERANCE`]).
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

/// The modes of a wheel model, for `softway modes`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModesReport {
    /// The rest modes ([`natural_modes`]).
    pub at_rest: Vec<Mode>,
    /// The modes of the spinning wheel in the rotating frame ([`spinning_modes`]), when the
    /// model spins and is small enough.
    pub spinning: Option<Vec<SpinMode>>,
    /// Number of dofs of the model.
    pub dofs: usize,
    /// Number of free (unsupported) dofs, the size of the rest eigenproblem.
    pub free_dofs: usize,
    /// Why an analysis was skipped, if one was.
    pub notes: Vec<String>,
}

/// Errors of the modal analyses.
#[derive(Debug, thiserror::Error)]
pub enum ModesError {
    /// Too many free dofs for a dense eigenproblem.
    #[error(
        "the {analysis} analysis is dense and accepts at most {limit} free degrees of freedom; \
         this model has {dofs} (memory grows as n^2, time as n^3): use a coarser mesh \
         (fewer rings)"
    )]
    TooLarge {
        /// `"rest"` or `"spinning"`.
        analysis: &'static str,
        /// Free dofs of the model.
        dofs: usize,
        /// The limit.
        limit: usize,
    },
    /// Every dof is fixed.
    #[error("the model has no free degree of freedom")]
    NoFreeDofs,
    /// A fixed dof does not exist.
    #[error("fixed dof {dof} is out of range: the model has {dofs} dofs")]
    FixedDofOutOfRange {
        /// The dof.
        dof: usize,
        /// Number of dofs of the model.
        dofs: usize,
    },
    /// A matrix does not fit the pattern.
    #[error("the {matrix} matrix has {len} values, the pattern {expected}")]
    MatrixSize {
        /// `"mass"`, `"stiffness"` or `"damping"`.
        matrix: &'static str,
        /// Values given.
        len: usize,
        /// Values expected.
        expected: usize,
    },
    /// A matrix holds NaN or infinity.
    #[error("the {matrix} matrix holds a value that is not finite")]
    NotFinite {
        /// `"mass"`, `"stiffness"` or `"damping"`.
        matrix: &'static str,
    },
    /// The mass matrix is not positive definite on the free dofs.
    #[error(
        "the mass matrix is not positive definite on the free dofs (Cholesky pivot {index}): \
         a free node without mass, or a non-positive density?"
    )]
    MassNotPositive {
        /// The failing pivot (free-dof index).
        index: usize,
    },
    /// The eigensolver did not converge.
    #[error("the dense {0} eigensolver did not converge")]
    NoConvergence(&'static str),
    /// An eigenpair failed the residual check (a defect of the dense eigensolver).
    #[error(
        "the dense {solver} eigensolver returned an inaccurate eigenpair (relative residual \
         {residual:e})"
    )]
    Inaccurate {
        /// Which solver.
        solver: &'static str,
        /// `max |A z - lambda z| / |z|` on the unit-scaled matrix.
        residual: f64,
    },
    /// Writing a file failed.
    #[error("cannot write {}: {source}", .path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// Writing a VTK file failed.
    #[error(transparent)]
    Vtk(#[from] VtkError),
}

/// The matrices of a generic model for [`natural_modes_of`]: `M` and `K` on the pattern of
/// `assembler`, the supported dofs, and the mesh (for classifying rigid modes).
#[derive(Debug, Clone, Copy)]
pub struct Matrices<'a> {
    /// The mesh (reference positions).
    pub mesh: &'a Mesh,
    /// Pattern of the matrices.
    pub assembler: &'a Assembler,
    /// Mass matrix values.
    pub m: &'a [f64],
    /// Stiffness matrix values.
    pub k: &'a [f64],
    /// Supported (fixed) dofs, any order, repeats allowed.
    pub fixed_dofs: &'a [usize],
}

/// The rest modes of the wheel: `K phi = omega^2 M phi` on the free dofs, with the elastic
/// stiffness `K` ([`WheelModel::k_elastic`]) and the model's mass matrix.
///
/// Returns the zero-frequency (rigid) modes, then the `count` lowest elastic modes (fewer
/// if the model has fewer), by increasing frequency; each elastic mode carries its number
/// of circumferential waves ([`Mode::wavenumber`]).
///
/// # Errors
/// [`ModesError::TooLarge`] past [`MAX_DENSE_DOFS`] free dofs, [`ModesError::NoFreeDofs`],
/// [`ModesError::MassNotPositive`], [`ModesError::NotFinite`],
/// [`ModesError::NoConvergence`].
pub fn natural_modes(model: &WheelModel, count: usize) -> Result<Vec<Mode>, ModesError> {
    let mut modes = natural_modes_of(&wheel_matrices(model), count)?;
    for mode in &mut modes {
        if mode.kind == "elastic" {
            mode.wavenumber = rim_wavenumber(model, &mode.shape);
        }
    }
    Ok(modes)
}

/// [`natural_modes`] for any model given by its matrices (`wavenumber` is left `None`).
///
/// # Errors
/// As [`natural_modes`], plus [`ModesError::MatrixSize`] and
/// [`ModesError::FixedDofOutOfRange`] for inconsistent input.
pub fn natural_modes_of(sys: &Matrices, count: usize) -> Result<Vec<Mode>, ModesError> {
    let n = sys.assembler.pattern.nrows();
    check_values(sys.assembler, sys.m, "mass")?;
    check_values(sys.assembler, sys.k, "stiffness")?;
    let free = FreeDofs::new(n, sys.fixed_dofs)?;
    free.check_size("rest", MAX_DENSE_DOFS)?;
    let par = faer::get_global_parallelism();
    let l = cholesky_mass(sys.assembler, sys.m, &free)?;
    let (kt, scale) = unit_scaled(congruence(
        l.as_ref(),
        free.dense(sys.assembler, sys.k),
        par,
        true,
    ));
    let evd = kt
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| ModesError::NoConvergence("self-adjoint"))?;
    let mu: Vec<f64> = (0..free.len())
        .map(|i| scale * evd.S().column_vector()[i])
        .collect();
    let omega_max = mu.iter().copied().fold(0.0, f64::max).sqrt();
    let tol = ZERO_FREQUENCY_RATIO * omega_max;

    // Pick the modes: every zero or negative one, then `count` elastic ones.
    let mut picked: Vec<(usize, Option<&'static str>)> = Vec::new();
    let mut elastic = 0;
    for (i, &m) in mu.iter().enumerate() {
        let w = m.abs().sqrt();
        if m < 0.0 && w >= tol {
            picked.push((i, Some("negative stiffness")));
        } else if w < tol || omega_max == 0.0 {
            picked.push((i, Some("rigid")));
        } else if elastic < count {
            picked.push((i, None));
            elastic += 1;
        } else {
            break;
        }
    }
    // Shapes phi = L^-T q, all picked columns at once, after checking the residuals.
    let mut q = Mat::<f64>::zeros(free.len(), picked.len());
    for (c, &(i, _)) in picked.iter().enumerate() {
        q.col_mut(c).copy_from(evd.U().col(i));
    }
    let r = &kt * &q;
    for (c, &(i, _)) in picked.iter().enumerate() {
        let mu_i = evd.S().column_vector()[i];
        let res = (0..free.len())
            .map(|f| (r[(f, c)] - mu_i * q[(f, c)]).abs())
            .fold(0.0, f64::max);
        check_residual(
            "self-adjoint",
            res / q.col(c).norm_l2().max(f64::MIN_POSITIVE),
        )?;
    }
    solve_upper_triangular_in_place(l.as_ref().transpose(), q.as_mut(), par);

    let mut modes = Vec::with_capacity(picked.len());
    for (c, &(i, special)) in picked.iter().enumerate() {
        let mut shape = vec![0.0; n];
        for (f, &dof) in free.dofs.iter().enumerate() {
            shape[dof] = q[(f, c)];
        }
        normalise(&mut shape);
        let w = mu[i].abs().sqrt();
        let (frequency_hz, kind) = match special {
            Some("rigid") => (0.0, rigid_kind(sys.mesh, &shape).to_string()),
            Some(other) => (w / (2.0 * std::f64::consts::PI), other.to_string()),
            None => (w / (2.0 * std::f64::consts::PI), "elastic".to_string()),
        };
        modes.push(Mode {
            frequency_hz,
            period_us: period_us(frequency_hz),
            shape,
            kind,
            wavenumber: None,
        });
    }
    Ok(modes)
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
        let (best, paired) = rest.nearest(qre.as_ref());
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
    fn nearest(&self, qre: MatRef<'_, f64>) -> (usize, bool) {
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
        let near = |k: usize| (self.w[k] - wb).abs() <= PAIR_TOLERANCE * wb;
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
fn zero_frequency_modes(eigenvalues: &[[f64; 2]], tol: f64) -> Vec<SpinMode> {
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

/// Rest modes, and the spinning modes when the model spins (rotating frame, `omega != 0`)
/// and has at most [`MAX_SPINNING_DOFS`] free dofs (otherwise a note says why not).
///
/// # Errors
/// As [`natural_modes`]; a spinning analysis that fails for another reason than its size.
pub fn modes_report(model: &WheelModel, count: usize) -> Result<ModesReport, ModesError> {
    let at_rest = natural_modes(model, count)?;
    let n = model.mesh.n_dofs();
    let free_dofs = FreeDofs::new(n, &model.fixed_dofs)?.len();
    let mut notes = Vec::new();
    let spinning = if model.spec.rotating_frame && model.spec.omega != 0.0 {
        match spinning_modes(model, count) {
            Ok(m) => Some(m),
            Err(e @ ModesError::TooLarge { .. }) => {
                notes.push(format!("spinning modes skipped: {e}"));
                None
            }
            Err(e) => return Err(e),
        }
    } else {
        notes.push("spinning modes skipped: the wheel does not spin (omega = 0)".to_string());
        None
    };
    Ok(ModesReport {
        at_rest,
        spinning,
        dofs: n,
        free_dofs,
        notes,
    })
}

/// Writes one `.vtu` per mode (`mode_001.vtu`, ...: the point field `"mode_shape"`, `dim`
/// components per node), `modes.pvd` indexing them by mode number (the "time" of an entry
/// is its 1-based mode number, so ParaView's time control steps through the modes) and
/// `modes.csv` (`index,frequency_hz,period_us,kind`, `index` the mode number) into `dir`,
/// created if missing. Returns the paths written, `.vtu` files first.
///
/// # Errors
/// [`ModesError::Io`] if `dir` cannot be created or a file written, [`ModesError::Vtk`]
/// (e.g. a shape of the wrong length).
pub fn write_mode_shapes(
    model: &WheelModel,
    modes: &[Mode],
    dir: &Path,
) -> Result<Vec<PathBuf>, ModesError> {
    write_mode_shapes_of(&model.mesh, modes, dir)
}

/// [`write_mode_shapes`] for any mesh.
///
/// # Errors
/// As [`write_mode_shapes`].
pub fn write_mode_shapes_of(
    mesh: &Mesh,
    modes: &[Mode],
    dir: &Path,
) -> Result<Vec<PathBuf>, ModesError> {
    std::fs::create_dir_all(dir).map_err(|source| ModesError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut written = Vec::with_capacity(modes.len() + 2);
    let mut pvd = PvdWriter::new();
    let mut csv = String::from("index,frequency_hz,period_us,kind\n");
    let width = modes.len().to_string().len().max(3);
    for (i, mode) in modes.iter().enumerate() {
        let number = i + 1;
        let name = format!("mode_{number:0width$}.vtu");
        let path = dir.join(&name);
        let field = Field {
            name: "mode_shape",
            components: mesh.dim,
            values: &mode.shape,
        };
        write_vtu(&path, mesh, None, &[field], &[])?;
        pvd.add(number as f64, name);
        written.push(path);
        csv.push_str(&format!(
            "{number},{:e},{:e},\"{}\"\n",
            mode.frequency_hz,
            mode.period_us,
            mode.kind.replace('"', "\"\"")
        ));
    }
    let pvd_path = dir.join("modes.pvd");
    pvd.write(&pvd_path)?;
    written.push(pvd_path);
    let csv_path = dir.join("modes.csv");
    crate::output::files::write_atomic(&csv_path, csv.as_bytes()).map_err(|source| {
        ModesError::Io {
            path: csv_path.clone(),
            source,
        }
    })?;
    written.push(csv_path);
    Ok(written)
}

/// The number of circumferential waves of a disk mode: the dominant Fourier term `n` of
/// the radial and tangential displacement of the rim nodes (by their angles),
/// `P_n = |sum u_r e^{-i n theta}|^2 + |sum u_t e^{-i n theta}|^2`, `n = 0..=N/2`.
/// `None` if the rim does not move.
pub fn rim_wavenumber(model: &WheelModel, shape: &[f64]) -> Option<usize> {
    let rim = &model.rim;
    if rim.is_empty() || shape.len() != model.mesh.n_dofs() || model.mesh.dim != 2 {
        return None;
    }
    let mut best = (0.0, None);
    let mut total = 0.0;
    for k in 0..=rim.len() / 2 {
        let (mut rc, mut rs, mut tc, mut ts) = (0.0, 0.0, 0.0, 0.0);
        for &node in rim {
            let [x, y] = model.mesh.points[node];
            let th = y.atan2(x);
            let (ux, uy) = (shape[2 * node], shape[2 * node + 1]);
            let ur = ux * th.cos() + uy * th.sin();
            let ut = -ux * th.sin() + uy * th.cos();
            let (s, c) = (k as f64 * th).sin_cos();
            rc += ur * c;
            rs += ur * s;
            tc += ut * c;
            ts += ut * s;
        }
        let p = rc * rc + rs * rs + tc * tc + ts * ts;
        total += p;
        if p > best.0 {
            best = (p, Some(k));
        }
    }
    if total > 0.0 {
        best.1
    } else {
        None
    }
}

/// The wheel's rest matrices.
fn wheel_matrices(model: &WheelModel) -> Matrices<'_> {
    Matrices {
        mesh: &model.mesh,
        assembler: &model.model.assembler,
        m: &model.model.m,
        k: &model.k_elastic,
        fixed_dofs: &model.fixed_dofs,
    }
}

fn check_values(asm: &Assembler, values: &[f64], matrix: &'static str) -> Result<(), ModesError> {
    if values.len() != asm.nnz() {
        return Err(ModesError::MatrixSize {
            matrix,
            len: values.len(),
            expected: asm.nnz(),
        });
    }
    if values.iter().any(|v| !v.is_finite()) {
        return Err(ModesError::NotFinite { matrix });
    }
    Ok(())
}

/// The free dofs and the map from a dof to its free index.
struct FreeDofs {
    dofs: Vec<usize>,
    index: Vec<Option<usize>>,
}

impl FreeDofs {
    fn new(n: usize, fixed: &[usize]) -> Result<Self, ModesError> {
        let mut is_fixed = vec![false; n];
        for &d in fixed {
            *is_fixed
                .get_mut(d)
                .ok_or(ModesError::FixedDofOutOfRange { dof: d, dofs: n })? = true;
        }
        let dofs: Vec<usize> = (0..n).filter(|&d| !is_fixed[d]).collect();
        let mut index = vec![None; n];
        for (f, &d) in dofs.iter().enumerate() {
            index[d] = Some(f);
        }
        if dofs.is_empty() {
            return Err(ModesError::NoFreeDofs);
        }
        Ok(Self { dofs, index })
    }

    fn len(&self) -> usize {
        self.dofs.len()
    }

    fn check_size(&self, analysis: &'static str, limit: usize) -> Result<(), ModesError> {
        if self.len() > limit {
            return Err(ModesError::TooLarge {
                analysis,
                dofs: self.len(),
                limit,
            });
        }
        Ok(())
    }

    /// The dense free-free block of a matrix on the pattern of `asm`.
    fn dense(&self, asm: &Assembler, values: &[f64]) -> Mat<f64> {
        let nf = self.len();
        let mut a = Mat::<f64>::zeros(nf, nf);
        let cp = asm.pattern.col_ptr();
        let ri = asm.pattern.row_idx();
        for (j, fj) in self.index.iter().enumerate() {
            let Some(fj) = *fj else { continue };
            for p in cp[j]..cp[j + 1] {
                if let Some(fi) = self.index[ri[p]] {
                    a[(fi, fj)] += values[p];
                }
            }
        }
        a
    }
}

/// The lower Cholesky factor `L` of the free-free mass block.
fn cholesky_mass(asm: &Assembler, m: &[f64], free: &FreeDofs) -> Result<Mat<f64>, ModesError> {
    let llt = free.dense(asm, m).llt(Side::Lower).map_err(|e| match e {
        LltError::NonPositivePivot { index } => ModesError::MassNotPositive { index },
    })?;
    Ok(llt.L().to_owned())
}

/// `L^-1 A L^-T` (symmetrised when `symmetric`).
fn congruence(l: MatRef<'_, f64>, mut a: Mat<f64>, par: Par, symmetric: bool) -> Mat<f64> {
    solve_lower_triangular_in_place(l, a.as_mut(), par); // L^-1 A
    let mut b = a.transpose().to_owned(); // A^T L^-T
    drop(a);
    solve_lower_triangular_in_place(l, b.as_mut(), par); // L^-1 A^T L^-T = (L^-1 A L^-T)^T
    let n = b.nrows();
    if symmetric {
        for j in 0..n {
            for i in j + 1..n {
                let s = 0.5 * (b[(i, j)] + b[(j, i)]);
                b[(i, j)] = s;
                b[(j, i)] = s;
            }
        }
        b
    } else {
        b.transpose().to_owned()
    }
}

/// Largest accepted residual `max_i |(A z - lambda z)_i| / |z|` of an eigenpair of the
/// unit-scaled matrix.
const MAX_RESIDUAL: f64 = 1e-8;

fn check_residual(solver: &'static str, residual: f64) -> Result<(), ModesError> {
    if residual.is_finite() && residual <= MAX_RESIDUAL {
        Ok(())
    } else {
        Err(ModesError::Inaccurate { solver, residual })
    }
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

/// `A / max |a_ij|` and the scale `max |a_ij|` (1 for a zero matrix).
///
/// The dense eigensolvers of faer 0.24 lose accuracy on matrices with large entries (the
/// self-adjoint one returned eigenvectors with residuals of 1e-3 relative on the wheel's
/// `L^-1 K L^-T`, entries ~1e12), so the matrices are scaled to unit size first.
fn unit_scaled(mut a: Mat<f64>) -> (Mat<f64>, f64) {
    let s = a.norm_max();
    if s > 0.0 && s.is_finite() {
        a *= faer::Scale(1.0 / s);
        (a, s)
    } else {
        (a, 1.0)
    }
}

/// Scales `u` to `max |u_i| = 1` with its largest component positive.
fn normalise(u: &mut [f64]) {
    let (mut big, mut at) = (0.0, 0);
    for (i, v) in u.iter().enumerate() {
        if v.abs() > big {
            (big, at) = (v.abs(), i);
        }
    }
    if big > 0.0 {
        let s = u[at].signum() / big;
        u.iter_mut().for_each(|v| *v *= s);
    }
}

fn period_us(frequency_hz: f64) -> f64 {
    if frequency_hz > 0.0 {
        1e6 / frequency_hz
    } else {
        f64::INFINITY
    }
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
fn rigid_kind(mesh: &Mesh, u: &[f64]) -> &'static str {
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
        .points
        .iter()
        .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
    let c = [c[0] / nn as f64, c[1] / nn as f64];
    // Orthogonal basis: tx, ty, rotation about the centroid (orthogonal to both).
    let (mut tx, mut ty, mut rot, mut r2) = (0.0, 0.0, 0.0, 0.0);
    for (i, p) in mesh.points.iter().enumerate() {
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
fn angular_momentum(asm: &Assembler, m: &[f64], a: &[f64], b: &[f64], dim: usize) -> f64 {
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

/// The bounce of the wheel: the lowest mode with vertical translation, the disk moving
/// between its support (pin or hub) and the contact held on the base.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bounce {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// The mode's effective mass in vertical translation over the total mass (1: a rigid
    /// disk on two springs).
    pub vertical_mass_fraction: f64,
    /// Rim nodes held (their vertical dof) as the static contact patch.
    pub held_nodes: usize,
}

/// The bounce mode of the wheel pressed to the flattening `d` (m) on a base below it: the
/// rim nodes whose undeformed position lies beyond the base line `y = -(R - d)` (at least
/// the lowest one) are held vertically, the support as in the model, and among the lowest
/// modes of `K phi = omega^2 M phi` (elastic stiffness [`WheelModel::k_elastic`], the
/// model's mass) the bounce is the one with the largest effective mass in vertical
/// translation, `(phi^T M e_y)^2 / (phi^T M phi  e_y^T M e_y)`. With a pinned centre it is
/// the lowest mode (the point support is soft); with a clamped hub lower flexural modes
/// come first, so the modes are found by subspace iteration: [`BOUNCE_SUBSPACE`] vectors
/// (vertical and horizontal loads modulated by `cos j theta`, `sin (j+1) theta`), twelve
/// iterations `Phi <- K^{-1} M Phi` with one sparse factorization of `K`, each followed by a
/// Rayleigh-Ritz projection. Sparse: any mesh size.
///
/// # Errors
/// [`ModesError::NotFinite`] when `K` with the held dofs is singular;
/// [`ModesError::MassNotPositive`] or [`ModesError::NoConvergence`] from the projected
/// problem.
pub fn bounce_mode(model: &WheelModel, d: f64) -> Result<Bounce, ModesError> {
    use crate::linalg::{spmv_into, Factor};
    let n = model.mesh.n_dofs();
    let r = model.spec.radius;
    let pts = &model.mesh.points;
    let lowest = model
        .rim
        .iter()
        .copied()
        .min_by(|&a, &b| pts[a][1].total_cmp(&pts[b][1]));
    let mut held: Vec<usize> = model
        .rim
        .iter()
        .copied()
        .filter(|&i| pts[i][1] <= -(r - d))
        .collect();
    if held.is_empty() {
        held.extend(lowest);
    }
    let mut fixed = vec![false; n];
    for &dof in &model.fixed_dofs {
        fixed[dof] = true;
    }
    for &i in &held {
        fixed[2 * i + 1] = true;
    }
    let pattern = model.model.pattern();
    let (m, k) = (&model.model.m, &model.k_elastic);
    let mut kf = k.clone();
    crate::linalg::set_identity_rows(pattern, &mut kf, &fixed);
    let mut lu = Factor::auto(pattern, &kf).map_err(|_| ModesError::NotFinite {
        matrix: "stiffness",
    })?;
    let q = BOUNCE_SUBSPACE
        .min(fixed.iter().filter(|f| !**f).count())
        .max(1);
    // Start: vertical and horizontal loads modulated around the disk.
    let mut phi: Vec<Vec<f64>> = (0..q)
        .map(|c| {
            let (j, comp, sine) = (c / 4, (c / 2) % 2, c % 2 == 1);
            (0..n)
                .map(|dof| {
                    let p = pts[dof / 2];
                    let th = p[1].atan2(p[0]);
                    let w = if sine {
                        ((j + 1) as f64 * th).sin()
                    } else {
                        (j as f64 * th).cos()
                    };
                    if dof % 2 == 1 - comp && !fixed[dof] {
                        w
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    let mut tmp = vec![0.0; n];
    let mut ritz = (Vec::new(), Mat::<f64>::zeros(0, 0));
    for _ in 0..12 {
        for v in phi.iter_mut() {
            spmv_into(pattern, m, v, &mut tmp);
            for (t, &fx) in tmp.iter_mut().zip(&fixed) {
                if fx {
                    *t = 0.0;
                }
            }
            lu.solve_in_place(&mut tmp);
            v.copy_from_slice(&tmp);
        }
        ritz = rayleigh_ritz(pattern, m, k, &phi)?;
        // Phi <- Phi Y (the Ritz vectors, M-orthonormal).
        let y = &ritz.1;
        let old = phi.clone();
        for (c, v) in phi.iter_mut().enumerate() {
            for i in 0..n {
                v[i] = (0..q).map(|b| old[b][i] * y[(b, c)]).sum();
            }
        }
    }
    // The Ritz vector with the largest vertical effective mass.
    let ey: Vec<f64> = (0..n).map(|i| (i % 2) as f64).collect();
    let mut mey = vec![0.0; n];
    spmv_into(pattern, m, &ey, &mut mey);
    let mee: f64 = mey.iter().zip(&ey).map(|(a, b)| a * b).sum();
    let (mut best, mut frac) = (0, -1.0);
    for (c, v) in phi.iter().enumerate() {
        // M-orthonormal: phi^T M phi = 1.
        let g: f64 = v.iter().zip(&mey).map(|(a, b)| a * b).sum();
        let f = g * g / mee;
        if f > frac {
            (best, frac) = (c, f);
        }
    }
    let omega2 = ritz.0.get(best).copied().unwrap_or(0.0);
    Ok(Bounce {
        frequency_hz: omega2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
        vertical_mass_fraction: frac,
        held_nodes: held.len(),
    })
}

/// Vectors of the subspace iteration of [`bounce_mode`].
pub const BOUNCE_SUBSPACE: usize = 16;

/// Rayleigh-Ritz on the columns `phi`: the eigenvalues `omega^2` of the projected problem
/// (increasing) and the coefficients `Y` of its M-orthonormal eigenvectors (`Phi Y`).
fn rayleigh_ritz(
    pattern: &crate::linalg::Pattern,
    m: &[f64],
    k: &[f64],
    phi: &[Vec<f64>],
) -> Result<(Vec<f64>, Mat<f64>), ModesError> {
    use crate::linalg::spmv_into;
    let q = phi.len();
    let n = phi.first().map_or(0, |v| v.len());
    let mut mp = vec![vec![0.0; n]; q];
    let mut kp = vec![vec![0.0; n]; q];
    for c in 0..q {
        spmv_into(pattern, m, &phi[c], &mut mp[c]);
        spmv_into(pattern, k, &phi[c], &mut kp[c]);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut bm = Mat::<f64>::from_fn(q, q, |i, j| dot(&phi[i], &mp[j]));
    let am = Mat::<f64>::from_fn(q, q, |i, j| {
        0.5 * (dot(&phi[i], &kp[j]) + dot(&phi[j], &kp[i]))
    });
    for j in 0..q {
        for i in j + 1..q {
            let s = 0.5 * (bm[(i, j)] + bm[(j, i)]);
            bm[(i, j)] = s;
            bm[(j, i)] = s;
        }
    }
    let l = bm
        .llt(Side::Lower)
        .map_err(|e| match e {
            LltError::NonPositivePivot { index } => ModesError::MassNotPositive { index },
        })?
        .L()
        .to_owned();
    let c = congruence(l.as_ref(), am, Par::Seq, true);
    let evd = c
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| ModesError::NoConvergence("self-adjoint"))?;
    let vals: Vec<f64> = (0..q).map(|i| evd.S().column_vector()[i]).collect();
    let mut y = evd.U().to_owned();
    solve_upper_triangular_in_place(l.as_ref().transpose(), y.as_mut(), Par::Seq);
    Ok((vals, y))
}
