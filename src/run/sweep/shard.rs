//! A sweep in slices, for clusters without Python (SLURM job arrays): `softway sweep
//! --shard I/N` runs the points of slice `I` of `N` into a folder of their own with a
//! manifest (`shard.json`), and `softway gather` reads the `N` folders and writes the one
//! table and plot that `softway sweep` writes for the whole sweep ([`super::write_sweep`],
//! from the points' `summary.json` in the sweep's order).
//!
//! The sweep is any grid of `softway sweep` (one key, or several keys combined by
//! `--grid product` or `zip`, [`crate::scenario::overrides::grid`]). Its points are taken
//! in the grid's fixed order (product: the first key outermost) and slice `I` holds the
//! points `k` (0-based) with `k mod N = I - 1`: neighbouring points, whose runs cost about
//! the same, fall into different slices, so the slices take about equal times.

use super::{
    point_dir_name, run_points, write_sweep, Override, PointStatus, SweepError, SweepPoint,
};
use crate::output::files::write_json;
use crate::run::{Cancel, RunError};
use crate::scenario::overrides::{grid, Grid};
use std::path::{Path, PathBuf};

/// The manifest a shard writes beside its points.
pub const MANIFEST: &str = "shard.json";

/// The most shards a sweep is split into (`--shard I/N`, a manifest's `of`): far beyond a
/// cluster's job array (SLURM's default `MaxArraySize` is 1,001).
pub const MAX_SHARDS: usize = 1_000_000;

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
        if count > MAX_SHARDS {
            return Err(format!(
                "--shard {s}: at most {MAX_SHARDS} shards (a job array's tasks; a shard with no point of the grid writes only its manifest)"
            ));
        }
        Ok(Shard { index, count })
    }
}

impl Shard {
    /// The items of this slice, in their order: the `k`-th item when
    /// `k mod count = index - 1`.
    pub fn pick<T: Clone>(&self, items: &[T]) -> Vec<T> {
        items
            .iter()
            .enumerate()
            .filter(|(k, _)| k % self.count == self.index - 1)
            .map(|(_, v)| v.clone())
            .collect()
    }
}

/// `product` or `zip`, as the manifest writes a [`Grid`].
fn grid_name(how: Grid) -> &'static str {
    match how {
        Grid::Product => "product",
        Grid::Zip => "zip",
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
    /// The swept keys, each with all its values in order (TOML literals).
    pub keys: Vec<(String, Vec<String>)>,
    /// How the keys' values combine: `product` or `zip`.
    pub grid: String,
    /// This slice, 1-based.
    pub shard: usize,
    /// Slices in all.
    pub of: usize,
    /// This slice's points: `(values in the keys' order, folder name)`.
    pub points: Vec<(Vec<String>, String)>,
    /// Each point's status ([`PointStatus`] as the table writes it: `complete`,
    /// `interrupted`, `failed: <message>`), in the order of `points`. Empty in the
    /// manifests of older versions: the status is then the summaries' `interrupted` flag.
    #[serde(default)]
    pub status: Vec<String>,
}

impl Manifest {
    /// The sweep's keys, comma-separated (for messages).
    pub fn key_names(&self) -> String {
        self.keys
            .iter()
            .map(|(k, _)| k.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Every point of the whole sweep, in the grid's order.
    ///
    /// # Errors
    /// A one-line message: a grid that [`grid`] refuses or an unknown `grid`.
    pub fn all_points(&self) -> Result<Vec<Vec<Override>>, String> {
        let how = match self.grid.as_str() {
            "product" => Grid::Product,
            "zip" => Grid::Zip,
            g => return Err(format!("grid `{g}`: expected product or zip")),
        };
        grid(&self.keys, how)
    }
}

fn values_of(sets: &[Override]) -> Vec<String> {
    sets.iter().map(|o| o.value.clone()).collect()
}

/// Runs slice `shard` of the sweep of the scenario text at `path` over the grid of `keys`
/// combined by `how` (every point validated and built first, as `softway sweep` does)
/// into `out/<key>=<value>,.../`, writes the slice's own table (`sweep.csv`, `sweep.md`)
/// and its manifest [`MANIFEST`]; returns the slice's points and the files. A slice with
/// no point (more slices than points) writes its manifest only.
///
/// # Errors
/// [`SweepError`]: a grid that cannot be made, a point that cannot be set or built, a
/// failed run, a file not written.
#[allow(clippy::too_many_arguments)]
pub fn run_shard(
    path: &Path,
    text: &str,
    name: &str,
    keys: &[(String, Vec<String>)],
    how: Grid,
    shard: Shard,
    out: &Path,
    cancel: &Cancel,
) -> Result<(Vec<SweepPoint>, Vec<PathBuf>), SweepError> {
    let all = grid(keys, how).map_err(|message| SweepError::Value {
        key: keys
            .iter()
            .map(|(k, _)| k.as_str())
            .collect::<Vec<_>>()
            .join(","),
        value: String::new(),
        message,
    })?;
    let mine = shard.pick(&all);
    let points = run_points(path, text, &mine, out, cancel)?;
    let names: Vec<String> = keys.iter().map(|(k, _)| k.clone()).collect();
    let mut files = if points.is_empty() {
        Vec::new()
    } else {
        super::write_tables(out, &names, &table_columns_of(&points), &points)?
    };
    let manifest = Manifest {
        name: name.to_string(),
        scenario_sha256: crate::scenario::sha256_hex(text.as_bytes()),
        keys: keys.to_vec(),
        grid: grid_name(how).to_string(),
        shard: shard.index,
        of: shard.count,
        points: mine
            .iter()
            .map(|sets| (values_of(sets), point_dir_name(sets)))
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
/// keys, grid), the points in the order of the values, and the files.
///
/// # Errors
/// [`GatherError`]: a folder without a manifest, shards of different sweeps (scenario text,
/// keys, values, grid or count), a slice missing or given twice, the `summary.json` of a
/// point that completed missing. A point that was interrupted or failed keeps its status
/// (its figures are left out of the table and plot, as `softway sweep` leaves them).
pub fn gather(
    dirs: &[PathBuf],
    out: &Path,
) -> Result<(Manifest, Vec<SweepPoint>, Vec<PathBuf>), GatherError> {
    let manifests = dirs
        .iter()
        .map(|d| read_manifest(d))
        .collect::<Result<Vec<_>, _>>()?;
    let first = one_sweep(dirs, &manifests)?;
    let all = first
        .all_points()
        .map_err(|m| GatherError::Mismatch(format!("{}: {m}", dirs[0].join(MANIFEST).display())))?;
    let base = sweep_text(&dirs[0], &first.scenario_sha256)?;
    let mut points = Vec::with_capacity(all.len());
    for sets in all {
        points.push(gathered_point(dirs, &manifests, sets, &base)?);
    }
    std::fs::create_dir_all(out).map_err(|e| SweepError::Run(RunError::output(out, e)))?;
    let files = write_sweep(out, &points)?;
    Ok((first, points, files))
}

/// The first of the shards' `manifests` (of the folders `dirs`), once checked that they
/// are the shards of one sweep (its scenario, keys, values, grid and count of shards),
/// each given once, and all of them.
fn one_sweep(dirs: &[PathBuf], manifests: &[Manifest]) -> Result<Manifest, GatherError> {
    let Some(first) = manifests.first().cloned() else {
        return Err(GatherError::Mismatch(
            "no shard folder given: softway gather DIR1 DIR2 ...".into(),
        ));
    };
    // A manifest is input: its count of shards is bounded as `--shard` bounds it (an
    // edited `of` of 1e18 aborted on the allocation below).
    if !(1..=MAX_SHARDS).contains(&first.of) {
        return Err(GatherError::Mismatch(format!(
            "{}: `of` = {}: the sweep's shards in all, from 1 to {MAX_SHARDS} (as --shard I/N takes them)",
            dirs[0].join(MANIFEST).display(),
            first.of,
        )));
    }
    let mut by_index: Vec<Option<usize>> = vec![None; first.of];
    for (j, (d, m)) in dirs.iter().zip(manifests).enumerate() {
        if let Some(what) = differs(m, &first) {
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
        let listed = if missing.len() > 10 {
            format!(
                "{}, ... ({} in all)",
                missing[..10].join(", "),
                missing.len()
            )
        } else {
            missing.join(", ")
        };
        return Err(GatherError::Mismatch(format!(
            "shard {listed} of the sweep of {} not given (run softway sweep --shard I/N for it)",
            first.key_names(),
        )));
    }
    Ok(first)
}

/// What makes the manifest `m` another sweep's than `first`'s, if anything.
fn differs(m: &Manifest, first: &Manifest) -> Option<&'static str> {
    if m.scenario_sha256 != first.scenario_sha256 {
        Some("scenario text")
    } else if m
        .keys
        .iter()
        .map(|k| &k.0)
        .ne(first.keys.iter().map(|k| &k.0))
    {
        Some("keys")
    } else if m.keys != first.keys {
        Some("values")
    } else if m.grid != first.grid {
        Some("grid")
    } else if m.of != first.of {
        Some("number of shards")
    } else {
        None
    }
}

/// The point `sets` as the shard that lists it ran it: its folder, its status from the
/// manifest (an interrupted or failed point keeps it, with its summary if it has one), its
/// summary, checked against the sweep's scenario text `base` with the point's values set.
fn gathered_point(
    dirs: &[PathBuf],
    manifests: &[Manifest],
    sets: Vec<Override>,
    base: &str,
) -> Result<SweepPoint, GatherError> {
    let v = values_of(&sets);
    let (d, folder, status) = dirs
        .iter()
        .zip(manifests)
        .find_map(|(d, m)| {
            let k = m.points.iter().position(|(value, _)| *value == v)?;
            Some((d, &m.points[k].1, m.status.get(k)))
        })
        .ok_or_else(|| {
            GatherError::Mismatch(format!(
                "no shard lists the point {}: gather the folders of every shard",
                super::point_label(&sets)
            ))
        })?;
    let dir = d.join(folder);
    let status = match status.map(|s| s.parse::<PointStatus>()) {
        None => None,
        Some(Ok(s)) => Some(s),
        Some(Err(m)) => {
            return Err(GatherError::Read {
                path: d.join(MANIFEST),
                message: format!("{}: {m}", super::point_label(&sets)),
            })
        }
    };
    let sj = dir.join("summary.json");
    if let Some(s @ (PointStatus::Interrupted | PointStatus::Failed(_))) = &status {
        let summary = std::fs::read_to_string(&sj)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or(serde_json::Value::Null);
        if !summary.is_null() {
            check_point(&dir, &summary, base, &sets)?;
        }
        return Ok(SweepPoint {
            value: v.join(","),
            sets,
            dir,
            summary,
            warnings: Vec::new(),
            status: s.clone(),
        });
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
    check_point(&dir, &summary, base, &sets)?;
    Ok(SweepPoint {
        value: v.join(","),
        sets,
        dir,
        status: PointStatus::of_summary(&summary),
        summary,
        warnings: Vec::new(),
    })
}

/// The scenario text the sweep set its values into: the shard folder `dir`'s copy of it
/// (`scenario.toml`: a header of comments up to its first blank line, then the text),
/// checked against the manifest's `sha256`.
///
/// # Errors
/// [`GatherError`]: the copy unreadable, or not the manifest's text.
fn sweep_text(dir: &Path, sha256: &str) -> Result<String, GatherError> {
    let f = dir.join(crate::run::SCENARIO_COPY);
    let text = std::fs::read_to_string(&f).map_err(|e| GatherError::Read {
        path: f.clone(),
        message: format!(
            "cannot read the shard's copy of the scenario ({e}), which the points are checked against; give the folders written by softway sweep --shard I/N"
        ),
    })?;
    let body = text.split_once("\n\n").map_or("", |(_, b)| b);
    if crate::scenario::sha256_hex(body.as_bytes()) != sha256 {
        return Err(GatherError::Mismatch(format!(
            "{}: not the scenario of the shard's manifest (SHA-256 {sha256}): gather the folders as softway sweep --shard wrote them",
            f.display()
        )));
    }
    Ok(body.to_string())
}

/// Refuses a point folder `dir` whose run is not the sweep's point `sets`: its summary's
/// `scenario_sha256` must be that of the sweep's text `base` with the point's values set
/// into it (a folder re-run with other settings, e.g. `softway run --set rolling.omega=450
/// --out <shard>/rolling.omega=300`, was gathered as the 300 rad/s row; issue 47). The
/// message names the folder and, from its own `scenario.toml`, the values it ran with.
///
/// # Errors
/// [`GatherError::Mismatch`].
fn check_point(
    dir: &Path,
    summary: &serde_json::Value,
    base: &str,
    sets: &[Override],
) -> Result<(), GatherError> {
    let expected = crate::scenario::overrides::apply(base, sets)
        .map(|t| crate::scenario::sha256_hex(t.as_bytes()))
        .map_err(|m| GatherError::Mismatch(format!("{}: {m}", dir.display())))?;
    let got = summary["scenario_sha256"].as_str().unwrap_or("(none)");
    if got == expected {
        return Ok(());
    }
    let ran_with: Vec<String> = std::fs::read_to_string(dir.join(crate::run::SCENARIO_COPY))
        .unwrap_or_default()
        .lines()
        .take_while(|l| l.starts_with('#'))
        .filter_map(|l| l.strip_prefix("# --set ").map(str::to_string))
        .collect();
    let ran_with = if ran_with.is_empty() {
        String::new()
    } else {
        format!(
            "; its scenario.toml ran with --set {}",
            ran_with.join(" --set ")
        )
    };
    Err(GatherError::Mismatch(format!(
        "{}: not the sweep's point {} (its summary.json's scenario_sha256 {got}, the point's {expected}{ran_with}): the folder was run again with other settings; run the shard again (softway sweep --shard I/N) or gather the folders as it wrote them",
        dir.display(),
        super::point_label(sets)
    )))
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
        // Every point in exactly one slice, in order within each, for any count.
        let values: Vec<String> = (0..7).map(|i| format!("{}", 100 + i)).collect();
        for count in 1..=9 {
            let mut seen: Vec<String> = Vec::new();
            for index in 1..=count {
                let mine = Shard { index, count }.pick(&values);
                assert!(mine.windows(2).all(|w| w[0] < w[1]));
                seen.extend(mine);
            }
            seen.sort();
            assert_eq!(seen, values, "count {count}");
        }
    }

    /// A 2 x 2 product grid in 3 slices: the points in the grid's order (the first key
    /// outermost) dealt round the slices, and the manifest gives the whole grid back.
    #[test]
    fn a_grid_is_sliced_in_its_order() {
        let keys = vec![
            ("a".to_string(), vec!["1".to_string(), "2".to_string()]),
            ("b".to_string(), vec!["x".to_string(), "y".to_string()]),
        ];
        let all = grid(&keys, Grid::Product).unwrap();
        let vals = |pts: &[Vec<Override>]| -> Vec<Vec<String>> {
            pts.iter().map(|s| values_of(s)).collect()
        };
        let v = |a: &str, b: &str| vec![a.to_string(), b.to_string()];
        let s1 = Shard { index: 1, count: 3 }.pick(&all);
        let s2 = Shard { index: 2, count: 3 }.pick(&all);
        let s3 = Shard { index: 3, count: 3 }.pick(&all);
        assert_eq!(vals(&s1), vec![v("1", "x"), v("2", "y")]);
        assert_eq!(vals(&s2), vec![v("1", "y")]);
        assert_eq!(vals(&s3), vec![v("2", "x")]);
        let m = Manifest {
            name: "n".into(),
            scenario_sha256: String::new(),
            keys: keys.clone(),
            grid: "zip".into(),
            shard: 1,
            of: 3,
            points: Vec::new(),
            status: Vec::new(),
        };
        assert_eq!(
            vals(&m.all_points().unwrap()),
            vec![v("1", "x"), v("2", "y")]
        );
        let m = Manifest {
            grid: "product".into(),
            ..m
        };
        assert_eq!(m.all_points().unwrap(), all);
        let m = Manifest {
            grid: "diagonal".into(),
            ..m
        };
        assert!(m.all_points().unwrap_err().contains("product or zip"));
    }
}
