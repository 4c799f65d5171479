//! The growth study's state between passes and its checkpoint (`checkpoint.json`): the
//! profile, the passes done and their records, the carried plastic state, written atomically
//! after each pass and read back (every field checked) on `--resume`.

use super::*;
use crate::output::files::write_atomic;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Floats kept bit for bit through JSON (each as its `u64` bits).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bits(pub Vec<f64>);

impl Serialize for Bits {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.0.iter().map(|x| x.to_bits()))
    }
}

impl<'de> Deserialize<'de> for Bits {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v: Vec<u64> = Vec::deserialize(d)?;
        Ok(Bits(v.into_iter().map(f64::from_bits).collect()))
    }
}

/// One finished pass in the study's state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PassRecord {
    /// The profile after the pass, m.
    pub z: Bits,
    /// The uniform loss of this pass (`N_w` times the mean smoothed wear), m.
    pub uniform_loss: Bits,
    /// The smoothed wear of the one simulated pass, after the reference's subtraction, m.
    pub wear: Bits,
    /// The runner's scalars (names, values bit for bit).
    pub scalar_names: Vec<String>,
    /// Their values.
    pub scalar_values: Bits,
    /// Wall-clock time of the pass, s (not part of the physics).
    pub wall_s: f64,
}

/// The state of a study, as checkpointed after every pass (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyState {
    /// Format version.
    pub version: u32,
    /// SHA-256 of the scenario text the study runs (a resume refuses another).
    pub scenario_sha256: String,
    /// Grid: x0, dx (bits), n, periodic.
    pub x0: Bits,
    /// Sample spacing (bits).
    pub dx: Bits,
    /// Samples.
    pub n: usize,
    /// Periodic.
    pub periodic: bool,
    /// The initial profile, m.
    pub initial: Bits,
    /// The reference wear (the smooth surface's, minus its mean), m, when asked for.
    pub reference: Option<Bits>,
    /// The finished passes, in order.
    pub passes: Vec<PassRecord>,
    /// The runner's carried state after the last finished pass ([`PassRunner::carried_state`]:
    /// a plastic wheel's plastic state), when it carries one.
    #[serde(default)]
    pub runner: Option<Bits>,
}

/// The checkpoint's format version.
pub const CHECKPOINT_VERSION: u32 = 1;
/// The largest checkpoint read on `--resume`, bytes (16 GiB: 10,000 passes of a
/// 10,000-sample profile, as JSON bits, are about 6 GB; a larger file is not one a study
/// wrote).
pub const MAX_CHECKPOINT_BYTES: u64 = 1 << 34;
/// The checkpoint's file name in the output folder.
pub const CHECKPOINT: &str = "checkpoint.json";

impl StudyState {
    /// The profile after the last finished pass (the initial one before any).
    pub fn current(&self) -> SurfaceProfile {
        SurfaceProfile {
            x0: self.x0.0[0],
            dx: self.dx.0[0],
            z: self
                .passes
                .last()
                .map(|p| p.z.0.clone())
                .unwrap_or_else(|| self.initial.0.clone()),
            periodic: self.periodic,
        }
    }

    /// Every profile so far: the initial one, then after each pass.
    pub fn profiles(&self) -> Vec<&[f64]> {
        std::iter::once(self.initial.0.as_slice())
            .chain(self.passes.iter().map(|p| p.z.0.as_slice()))
            .collect()
    }

    /// The uniform loss accumulated over the passes, m.
    pub fn uniform_loss(&self) -> f64 {
        self.passes.iter().map(|p| p.uniform_loss.0[0]).sum()
    }

    /// Reads a checkpoint.
    ///
    /// # Errors
    /// [`GrowthError::Checkpoint`].
    pub fn read(path: &Path) -> Result<Self, GrowthError> {
        let err = |message: String| GrowthError::Checkpoint {
            path: path.to_path_buf(),
            message,
        };
        // A regular file only: a FIFO or a device in its place would block the read, deaf
        // to a signal.
        match std::fs::metadata(path) {
            Ok(m) if !m.is_file() => {
                return Err(err(
                    "not a regular file (a checkpoint is the checkpoint.json a study wrote)".into(),
                ))
            }
            Ok(m) if m.len() > MAX_CHECKPOINT_BYTES => {
                return Err(err(format!(
                    "{} bytes, more than a study writes ({MAX_CHECKPOINT_BYTES} at most)",
                    m.len()
                )))
            }
            _ => {}
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| err(format!("cannot read the checkpoint to resume from: {e}")))?;
        let s: Self = serde_json::from_str(&text)
            .map_err(|e| err(format!("not a growth checkpoint: {e}")))?;
        if s.version != CHECKPOINT_VERSION {
            return Err(err(format!(
                "checkpoint version {} (this softway reads {CHECKPOINT_VERSION})",
                s.version
            )));
        }
        s.check().map_err(err)?;
        Ok(s)
    }

    /// Checks the state read from a checkpoint as the input it is (a damaged or edited file
    /// must be refused, not panic or run to NaN): every field's length against the grid,
    /// every value finite, the passes consistent with each other. The message names the
    /// field.
    ///
    /// # Errors
    /// The first field at fault, named.
    pub fn check(&self) -> Result<(), String> {
        let one = |name: &str, b: &Bits| -> Result<f64, String> {
            match b.0.as_slice() {
                [v] if v.is_finite() => Ok(*v),
                [v] => Err(format!("`{name}` = {v}: must be finite")),
                v => Err(format!("`{name}` holds {} values: one is written", v.len())),
            }
        };
        one("x0", &self.x0)?;
        let dx = one("dx", &self.dx)?;
        if dx <= 0.0 {
            return Err(format!("`dx` = {dx}: must be > 0"));
        }
        if self.n < 3 {
            return Err(format!(
                "`n` = {}: a profile has at least 3 samples",
                self.n
            ));
        }
        let n = self.n;
        let profile = |name: String, b: &Bits| -> Result<(), String> {
            if b.0.len() != n {
                return Err(format!(
                    "`{name}` holds {} samples; the grid's `n` is {n}",
                    b.0.len()
                ));
            }
            match b.0.iter().position(|v| !v.is_finite()) {
                Some(i) => Err(format!("`{name}`[{i}] = {}: must be finite", b.0[i])),
                None => Ok(()),
            }
        };
        profile("initial".into(), &self.initial)?;
        if let Some(r) = &self.reference {
            profile("reference".into(), r)?;
        }
        for (k, p) in self.passes.iter().enumerate() {
            profile(format!("passes[{k}].z"), &p.z)?;
            profile(format!("passes[{k}].wear"), &p.wear)?;
            one(&format!("passes[{k}].uniform_loss"), &p.uniform_loss)?;
            if p.scalar_names.len() != p.scalar_values.0.len() {
                return Err(format!(
                    "`passes[{k}].scalar_values` holds {} values for {} names",
                    p.scalar_values.0.len(),
                    p.scalar_names.len()
                ));
            }
        }
        if let Some(r) = &self.runner {
            if let Some(i) = r.0.iter().position(|v| !v.is_finite()) {
                return Err(format!("`runner`[{i}] = {}: must be finite", r.0[i]));
            }
        }
        Ok(())
    }

    /// Writes the checkpoint atomically.
    ///
    /// # Errors
    /// [`GrowthError::Output`].
    pub fn write(&self, path: &Path) -> Result<(), GrowthError> {
        let text = serde_json::to_string(self).map_err(|e| GrowthError::output(path, e))?;
        write_atomic(path, text.as_bytes()).map_err(|e| GrowthError::output(path, e))
    }
}
