//! `softway._native`: the engine for the Python package `softway` (python/softway/).
//!
//! A thin layer over the library: the scenario's validation ([`Scenario::from_str`],
//! [`resolve`]) with its one-line errors as `ScenarioError` carrying the key, and a run
//! ([`softway::run()`], results in memory) on a thread of its own while the calling thread
//! waits without the GIL, waking every `poll_s` to report the progress and to let Python
//! handle its signals: a KeyboardInterrupt cancels the run's token ([`Cancel`]), which stops
//! it at its next step with what it has computed. The tables and fields cross as raw
//! little-endian `f64` bytes that the Python side views as numpy arrays (no copy of the
//! numbers beyond one into a `bytearray`: writable arrays, owned by Python). A growth study
//! ([`softway::run::grow::grow`], the command line's `softway grow`) runs the same way, its
//! passes reported as they finish.

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict, PyList};
use softway::build::resolve;
use softway::growth::{report, spectrum, GrowthConfig, PassLine, StudyState};
use softway::mesh::CellKind;
use softway::run::grow::GrowOptions;
use softway::run::{Cancel, Columns, Par, ProgressWatch, Results, RunOptions};
use softway::scenario::overrides::{apply, Override};
use softway::scenario::{Scenario, ScenarioError as ScError};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// Runs `f` in a rayon pool of this call's own, `threads` threads (None: rayon's default,
/// the cores), which ends with the call. Nothing of the engine runs in rayon's
/// process-wide pool, so that no worker thread or lock of softway outlives a call: a
/// process forked afterwards (`concurrent.futures.ProcessPoolExecutor`,
/// `multiprocessing`'s default on Linux) starts with no pool whose threads it lacks. (A
/// child of a process whose global pool was started waits forever on its first parallel
/// loop: the pool's threads are not copied by `fork`.)
fn in_pool<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .thread_name(|i| format!("softway-{i}"))
        .build()
        .map_err(|e| format!("cannot start the run's threads: {e}"))?;
    Ok(pool.install(f))
}

create_exception!(
    _native,
    ScenarioError,
    PyValueError,
    "A scenario refused by the validation: the file, the key and what is allowed, on one line (the command line's message). `key` is the dotted key at fault (None where the parser names no key)."
);
create_exception!(
    _native,
    RunError,
    PyRuntimeError,
    "A run that failed: a model that cannot be built, a run stopped by the divergence guard, an output not written."
);

/// The dotted key an error names (`bar.length`, `runs[1].h`): the validation's own; for the
/// parser's errors (`text` the scenario's text) the key at the line and column the message
/// gives, found in the parsed document (with the table of a `[table]` or `[[runs]]` header,
/// the index of an array's entry, the keys of an inline table), then the field the message
/// names (`missing field `f`` at a table's header); without a position, the field named.
fn error_key(e: &ScError, text: Option<&str>) -> Option<String> {
    match e {
        ScError::Invalid { key, .. } | ScError::Missing { key, .. } => Some(key.clone()),
        ScError::Parse { message, .. } => {
            let between = |s: &str, open: &str| -> Option<String> {
                let i = s.find(open)? + open.len();
                let j = s[i..].find('`')?;
                Some(s[i..i + j].to_string())
            };
            let missing = between(message, "missing field `");
            if let Some(at) = text.and_then(|t| key_at(t, message)) {
                return Some(match missing {
                    Some(f) if !at.ends_with(&format!(".{f}")) && at != f => format!("{at}.{f}"),
                    _ => at,
                });
            }
            // Without a position: the table a message starts with (`[growth]: ...`), then
            // the field it names, or the key of the line it stopped at.
            let table = message
                .strip_prefix('[')
                .and_then(|m| m.split_once("]: "))
                .map(|(t, _)| t.to_string());
            let field = missing
                .map(|f| {
                    match between(message, "(`[")
                        .and_then(|t| t.strip_suffix(']').map(String::from))
                    {
                        Some(t) => format!("{t}.{f}"),
                        None => f,
                    }
                })
                .or_else(|| between(message, "unknown field `"))
                .or_else(|| {
                    between(message, "(`")
                        .and_then(|l| l.split('=').next().map(|k| k.trim().to_string()))
                        .filter(|k| !k.is_empty())
                })?;
            Some(match table {
                Some(t) => format!("{t}.{field}"),
                None => field,
            })
        }
        ScError::Io { .. } => None,
    }
}

/// The dotted key of the scenario text `text` at the `line L, column C` a parser's message
/// gives: the deepest key (or table header, or array entry) whose span holds that byte.
fn key_at(text: &str, message: &str) -> Option<String> {
    use toml::de::{DeTable, DeValue};
    let rest = &message[message.find("line ")? + "line ".len()..];
    let (line, rest) = rest.split_once(", column ")?;
    let line: usize = line.parse().ok()?;
    let column: usize = rest
        .split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()?;
    let start: usize = text
        .split('\n')
        .take(line.checked_sub(1)?)
        .map(|l| l.len() + 1)
        .sum();
    let pos = start + column.checked_sub(1)?;
    let doc = DeTable::parse(text).ok()?;
    fn walk(
        t: &DeTable<'_>,
        prefix: &str,
        depth: usize,
        pos: usize,
        best: &mut Option<(usize, String)>,
    ) {
        fn found(best: &mut Option<(usize, String)>, depth: usize, path: &str) {
            if best.as_ref().is_none_or(|(d, _)| depth > *d) {
                *best = Some((depth, path.to_string()));
            }
        }
        for (k, v) in t.iter() {
            let path = if prefix.is_empty() {
                k.get_ref().to_string()
            } else {
                format!("{prefix}.{}", k.get_ref())
            };
            if k.span().contains(&pos) || v.span().contains(&pos) {
                found(best, depth, &path);
            }
            match v.get_ref() {
                DeValue::Table(t) => walk(t, &path, depth + 1, pos, best),
                DeValue::Array(a) => {
                    for (i, e) in a.iter().enumerate() {
                        let entry = format!("{path}[{i}]");
                        if e.span().contains(&pos) {
                            found(best, depth + 1, &entry);
                        }
                        if let DeValue::Table(t) = e.get_ref() {
                            walk(t, &entry, depth + 2, pos, best);
                        }
                    }
                }
                _ => {}
            }
        }
    }
    let mut best = None;
    walk(doc.get_ref(), "", 0, pos, &mut best);
    best.map(|(_, k)| k)
}

/// The Python exception of `e`, its `key` the dotted key at fault (`text`: the scenario's
/// text, for the position of a parser's error).
fn scenario_error(e: ScError, text: Option<&str>) -> PyErr {
    let key = error_key(&e, text);
    let err = ScenarioError::new_err(e.to_string());
    Python::with_gil(|py| {
        let _ = err.value(py).setattr("key", key);
    });
    err
}

/// Parses, validates and builds the scenario text `text` (named `path` in errors, its
/// relative mesh paths read from `path`'s folder).
fn build(text: &str, path: &str) -> PyResult<Scenario> {
    in_pool(Some(1), || {
        Scenario::from_str(text, Path::new(path)).and_then(|sc| resolve(&sc))
    })
    .map_err(RunError::new_err)?
    .map_err(|e| scenario_error(e, Some(text)))
}

/// Validates a scenario: returns its name, kind, warnings, default sweep, SHA-256 and runs'
/// labels; raises ScenarioError with the command line's message.
#[pyfunction]
fn check<'py>(py: Python<'py>, text: &str, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let sc = build(text, path)?;
    let d = PyDict::new(py);
    d.set_item("name", &sc.name)?;
    d.set_item("kind", sc.runs[0].model.kind())?;
    d.set_item("description", &sc.description)?;
    d.set_item("warnings", sc.warnings.clone())?;
    d.set_item("sweep", sc.sweep.clone())?;
    d.set_item("sweep_ladder", sc.sweep_ladder.clone())?;
    d.set_item("sweep_ladder_with", sc.sweep_ladder_with.clone())?;
    d.set_item("sha256", &sc.source_sha256)?;
    d.set_item(
        "runs",
        sc.runs.iter().map(|r| r.label.clone()).collect::<Vec<_>>(),
    )?;
    Ok(d)
}

/// Reads and validates the scenario file `path` as the command line does; raises its
/// ScenarioError (a file that cannot be read: missing, a folder, a pipe, not UTF-8).
#[pyfunction]
fn check_file(path: PathBuf) -> PyResult<()> {
    in_pool(Some(1), || Scenario::from_file(&path))
        .map_err(RunError::new_err)?
        .map_err(|e| {
            let text = std::fs::read_to_string(&path).ok();
            scenario_error(e, text.as_deref())
        })?;
    Ok(())
}

/// The text of the scenario file `path` as the command line reads it
/// ([`softway::scenario::read_text`]: a regular file of at most 16 MiB, UTF-8); raises its
/// ScenarioError otherwise (missing, a folder, a pipe or a device, too large, not UTF-8).
#[pyfunction]
fn read_scenario(path: PathBuf) -> PyResult<String> {
    softway::scenario::read_text(&path)
        .map_err(|source| scenario_error(ScError::Io { path, source }, None))
}

/// Sets the dotted key `key` to the TOML literal `value` in the scenario text exactly as
/// `softway run --set` and `softway sweep --set` write it (the same text, so the same
/// `scenario_sha256`); the text is not validated here.
#[pyfunction]
fn set_key(text: &str, key: &str, value: &str) -> PyResult<String> {
    let set = [Override {
        key: key.to_string(),
        value: value.to_string(),
    }];
    apply(text, &set).map_err(|m| {
        let err = ScenarioError::new_err(format!("`{key}` = {value}: {m}"));
        Python::with_gil(|py| {
            let _ = err.value(py).setattr("key", key);
        });
        err
    })
}

/// The one-line message of a grid the core refuses, in Python's words (`mode='zip'` for
/// `--grid zip`, no `--set`).
fn grid_message(m: &str) -> String {
    m.replace(
        "give --set KEY=V1,V2,...",
        "give at least one key and its values",
    )
    .replace("--grid zip: ", "mode='zip': ")
    .replace("--set ", "")
    .replace(
        " (a key with one value is set at every point; or --grid product)",
        " (a key with one value is set at every point; or mode='product')",
    )
}

/// Every point of a sweep checked before any runs, by the core as `softway sweep` checks
/// them: the grid ([`softway::scenario::overrides::grid`]: keys given once, each with
/// values, a zip's lists of one length), then each point's folder name and its scenario
/// with the point's values set in ([`softway::run::check_points`]: each value
/// refused by its dotted key, a point given twice). `keys`: each dotted key and its values
/// as TOML literals. Returns each point's value indices (in the keys' order) and its folder
/// name (`key=value,...`, as `softway sweep` names it). Raises ScenarioError (a ValueError)
/// with the command line's message and `key` the dotted key at fault.
#[pyfunction]
fn sweep_points(
    py: Python<'_>,
    text: &str,
    path: &str,
    keys: Vec<(String, Vec<String>)>,
    mode: &str,
) -> PyResult<(Vec<Vec<usize>>, Vec<String>)> {
    use softway::run::{check_points, point_dir_name, PointRefused};
    use softway::scenario::overrides::{grid, Grid};
    let how = match mode {
        "product" => Grid::Product,
        "zip" => Grid::Zip,
        other => {
            return Err(PyValueError::new_err(format!(
                "mode={other:?}: 'product' or 'zip'"
            )))
        }
    };
    let keyed = |m: String, key: Option<String>| {
        let err = ScenarioError::new_err(m);
        let _ = err.value(py).setattr("key", key);
        err
    };
    let points = grid(&keys, how).map_err(|m| {
        // The key a grid's message names (`--set K=: no values`, `--set K: given twice`).
        let key = keys
            .iter()
            .map(|(k, _)| k)
            .find(|k| m.contains(&format!("--set {k}:")) || m.contains(&format!("--set {k}=:")))
            .cloned();
        keyed(grid_message(&m), key)
    })?;
    let index: Vec<Vec<usize>> = points
        .iter()
        .map(|p| {
            p.iter()
                .zip(&keys)
                .map(|(o, (_, vs))| vs.iter().position(|v| *v == o.value).unwrap_or(0))
                .collect()
        })
        .collect();
    // A value given twice in a product (or a zip) is a point whose folder is another's:
    // the indices above then name its first copy, so they are taken from the grid of
    // indices instead.
    let by_index: Vec<(String, Vec<String>)> = keys
        .iter()
        .map(|(k, vs)| (k.clone(), (0..vs.len()).map(|i| i.to_string()).collect()))
        .collect();
    let index = match grid(&by_index, how) {
        Ok(ix) => ix
            .iter()
            .map(|p| p.iter().map(|o| o.value.parse().unwrap_or(0)).collect())
            .collect(),
        Err(_) => index,
    };
    let checked =
        py.allow_threads(|| in_pool(Some(1), || check_points(Path::new(path), text, &points)));
    match checked.map_err(RunError::new_err)? {
        Ok(_) => {}
        Err(r) => {
            let sets = &points[r.point()];
            let join =
                |f: &dyn Fn(&Override) -> &str| sets.iter().map(f).collect::<Vec<_>>().join(",");
            let (k, v) = (join(&|o| o.key.as_str()), join(&|o| o.value.as_str()));
            // The message as `softway sweep` prints it (`KEY = VALUE: why`), the key the
            // validation names (the swept key for a folder's refusal).
            let key = match &r {
                PointRefused::Scenario { error, .. } => {
                    let run_text = apply(text, sets).ok();
                    match error {
                        ScError::Parse { message, .. } if message.starts_with("--set ") => message
                            ["--set ".len()..]
                            .split_once('=')
                            .map(|(k, _)| k.to_string()),
                        _ => error_key(error, run_text.as_deref()),
                    }
                }
                PointRefused::Folder { .. } => Some(k.clone()),
            };
            return Err(keyed(format!("{k} = {v}: {}", r.message()), key));
        }
    }
    Ok((index, points.iter().map(|p| point_dir_name(p)).collect()))
}

/// The names of the history a run of the scenario text `text` (named `path`) gives, as
/// `Result.history` names them (`time` for `t_s`, the key column's name, every other
/// column): the run built and stopped before its first step (a cancelled token), so the
/// names are the engine's own, not a list kept here.
#[pyfunction]
fn history_names(py: Python<'_>, text: &str, path: &str) -> PyResult<Vec<String>> {
    let sc = build(text, path)?;
    let cancel = Cancel::new();
    cancel.cancel();
    let opts = RunOptions {
        progress: false,
        par: Some(Par::Seq),
        cancel,
        ..RunOptions::default()
    };
    let results = py
        .allow_threads(|| in_pool(Some(1), || softway::run(&sc, &opts)))
        .map_err(RunError::new_err)?
        .map_err(|e| RunError::new_err(e.to_string()))?;
    let h = &results.history;
    let mut names: Vec<String> = h.key().map(|k| k.name.clone()).into_iter().collect();
    names.extend(h.columns().iter().map(|c| {
        if c.name == "t_s" {
            "time".to_string()
        } else {
            c.name.clone()
        }
    }));
    Ok(names)
}

/// The unit of a swept scenario key (`rolling.omega` -> `rad/s`), from the core's
/// [`softway::run::KEY_UNITS`] (the unit of `sweep.csv`'s key column), else the
/// unit its name carries (`rolling.speed_km_h` -> `km/h`); None for a key without one.
#[pyfunction]
fn key_unit(key: &str) -> Option<String> {
    let column = softway::run::key_column(key);
    match column.strip_prefix(&format!("{key}_")) {
        Some(suffix) => Some(suffix_unit(suffix)),
        None => name_unit(key.rsplit('.').next().unwrap_or(key)),
    }
}

/// The unit of a summary's number (`mean_contact_force` -> `N`, `speed_m_s` -> `m/s`):
/// the unit of its column in `sweep.csv` ([`softway::run::column_name`]), else the
/// unit its name ends with; None for a count or a ratio.
#[pyfunction]
fn summary_unit(name: &str) -> Option<String> {
    let column = softway::run::column_name(name);
    match column.strip_prefix(&format!("{name}_")) {
        Some(suffix) => Some(suffix_unit(suffix)),
        None => name_unit(name),
    }
}

/// A column name's unit suffix as a unit: the first `_` is "per" (`rad_s` -> `rad/s`,
/// `kg_m3` -> `kg/m3`, `N_m` -> `N/m`).
fn suffix_unit(suffix: &str) -> String {
    suffix.replacen('_', "/", 1)
}

/// The unit at the end of a name (the engine's names carry theirs: `speed_m_s`,
/// `contact_stiffness_n_m`, `dominant_frequency_hz`, `max_j2_turn_average_mpa2`); the
/// longest ending first, so that `_m_s` is m/s and not s.
fn name_unit(name: &str) -> Option<String> {
    const ENDINGS: [(&str, &str); 22] = [
        ("_db_per_1e5", "dB per 1e5 real passes"),
        ("_rad_s", "rad/s"),
        ("_km_h", "km/h"),
        ("_kg_m3", "kg/m3"),
        ("_m_s", "m/s"),
        ("_n_m", "N/m"),
        ("_N_m", "N/m"),
        ("_mpa2", "MPa^2"),
        ("_mpa", "MPa"),
        ("_MPa", "MPa"),
        ("_pa", "Pa"),
        ("_Pa", "Pa"),
        ("_hz", "Hz"),
        ("_Hz", "Hz"),
        ("_deg", "deg"),
        ("_mib", "MiB"),
        ("_us", "us"),
        ("_db", "dB re 1 um"),
        ("_n", "N"),
        ("_N", "N"),
        ("_J", "J"),
        ("_m", "m"),
    ];
    if let Some((_, u)) = ENDINGS.iter().find(|(e, _)| name.ends_with(e)) {
        return Some((*u).to_string());
    }
    name.ends_with("_s").then(|| "s".to_string())
}

/// Writes the files `files` (`(name, bytes)`, a saved result's as [`NativeResults::files`]
/// gives them) into `folder` under the command line's folder rules
/// ([`softway::run::save_files`]: written whole or not at all, a folder of other
/// files refused unless `force`, the current and the home folder never replaced, marked as
/// softway's and `interrupted` when the run was). Returns their paths.
#[pyfunction]
#[pyo3(signature = (folder, files, interrupted, force=false))]
fn save_files(
    py: Python<'_>,
    folder: PathBuf,
    files: Vec<(String, Vec<u8>)>,
    interrupted: bool,
    force: bool,
) -> PyResult<Vec<PathBuf>> {
    py.allow_threads(|| softway::run::save_files(&folder, &files, interrupted, force))
        .map_err(|e| RunError::new_err(e.to_string()))
}

/// Claims `folder` for a study of `command` written in place (`sweep(out=)`) under the
/// command line's folder rules ([`softway::run::claim_folder`]: a folder of the user's files
/// or of another command's results refused unless `force`, the current and the home folder
/// and the scenario's folder never replaced); the folder is then empty and marked.
#[pyfunction]
#[pyo3(signature = (folder, command, force=false, scenario=None))]
fn claim_folder(
    py: Python<'_>,
    folder: PathBuf,
    command: String,
    force: bool,
    scenario: Option<PathBuf>,
) -> PyResult<PathBuf> {
    py.allow_threads(|| {
        let inputs: Vec<&std::path::Path> = scenario.iter().map(PathBuf::as_path).collect();
        softway::run::claim_folder(&folder, &command, force, &inputs)
    })
    .map_err(|e| RunError::new_err(e.to_string()))
}

/// The TOML text of a scenario given as JSON (a Python dict through `json.dumps`).
#[pyfunction]
fn json_to_toml(json: &str) -> PyResult<String> {
    let v: toml::Value = serde_json::from_str(json)
        .map_err(|e| ScenarioError::new_err(format!("<dict>: not a TOML table: {e}")))?;
    match v {
        toml::Value::Table(t) => {
            toml::to_string(&t).map_err(|e| ScenarioError::new_err(format!("<dict>: {e}")))
        }
        _ => Err(ScenarioError::new_err(
            "<dict>: a scenario is a table of keys (a dict)",
        )),
    }
}

/// The results of a run, held by Rust; the Python class `softway.Result` reads them.
#[pyclass(module = "softway._native", frozen)]
struct NativeResults(Results);

/// A little-endian copy of `v` as a Python bytearray (numpy views it as a writable array:
/// the one copy of the numbers, owned by Python).
fn f64_bytes<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyByteArray> {
    let mut b = Vec::with_capacity(v.len() * 8);
    for x in v {
        b.extend_from_slice(&x.to_le_bytes());
    }
    PyByteArray::new(py, &b)
}

/// A table as `(key, columns)`: `key` None or `(name, labels, codes)`, `columns` a list of
/// `(name, unit, bytes)`.
fn table<'py>(py: Python<'py>, t: &Columns) -> PyResult<PyObject> {
    let key = t.key().map(|k| {
        let codes: Vec<f64> = k.codes.iter().map(|&c| c as f64).collect();
        (k.name.clone(), k.labels.clone(), f64_bytes(py, &codes))
    });
    let cols = PyList::empty(py);
    for c in t.columns() {
        cols.append((c.name.clone(), c.unit.clone(), f64_bytes(py, &c.values)))?;
    }
    Ok((key, cols).into_pyobject(py)?.into_any().unbind())
}

#[pymethods]
impl NativeResults {
    /// The model's kind.
    #[getter]
    fn kind(&self) -> &'static str {
        self.0.kind
    }

    /// `summary.json`'s object as JSON text.
    #[getter]
    fn summary_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.0.summary).map_err(|e| RunError::new_err(e.to_string()))
    }

    /// The screen summary's lines.
    #[getter]
    fn lines(&self) -> Vec<String> {
        self.0.lines.clone()
    }

    /// The run's warnings.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.0.warnings.clone()
    }

    /// True when the run was interrupted.
    #[getter]
    fn interrupted(&self) -> bool {
        self.0.interrupted
    }

    /// A table by name: `history`, `contact_nodes`, `traction_history`, `rim_profile`
    /// (None when the run has none).
    fn table(&self, py: Python<'_>, name: &str) -> PyResult<Option<PyObject>> {
        let t = match name {
            "history" => Some(&self.0.history),
            "contact_nodes" => self.0.contact_nodes.as_ref(),
            "traction_history" => self.0.traction_history.as_ref(),
            "rim_profile" => self.0.rim_profile.as_ref(),
            _ => return Err(PyValueError::new_err(format!("no table `{name}`"))),
        };
        t.map(|t| table(py, t)).transpose()
    }

    /// The fields: `(mesh, frames)`; `mesh` None or `(dim, coords bytes, cell kind, nodes
    /// per cell, cells bytes)`, each frame `(file, time, displacement bytes or None,
    /// point data, cell data)` with the data `[(name, components, bytes)]`.
    fn fields(&self, py: Python<'_>) -> PyResult<PyObject> {
        let f = &self.0.fields;
        let mesh = f.mesh.as_ref().map(|m| {
            // meshio's and pyvista's names of the cells (VTK's node order: the core's
            // `CellKind::vtk_order`).
            let k = m.cells.kind();
            let kind = match k {
                CellKind::Bar2 => "line",
                CellKind::Tri3 => "triangle",
                CellKind::Tet4 => "tetra",
                CellKind::Tet10 => "tetra10",
                CellKind::Hex8 => "hexahedron",
            };
            let per = k.nodes();
            let flat: Vec<f64> = m
                .cells
                .connectivity()
                .chunks_exact(per)
                .flat_map(|c| k.vtk_order().iter().map(|&j| c[j] as f64))
                .collect();
            (
                m.dim,
                f64_bytes(py, &m.coords),
                kind,
                per,
                f64_bytes(py, &flat),
            )
        });
        let arrays =
            |a: &[softway::run::FieldArray]| -> Vec<(String, usize, Bound<'_, PyByteArray>)> {
                a.iter()
                    .map(|x| (x.name.clone(), x.components, f64_bytes(py, &x.values)))
                    .collect()
            };
        let frames: Vec<_> = f
            .frames
            .iter()
            .map(|fr| {
                (
                    fr.file.clone(),
                    fr.time,
                    fr.displacement.as_ref().map(|d| f64_bytes(py, d)),
                    arrays(&fr.point_data),
                    arrays(&fr.cell_data),
                )
            })
            .collect();
        Ok((mesh, frames).into_pyobject(py)?.into_any().unbind())
    }

    /// The files [`NativeResults::save`] writes, as `(name, bytes)` in the order it lists
    /// them: written by the core's [`Results::save`] into `scratch` (an empty folder the
    /// caller removes), read back. What a pickled `Result` carries, so that `save` works
    /// where it is unpickled ([`save_files`]).
    fn files<'py>(
        &self,
        py: Python<'py>,
        scratch: PathBuf,
    ) -> PyResult<Vec<(String, Bound<'py, pyo3::types::PyBytes>)>> {
        let read = py
            .allow_threads(|| -> Result<Vec<(String, Vec<u8>)>, String> {
                let files = in_pool(None, || self.0.save(&scratch))?.map_err(|e| e.to_string())?;
                files
                    .iter()
                    .map(|f| {
                        let name = f
                            .strip_prefix(&scratch)
                            .map_err(|_| format!("{}: outside {}", f.display(), scratch.display()))?
                            .to_string_lossy()
                            .into_owned();
                        let bytes = std::fs::read(f)
                            .map_err(|e| format!("cannot read {}: {e}", f.display()))?;
                        Ok((name, bytes))
                    })
                    .collect()
            })
            .map_err(RunError::new_err)?;
        Ok(read
            .into_iter()
            .map(|(n, b)| (n, pyo3::types::PyBytes::new(py, &b)))
            .collect())
    }

    /// Writes the command line's files into `folder` under the command line's folder
    /// rules (written whole; a folder of other files refused unless `force`; the current
    /// and the home folder never replaced); returns their paths.
    #[pyo3(signature = (folder, force=false))]
    fn save(&self, py: Python<'_>, folder: PathBuf, force: bool) -> PyResult<Vec<PathBuf>> {
        py.allow_threads(|| {
            in_pool(None, || self.0.save_folder(&folder, force))?.map_err(|e| e.to_string())
        })
        .map_err(RunError::new_err)
    }
}

/// Runs the scenario text `text` (named `path`) on a thread of its own, `threads` threads
/// (None: the cores), and waits without the GIL, waking every `poll_s` seconds to call
/// `progress(label, done, steps)` (if given) and to handle Python's signals. A signal's
/// exception (KeyboardInterrupt) cancels the run, which stops at its next step; returns
/// `(results, exception or None)`.
#[pyfunction]
#[pyo3(signature = (text, path, threads=None, progress=None, poll_s=0.1))]
fn run(
    py: Python<'_>,
    text: &str,
    path: &str,
    threads: Option<usize>,
    progress: Option<PyObject>,
    poll_s: f64,
) -> PyResult<(NativeResults, Option<PyErr>)> {
    let sc = build(text, path)?;
    let cancel = Cancel::new();
    let watch = ProgressWatch::new();
    let opts = RunOptions {
        progress: false,
        par: threads.map(Par::threads),
        cancel: cancel.clone(),
        progress_watch: Some(watch.clone()),
        ..RunOptions::default()
    };
    let (tx, rx) = mpsc::channel();
    let worker = std::thread::Builder::new()
        .name("softway-run".into())
        .spawn(move || {
            let r = in_pool(threads, || softway::run(&sc, &opts));
            let _ = tx.send(());
            r
        })
        .map_err(|e| RunError::new_err(format!("cannot start the run's thread: {e}")))?;
    let poll = Duration::from_secs_f64(poll_s.clamp(0.01, 10.0));
    let rx = std::sync::Mutex::new(rx);
    let mut raised: Option<PyErr> = None;
    loop {
        let done = py.allow_threads(|| match rx.lock() {
            Ok(rx) => rx.recv_timeout(poll),
            Err(_) => Err(mpsc::RecvTimeoutError::Disconnected),
        });
        if !matches!(done, Err(mpsc::RecvTimeoutError::Timeout)) {
            break;
        }
        if let (Some(cb), Some((label, pos, len))) = (&progress, watch.get()) {
            if let Err(e) = cb.call1(py, (label, pos, len)) {
                cancel.cancel();
                raised.get_or_insert(e);
            }
        }
        if let Err(e) = py.check_signals() {
            cancel.cancel();
            raised.get_or_insert(e);
        }
    }
    let results = py
        .allow_threads(|| worker.join())
        .map_err(|_| RunError::new_err("the run's thread panicked"))?
        .map_err(RunError::new_err)?
        .map_err(|e| RunError::new_err(e.to_string()))?;
    if let (Some(cb), Some((label, pos, len))) = (&progress, watch.get()) {
        let _ = cb.call1(
            py,
            (label, pos.max(len * u64::from(!results.interrupted)), len),
        );
    }
    Ok((NativeResults(results), raised))
}

/// What the study's thread sends the waiting thread.
enum GrowMsg {
    /// A pass finished: its line.
    Pass(PassLine),
    /// The study ended.
    Done,
}

/// A growth study's results, held by Rust; the Python class `softway.GrowthResult` reads
/// them. The state is the study's checkpoint (every profile, bit for bit).
#[pyclass(module = "softway._native", frozen)]
struct NativeGrowth {
    summary_json: String,
    lines: Vec<String>,
    files: Vec<PathBuf>,
    interrupted: bool,
    passes_run: usize,
    passes_per_pass: f64,
    state: StudyState,
    config: GrowthConfig,
    speed_m_s: f64,
    plots: bool,
    scenario_copy: String,
}

#[pymethods]
impl NativeGrowth {
    /// `summary.json`'s object as JSON text.
    #[getter]
    fn summary_json(&self) -> &str {
        &self.summary_json
    }

    /// The screen summary's lines.
    #[getter]
    fn lines(&self) -> Vec<String> {
        self.lines.clone()
    }

    /// The files the study wrote (the command line's).
    #[getter]
    fn files(&self) -> Vec<PathBuf> {
        self.files.clone()
    }

    /// True when Ctrl-C stopped the study (the finished passes are kept).
    #[getter]
    fn interrupted(&self) -> bool {
        self.interrupted
    }

    /// Passes run by this call (not those resumed from).
    #[getter]
    fn passes_run(&self) -> usize {
        self.passes_run
    }

    /// Writes the command line's files of this state into `folder` (created as needed):
    /// `scenario.toml`, `checkpoint.json` (a study resumed from `folder` goes on from this
    /// state), the tables, `summary.json` and the plots, as `softway grow` writes them;
    /// the runner's own outputs written at the end of a study (the track's prediction) are
    /// copied from the study's folder. Returns their paths.
    #[pyo3(signature = (folder, force=false))]
    fn save(&self, py: Python<'_>, folder: PathBuf, force: bool) -> PyResult<Vec<PathBuf>> {
        py.allow_threads(|| {
            in_pool(None, || -> Result<Vec<PathBuf>, String> {
            // The study's own folder is written in place; another is claimed under the
            // command line's folder rules (a folder of other files refused unless `force`,
            // an older study there replaced whole). Either is marked as softway's:
            // `softway grow --resume` goes on in it.
            let own = self.files.first().and_then(|f| f.parent());
            let same = |a: &std::path::Path, b: &std::path::Path| {
                matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
            };
            if own.is_some_and(|d| same(d, &folder)) {
                softway::run::grow::mark_study_folder(&folder).map_err(|e| e.to_string())?;
            } else {
                softway::run::grow::claim_study_folder(&folder, force)
                    .map_err(|e| e.to_string())?;
            }
            let copy = folder.join(softway::run::SCENARIO_COPY);
            std::fs::write(&copy, &self.scenario_copy)
                .map_err(|e| format!("cannot write {}: {e}", copy.display()))?;
            let ck = folder.join(softway::growth::CHECKPOINT);
            self.state.write(&ck).map_err(|e| e.to_string())?;
            let mut files = vec![copy, ck];
            files.extend(
                report::write_all(
                    &folder,
                    &self.state,
                    &self.config,
                    self.speed_m_s,
                    (self.plots, self.interrupted),
                )
                .map_err(|e| e.to_string())?,
            );
            for f in &self.files {
                let Some(name) = f.file_name() else { continue };
                let to = folder.join(name);
                if files.contains(&to) || !f.is_file() || to == *f {
                    continue;
                }
                std::fs::copy(f, &to).map_err(|e| format!("cannot write {}: {e}", to.display()))?;
                files.push(to);
            }
            Ok(files)
            })
            .and_then(|r| r)
        })
        .map_err(RunError::new_err)
    }

    /// `passes.csv`'s columns: `[(name, bytes)]`, a row per finished pass.
    fn passes(&self, py: Python<'_>) -> PyResult<PyObject> {
        let st = &self.state;
        let mut loss = 0.0;
        let mut cols: Vec<(String, Vec<f64>)> =
            ["pass", "real_passes", "rms_m", "uniform_loss_m", "wall_s"]
                .iter()
                .map(|n| (n.to_string(), Vec::new()))
                .collect();
        if let Some(first) = st.passes.first() {
            cols.extend(first.scalar_names.iter().map(|n| (n.clone(), Vec::new())));
        }
        for (p, rec) in st.passes.iter().enumerate() {
            loss += rec.uniform_loss.0[0];
            let row = [
                p as f64,
                (p + 1) as f64 * self.passes_per_pass,
                spectrum::rms(&rec.z.0),
                loss,
                rec.wall_s,
            ];
            for (c, v) in cols.iter_mut().zip(row.iter().chain(&rec.scalar_values.0)) {
                c.1.push(*v);
            }
        }
        let out = PyList::empty(py);
        for (name, v) in &cols {
            out.append((name.clone(), f64_bytes(py, v)))?;
        }
        Ok(out.into_any().unbind())
    }

    /// The profiles: `(x0, dx, n, periodic, profiles, wear_last)`; `profiles` the initial
    /// one then one after each pass (`(passes + 1) x n` values), `wear_last` the last
    /// pass's smoothed wear (None before any pass).
    fn profiles(&self, py: Python<'_>) -> PyResult<PyObject> {
        let st = &self.state;
        let flat: Vec<f64> = st.profiles().concat();
        let wear = st.passes.last().map(|p| f64_bytes(py, &p.wear.0));
        Ok((
            st.x0.0[0],
            st.dx.0[0],
            st.n,
            st.periodic,
            f64_bytes(py, &flat),
            wear,
        )
            .into_pyobject(py)?
            .into_any()
            .unbind())
    }

    /// The one-third-octave band levels of every profile (`bands.csv`'s, before its
    /// rounding): `(centre wavelengths, first orders, last orders, levels)` with `levels`
    /// `(passes + 1) x bands` values, dB re 1 um.
    fn bands(&self, py: Python<'_>) -> PyResult<PyObject> {
        let st = &self.state;
        let b = spectrum::bands(st.n, st.n as f64 * st.dx.0[0]);
        let levels: Vec<f64> = st
            .profiles()
            .iter()
            .flat_map(|z| spectrum::band_levels(&spectrum::order_amplitudes(z), &b))
            .collect();
        let centre: Vec<f64> = b.iter().map(|b| b.centre).collect();
        let first: Vec<f64> = b.iter().map(|b| b.k_first as f64).collect();
        let last: Vec<f64> = b.iter().map(|b| b.k_last as f64).collect();
        Ok((
            f64_bytes(py, &centre),
            f64_bytes(py, &first),
            f64_bytes(py, &last),
            f64_bytes(py, &levels),
        )
            .into_pyobject(py)?
            .into_any()
            .unbind())
    }

    /// The polygon orders' amplitudes of every profile (`orders.csv`'s; periodic profiles):
    /// `(passes + 1) x orders` values, m (empty bytes for an open profile).
    fn orders<'py>(&self, py: Python<'py>) -> Bound<'py, PyByteArray> {
        let st = &self.state;
        let a: Vec<f64> = if st.periodic {
            st.profiles()
                .iter()
                .flat_map(|z| spectrum::order_amplitudes(z))
                .collect()
        } else {
            Vec::new()
        };
        f64_bytes(py, &a)
    }
}

/// Runs the growth study of the scenario text `text` (named `path`) into the folder `out`
/// (`softway grow`'s files and checkpoint; with `resume` it goes on from the checkpoint
/// there) to `passes` passes in all (None: `growth.passes`), on a thread of its own, and
/// waits without the GIL, waking every `poll_s` seconds to handle Python's signals and
/// calling `progress(pass, target, rms_m, uniform_loss_m, wall_s, scalars)` after every
/// pass. A signal's exception (KeyboardInterrupt) cancels the study: the pass under way
/// stops within a step and is dropped, the finished ones stay in the checkpoint. Returns
/// `(results, exception or None)`.
#[pyfunction]
#[pyo3(signature = (text, path, out, passes=None, resume=false, threads=None, progress=None, poll_s=0.1))]
#[allow(clippy::too_many_arguments)]
fn grow(
    py: Python<'_>,
    text: &str,
    path: &str,
    out: PathBuf,
    passes: Option<usize>,
    resume: bool,
    threads: Option<usize>,
    progress: Option<PyObject>,
    poll_s: f64,
) -> PyResult<(NativeGrowth, Option<PyErr>)> {
    let sc = build(text, path)?;
    let Some(config) = sc.growth.clone() else {
        let err = ScenarioError::new_err(
            softway::run::RunError::Input {
                path: sc.path.clone(),
                message: "no [growth] table: softway grow needs [growth] and [wear] (the book, docs/src/growth.md)".into(),
            }
            .to_string(),
        );
        err.value(py).setattr("key", "growth")?;
        return Err(err);
    };
    if passes == Some(0) {
        return Err(PyValueError::new_err("passes: at least 1"));
    }
    let cancel = Cancel::new();
    let (plots, scenario_copy) = (sc.plots, sc.provenance_text());
    // The threads as the pool the study runs in has them (`Par::current` there).
    let grow_opts = move || GrowOptions {
        passes,
        resume,
        plots,
        par: threads.map(Par::threads).unwrap_or_else(Par::current),
    };
    let (tx, rx) = mpsc::channel();
    let worker = {
        let (cancel, out) = (cancel.clone(), out.clone());
        std::thread::Builder::new()
            .name("softway-grow".into())
            .spawn(move || {
                let pass_tx = tx.clone();
                let r = in_pool(threads, || {
                    softway::run::grow::grow(&sc, &out, &grow_opts(), &cancel, |l| {
                        let _ = pass_tx.send(GrowMsg::Pass(l.clone()));
                    })
                });
                let _ = tx.send(GrowMsg::Done);
                r
            })
            .map_err(|e| RunError::new_err(format!("cannot start the study's thread: {e}")))?
    };
    let poll = Duration::from_secs_f64(poll_s.clamp(0.01, 10.0));
    let rx = std::sync::Mutex::new(rx);
    let mut raised: Option<PyErr> = None;
    loop {
        let msg = py.allow_threads(|| match rx.lock() {
            Ok(rx) => rx.recv_timeout(poll),
            Err(_) => Err(mpsc::RecvTimeoutError::Disconnected),
        });
        match msg {
            Ok(GrowMsg::Pass(l)) => {
                if let Some(cb) = &progress {
                    let scalars = PyDict::new(py);
                    for (k, v) in &l.scalars {
                        scalars.set_item(k, v)?;
                    }
                    let args = (l.pass, l.target, l.rms, l.uniform_loss, l.wall_s, scalars);
                    if let Err(e) = cb.call1(py, args) {
                        cancel.cancel();
                        raised.get_or_insert(e);
                    }
                }
            }
            Ok(GrowMsg::Done) | Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if let Err(e) = py.check_signals() {
            cancel.cancel();
            raised.get_or_insert(e);
        }
    }
    let report = py
        .allow_threads(|| worker.join())
        .map_err(|_| RunError::new_err("the study's thread panicked"))?
        .map_err(RunError::new_err)?
        .map_err(|e| RunError::new_err(e.to_string()))?;
    // The state is the checkpoint the study wrote after its last finished pass (none when
    // Ctrl-C stopped a new study's reference pass: the exception alone, then).
    let state = match StudyState::read(&out.join(softway::growth::CHECKPOINT)) {
        Ok(s) => s,
        Err(e) => return Err(raised.unwrap_or_else(|| RunError::new_err(e.to_string()))),
    };
    let summary_json =
        serde_json::to_string(&report.summary).map_err(|e| RunError::new_err(e.to_string()))?;
    Ok((
        NativeGrowth {
            summary_json,
            lines: softway::run::grow::summary_lines(&report.summary),
            files: report.files,
            interrupted: report.interrupted,
            passes_run: report.passes_run,
            passes_per_pass: config.passes_per_pass,
            state,
            config,
            speed_m_s: report.summary.speed_m_s,
            plots,
            scenario_copy,
        },
        raised,
    ))
}

/// The engine of the Python package `softway`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("RunError", m.py().get_type::<RunError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<NativeResults>()?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(claim_folder, m)?)?;
    m.add_function(wrap_pyfunction!(set_key, m)?)?;
    m.add_function(wrap_pyfunction!(check_file, m)?)?;
    m.add_function(wrap_pyfunction!(json_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(read_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_points, m)?)?;
    m.add_function(wrap_pyfunction!(history_names, m)?)?;
    m.add_function(wrap_pyfunction!(key_unit, m)?)?;
    m.add_function(wrap_pyfunction!(summary_unit, m)?)?;
    m.add_function(wrap_pyfunction!(save_files, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_class::<NativeGrowth>()?;
    m.add_function(wrap_pyfunction!(grow, m)?)?;
    Ok(())
}
