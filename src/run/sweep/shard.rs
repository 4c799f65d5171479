//! A sweep in slices, for clusters without Python (SLURM job arrays): `softway sweep
//! --shard I/N` runs the points of slice `I` of `N` into a folder of their own with a
//! manifest (`shard.json`), and `softway gather` reads the `N` folders and writes the one
//! table and plot that `softway sweep` writes for the whole sweep ([`super::write_sweep`],
//! from the points' `summary.json` in the order of the values).
//!
//! Slice `I` holds the points `k` (0-based, in the order of the values) with
//! `k mod N = I - 1`: neighbouring values, whose runs cost about the same, fall into
//! different slices, so the slices take about equal times.

use super::{point_dir_name, run_ladder, write_sweep, PointStatus, SweepError, SweepPoint};
use crate::output::files::write_json;
use crate::run::{Cancel, RunError};
use std::path::{Path, PathBuf};

/// The manifest a shard writes beside its points.
pub const MANIFEST: &str = "shard.json";

/// Slice `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, 1 ..= `count`.
    pub index: usize,
    /// Slices in all (at least 1).
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `I/N` with `1 <= I <= N` (SLURM's `$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT` with
    /// `--array=1-N`).
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("--shard {s}: expected I/N with 1 <= I <= N (e.g. --shard 1/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl Shard {
    /// The values of this slice, in their order: the `k`-th value when
    /// `k mod count = index - 1`.
    pub fn values(&self, values: &[String]) -> Vec<String> {
        values
            .iter()
            .enumerate()
            .filter(|(k, _)| k % self.count == self.index - 1)
            .map(|(_, v)| v.clone())
            .collect()
    }
}

/// What a shard's `shard.json` holds: enough for `gather` to check that the shards belong
/// to one sweep and to find every point's folder.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// The scenario's name (the gathered folder's default `out/<name>-sweep`).
    pub name: String,
    /// SHA-256 of the scenario text the sweep set its values into.
    pub scenario_sha256: String,
    /// The swept key.
    pub key: String,
    /// All the sweep's values, in order (TOML literals).
    pub values: Vec<String>,
    /// This slice, 1-based.
    pub shard: usize,
    /// Slices in all.
    pub of: usize,
    /// This slice's points: `(value, folder name)`.
    pub points: Vec<(String, String)>,
    /// Each point's status ([`PointStatus`] as the table writes it: `complete`,
    /// `interrupted`, `failed: <message>`), in the order of `points`. Empty in the
    /// manifests of older versions: the status is then the summaries' `interrupted` flag.
    #[serde(default)]
    pub status: Vec<String>,
}

/// Runs slice `shard` of the sweep of the scenario text at `path` over `values` of `key`
/// into `out/<key>=<value>/`, writes the slice's own table (`sweep.csv`, `sweep.md`) and
/// its manifest [`MANIFEST`]; returns the slice's points and the files. A slice with no
/// point (more slices than values) writes its manifest only.
///
/// # Errors
/// [`SweepError`]: a value that cannot be set or built (every value of the slice is built
/// before a run starts), a failed run, a file not written.
#[allow(clippy::too_many_arguments)]
pub fn run_shard(
    path: &Path,
    text: &str,
    name: &str,
    key: &str,
    values: &[String],
    shard: Shard,
    out: &Path,
    cancel: &Cancel,
) -> Result<(Vec<SweepPoint>, Vec<PathBuf>), SweepError> {
    let mine = shard.values(values);
    let points = run_ladder(path, text, key, &mine, out, cancel)?;
    let mut files = if points.is_empty() {
        Vec::new()
    } else {
        super::write_tables(out, &[key.to_string()], &table_columns_of(&points), &points)?
    };
    let manifest = Manifest {
        name: name.to_string(),
        scenario_sha256: crate::scenario::sha256_hex(text.as_bytes()),
        key: key.to_string(),
        values: values.to_vec(),
        shard: shard.index,
        of: shard.count,
        points: mine
            .iter()
            .map(|v| {
                let set = [super::Override {
                    key: key.to_string(),
                    value: v.clone(),
                }];
                (v.clone(), point_dir_name(&set))
            })
            .collect(),
        status: points.iter().map(|p| p.status.to_string()).collect(),
    };
    let f = out.join(MANIFEST);
    write_json(&f, &manifest).map_err(|e| RunError::output(&f, e))?;
    files.push(f);
    Ok((points, files))
}

/// The table's columns for `points`, as [`super::write_sweep`] chooses them.
fn table_columns_of(points: &[SweepPoint]) -> Vec<String> {
    let (is_wheel, with_traction) = super::model_of(points);
    super::table_columns(points, is_wheel, with_traction)
}

/// Errors of [`gather`]: each names the folder or file at fault.
#[derive(Debug, thiserror::Error)]
pub enum GatherError {
    /// A shard's manifest or a point's summary cannot be read or parsed.
    #[error("{path}: {message}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// The shards do not make one whole sweep.
    #[error("{0}")]
    Mismatch(String),
    /// The table or plot cannot be written.
    #[error(transparent)]
    Write(#[from] SweepError),
}

/// Reads the manifest of the shard folder `dir`.
///
/// # Errors
/// [`GatherError::Read`] naming the manifest.
pub fn read_manifest(dir: &Path) -> Result<Manifest, GatherError> {
    let f = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&f).map_err(|e| GatherError::Read {
        path: f.clone(),
        message: format!(
            "cannot read the shard's manifest ({e}); give the folders written by softway sweep --shard I/N"
        ),
    })?;
    serde_json::from_str(&text).map_err(|e| GatherError::Read {
        path: f.clone(),
        message: format!("not a shard manifest: {e}"),
    })
}

/// Assembles the shards in `dirs` (the folders of `softway sweep --shard I/N` for every
/// `I` of one `N`, in any order) into `out`: the table and plot of the whole sweep, the
/// same files as `softway sweep` writes. Returns the manifest of the first shard (name,
/// key, values), the points in the order of the values, and the files.
///
/// # Errors
/// [`GatherError`]: a folder without a manifest, shards of different sweeps (scenario text,
/// key, values or count), a slice missing or given twice, the `summary.json` of a point
/// that completed missing. A point that was interrupted or failed keeps its status (its
/// figures are left out of the table and plot, as `softway sweep` leaves them).
pub fn gather(
    dirs: &[PathBuf],
    out: &Path,
) -> Result<(Manifest, Vec<SweepPoint>, Vec<PathBuf>), GatherError> {
    let manifests = dirs
        .iter()
        .map(|d| read_manifest(d))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(first) = manifests.first().cloned() else {
        return Err(GatherError::Mismatch(
            "no shard folder given: softway gather DIR1 DIR2 ...".into(),
        ));
    };
    let mut by_index: Vec<Option<usize>> = vec![None; first.of];
    for (j, (d, m)) in dirs.iter().zip(&manifests).enumerate() {
        let differs = if m.scenario_sha256 != first.scenario_sha256 {
            Some("scenario text")
        } else if m.key != first.key {
            Some("key")
        } else if m.values != first.values {
            Some("values")
        } else if m.of != first.of {
            Some("number of shards")
        } else {
            None
        };
        if let Some(what) = differs {
            return Err(GatherError::Mismatch(format!(
                "{}: another sweep than {} ({what} not the same): gather the shards of one sweep",
                d.display(),
                dirs[0].display()
            )));
        }
        let slot = by_index.get_mut(m.shard.wrapping_sub(1)).ok_or_else(|| {
            GatherError::Mismatch(format!(
                "{}: shard {}/{} out of range",
                d.display(),
                m.shard,
                m.of
            ))
        })?;
        if let Some(i) = slot.replace(j) {
            return Err(GatherError::Mismatch(format!(
                "{} and {}: both are shard {}/{}; give each shard once",
                dirs[i].display(),
                d.display(),
                m.shard,
                m.of
            )));
        }
    }
    let missing: Vec<String> = by_index
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| format!("{}/{}", i + 1, first.of))
        .collect();
    if !missing.is_empty() {
        return Err(GatherError::Mismatch(format!(
            "shard {} of the sweep of {} over {} values not given (run softway sweep --shard I/N for it)",
            missing.join(", "),
            first.key,
            first.values.len()
        )));
    }
    let mut points = Vec::with_capacity(first.values.len());
    for v in &first.values {
        let (d, folder, status) = dirs
            .iter()
            .zip(&manifests)
            .find_map(|(d, m)| {
                let k = m.points.iter().position(|(value, _)| value == v)?;
                Some((d, &m.points[k].1, m.status.get(k)))
            })
            .ok_or_else(|| {
                GatherError::Mismatch(format!(
                    "no shard lists the point {} = {v}: gather the folders of every shard",
                    first.key
                ))
            })?;
        let dir = d.join(folder);
        let status = match status.map(|s| s.parse::<PointStatus>()) {
            None => None,
            Some(Ok(s)) => Some(s),
            Some(Err(m)) => {
                return Err(GatherError::Read {
                    path: d.join(MANIFEST),
                    message: format!("{} = {v}: {m}", first.key),
                })
            }
        };
        let sj = dir.join("summary.json");
        if let Some(s @ (PointStatus::Interrupted | PointStatus::Failed(_))) = &status {
            let summary = std::fs::read_to_string(&sj)
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok())
                .unwrap_or(serde_json::Value::Null);
            points.push(SweepPoint {
                sets: vec![super::Override {
                    key: first.key.clone(),
                    value: v.clone(),
                }],
                value: v.clone(),
                dir,
                summary,
                warnings: Vec::new(),
                status: s.clone(),
            });
            continue;
        }
        let summary: serde_json::Value = std::fs::read_to_string(&sj)
            .map_err(|e| GatherError::Read {
                path: sj.clone(),
                message: format!("cannot read the point's summary ({e}); did its run finish?"),
            })
            .and_then(|s| {
                serde_json::from_str(&s).map_err(|e| GatherError::Read {
                    path: sj.clone(),
                    message: format!("not a summary: {e}"),
                })
            })?;
        points.push(SweepPoint {
            sets: vec![super::Override {
                key: first.key.clone(),
                value: v.clone(),
            }],
            value: v.clone(),
            dir,
            status: PointStatus::of_summary(&summary),
            summary,
            warnings: Vec::new(),
        });
    }
    std::fs::create_dir_all(out).map_err(|e| SweepError::Run(RunError::output(out, e)))?;
    let files = write_sweep(out, &points)?;
    Ok((first, points, files))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_partition_the_values() {
        assert_eq!("2/3".parse::<Shard>(), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "1", "a/b", "1/0", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.contains("expected I/N"), "{bad}: {e}");
        }
        // Every value in exactly one slice, in order within each, for any count.
        let values: Vec<String> = (0..7).map(|i| format!("{}", 100 + i)).collect();
        for count in 1..=9 {
            let mut seen: Vec<String> = Vec::new();
            for index in 1..=count {
                let mine = Shard { index, count }.values(&values);
                assert!(mine.windows(2).all(|w| w[0] < w[1]));
                seen.extend(mine);
            }
            seen.sort();
            assert_eq!(seen, values, "count {count}");
        }
    }
}
