//! Natural frequencies and mode shapes of the wheel, at rest and spinning (`softway modes`).
//!
//! `softway modes` ([`modes_report`]) finds the lowest modes by shift-invert on the sparse
//! factorizations, at any size ([`natural_modes_sparse`], [`spinning_modes_sparse`]; the
//! module `sparse`). The dense analyses below ([`natural_modes`], [`spinning_modes`]) solve
//! the whole eigenproblem and are their reference (`tests/sparse_modes.rs`: the same
//! frequencies to 1e-8); they copy the matrices restricted to the free degrees of freedom
//! into dense `faer` matrices, so they are meant for a few thousand dofs, and larger models
//! are refused up front with [`ModesError::TooLarge`] ([`MAX_DENSE_DOFS`],
//! [`MAX_SPINNING_DOFS`]) instead of running for hours.
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
//! $$z\' = A z,\qquad A = \begin{pmatrix} 0 & a I \\\\ -\tilde K / a & -\tilde C \end{pmatrix},$$
//! where the scale `a = sqrt(max diag K~)` balances the two blocks (the eigenvalues do not
//! depend on it). `faer`'s dense real eigensolver gives the `2n` eigenvalues `lambda`; the
//! frequency in the rotating frame is `|Im lambda| / (2 pi)` and `Re lambda` is the growth
//! rate (negative: decaying). Without damping, with `K_eff` positive semi-definite, the
//! gyroscopic system is marginally stable: every `lambda` is imaginary.
//!
//! **Splitting of paired modes.** A disk has pairs of equal rest frequencies (modes with
//! `n >= 1` waves around the circumference, `cos n theta` and `sin n theta`). Premultiplying
//! the quadratic problem by `phi^H` at `lambda = i omega` gives
//! $$\omega^2 m + 2\Omega h\\,\omega - k = 0,\qquad m = \varphi^H M \varphi,\quad
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
//! [`WheelModel::k_elastic`]: crate::bodies::wheel::WheelModel::k_elastic

use std::path::{Path, PathBuf};

use faer::linalg::solvers::LltError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatRef, Par, Side};

use crate::assembly::Assembler;
use crate::bodies::wheel::WheelModel;
use crate::mesh::Mesh;
use crate::output::vtk::{write_vtu, Field, PvdWriter, VtkError};

mod bounce;
mod figure;
mod sparse;
mod spinning;

pub use bounce::{bounce_mode, Bounce, BOUNCE_SUBSPACE};
pub use figure::{mode_label, write_modes_figure, FIGURE_MODES, SHAPE_SCALE};
pub use sparse::{natural_modes_sparse, natural_modes_sparse_of, spinning_modes_sparse};
use spinning::rigid_kind;
pub use spinning::{spinning_analysis, spinning_modes, SpinAnalysis, SpinMode, Whirl};

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

/// Whether two rest modes of circular frequencies `w` and `wk` (rad/s) pair into a whirling
/// pair on a disk spinning at `omega_frame` (rad/s): equal to [`PAIR_TOLERANCE`], or split
/// by less than the spin's Coriolis coupling `2 |omega_frame|`. A mesh without the disk's
/// rotational symmetry splits a doublet slightly (3e-4 of 6.4 kHz on `wheel.toml`'s graded
/// disk, 12 rad/s); the spin at 300 rad/s still turns such a pair into a forward and a
/// backward wave, while a split larger than the coupling leaves two standing modes.
pub fn paired(w: f64, wk: f64, omega_frame: f64) -> bool {
    let d = (w - wk).abs();
    w > 0.0 && (d <= PAIR_TOLERANCE * w || d <= 2.0 * omega_frame.abs())
}

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
    /// The sparse shift-invert solver's Krylov space did not hold the modes asked for to
    /// its tolerance.
    #[error(
        "the sparse shift-invert eigensolver did not converge: {wanted} eigenpairs asked for, \
         a basis of {basis} vectors; ask for fewer modes (--count)"
    )]
    SparseNoConvergence {
        /// Eigenpairs asked for.
        wanted: usize,
        /// The basis reached.
        basis: usize,
    },
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
    /// Drawing `modes.png` failed.
    #[error(transparent)]
    Plot(#[from] crate::output::plot::PlotError),
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

/// Rest modes, and the spinning modes when the model spins (rotating frame, `omega != 0`;
/// otherwise a note says why not), both by the sparse shift-invert solver
/// ([`natural_modes_sparse`], [`spinning_modes_sparse`]): any size. The dense analyses
/// ([`natural_modes`], [`spinning_modes`]) are their reference.
///
/// # Errors
/// As [`natural_modes_sparse`].
pub fn modes_report(model: &WheelModel, count: usize) -> Result<ModesReport, ModesError> {
    let at_rest = natural_modes_sparse(model, count)?;
    let n = model.mesh.n_dofs();
    let free_dofs = FreeDofs::new(n, &model.fixed_dofs)?.len();
    let mut notes = Vec::new();
    let spinning = if model.spec.rotating_frame && model.spec.omega != 0.0 {
        Some(spinning_modes_sparse(model, count)?)
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
    let mut csv = crate::output::csv::record(["index", "frequency_hz", "period_us", "kind"]);
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
        crate::output::csv::push_record(
            &mut csv,
            [
                format!("{number}"),
                format!("{:e}", mode.frequency_hz),
                format!("{:e}", mode.period_us),
                mode.kind.to_string(),
            ],
        );
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
            let (x, y) = (model.mesh.point(node)[0], model.mesh.point(node)[1]);
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
