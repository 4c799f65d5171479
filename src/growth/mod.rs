//! Growth studies (placeholder of the interface; the driver lands from its own branch).

pub mod track;

/// A surface profile over the rolling coordinate: evenly spaced samples. Positive `z` is
/// material standing proud (a bump on the wheel's rim, a rail surface higher), m.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SurfaceProfile {
    /// First sample's abscissa, m.
    pub x0: f64,
    /// Spacing, m.
    pub dx: f64,
    /// Heights, m.
    pub z: Vec<f64>,
    /// Periodic (a wheel's rim).
    pub periodic: bool,
}

/// What one simulated pass gives, per sample of the profile's grid.
pub struct PassResult {
    /// Depth worn in this one simulated pass, m (>= 0), before the wear step's scaling.
    pub wear_depth: Vec<f64>,
    /// Permanent surface displacement of plastic flow in this pass, m (+ = proud).
    pub plastic: Vec<f64>,
    /// Scalars of the pass for the per-pass table (name, value).
    pub scalars: Vec<(String, f64)>,
}

/// Where a pass runs.
pub trait PassRunner {
    /// The profile's grid: (x0, dx, n, periodic), fixed for the study.
    fn grid(&self) -> (f64, f64, usize, bool);
    /// The rolling speed of the pass, m/s.
    fn speed(&self) -> f64;
    /// Runs one pass over `profile`.
    ///
    /// # Errors
    /// [`crate::run::RunError`].
    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        pass: usize,
        interrupt: &std::sync::atomic::AtomicBool,
    ) -> Result<PassResult, crate::run::RunError>;
}
