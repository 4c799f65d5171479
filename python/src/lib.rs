//! `softway._native`: the engine for the Python package `softway` (python/softway/).
//!
//! A thin layer over the library: the scenario's validation ([`Scenario::from_str`],
//! [`resolve`]) with its one-line errors as `ScenarioError` carrying the key, and a run
//! ([`softway::run()`], results in memory) on a thread of its own while the calling thread
//! waits without the GIL, waking every `poll_s` to report the progress and to let Python
//! handle its signals: a KeyboardInterrupt cancels the run's token ([`Cancel`]), which stops
//! it at its next step with what it has computed. The tables and fields cross as raw
//! little-endian `f64` bytes that the Python side views as numpy arrays (no copy of the
//! numbers beyond one into `bytes`).

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use softway::build::resolve;
use softway::mesh::Cells;
use softway::run::{Cancel, Columns, Par, ProgressWatch, Results, RunOptions};
use softway::scenario::overrides::{apply, Override};
use softway::scenario::{Scenario, ScenarioError as ScError};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

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

/// The dotted key an error names: the validation's own, or for the parser's errors the
/// field it names (`unknown field `x``) or the key of the line it stopped at.
fn error_key(e: &ScError) -> Option<String> {
    match e {
        ScError::Invalid { key, .. } | ScError::Missing { key, .. } => Some(key.clone()),
        ScError::Parse { message, .. } => {
            let between = |s: &str, open: &str| -> Option<String> {
                let i = s.find(open)? + open.len();
                let j = s[i..].find('`')?;
                Some(s[i..i + j].to_string())
            };
            // A table's missing key: `missing field `f`` at the table's header `[t]`.
            let missing = between(message, "missing field `").map(|f| {
                match between(message, "(`[").and_then(|t| t.strip_suffix(']').map(String::from)) {
                    Some(t) => format!("{t}.{f}"),
                    None => f,
                }
            });
            missing
                .or_else(|| between(message, "unknown field `"))
                .or_else(|| {
                    between(message, "(`")
                        .and_then(|l| l.split('=').next().map(|k| k.trim().to_string()))
                        .filter(|k| !k.is_empty())
                })
        }
        ScError::Io { .. } => None,
    }
}

fn scenario_error(e: ScError) -> PyErr {
    let key = error_key(&e);
    let err = ScenarioError::new_err(e.to_string());
    Python::with_gil(|py| {
        let _ = err.value(py).setattr("key", key);
    });
    err
}

/// Parses, validates and builds the scenario text `text` (named `path` in errors, its
/// relative mesh paths read from `path`'s folder).
fn build(text: &str, path: &str) -> PyResult<Scenario> {
    Scenario::from_str(text, Path::new(path))
        .and_then(|sc| resolve(&sc))
        .map_err(scenario_error)
}

/// Validates a scenario: returns its name, kind, warnings, default sweep, SHA-256 and runs'
/// labels; raises ScenarioError with the command line's message.
#[pyfunction]
fn check<'py>(py: Python<'py>, text: &str, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let sc = build(text, path)?;
    let d = PyDict::new(py);
    d.set_item("name", &sc.name)?;
    d.set_item(
        "kind",
        match &sc.runs[0].model {
            softway::scenario::Model::Sdof(_) => "sdof",
            softway::scenario::Model::BarImpact(_) => "bar_impact",
            softway::scenario::Model::TwoBars(_) => "two_bars",
            softway::scenario::Model::Wheel(_) => "wheel",
            softway::scenario::Model::Track(_) => "track",
        },
    )?;
    d.set_item("description", &sc.description)?;
    d.set_item("warnings", sc.warnings.clone())?;
    d.set_item("sweep", sc.sweep.clone())?;
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
    Scenario::from_file(&path).map_err(scenario_error)?;
    Ok(())
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

/// A little-endian copy of `v` as Python bytes.
fn f64_bytes<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyBytes> {
    let mut b = Vec::with_capacity(v.len() * 8);
    for x in v {
        b.extend_from_slice(&x.to_le_bytes());
    }
    PyBytes::new(py, &b)
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
            let (kind, per, flat): (&str, usize, Vec<f64>) = match &m.cells {
                Cells::Bar2(c) => ("line", 2, c.iter().flatten().map(|&i| i as f64).collect()),
                Cells::Tri3(c) => (
                    "triangle",
                    3,
                    c.iter().flatten().map(|&i| i as f64).collect(),
                ),
            };
            (
                m.dim,
                f64_bytes(py, &m.coords),
                kind,
                per,
                f64_bytes(py, &flat),
            )
        });
        let arrays = |a: &[softway::run::FieldArray]| -> Vec<(String, usize, Bound<'_, PyBytes>)> {
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

    /// Writes the command line's files into `folder` (created as needed); returns their
    /// paths.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<Vec<PathBuf>> {
        py.allow_threads(|| {
            std::fs::create_dir_all(&folder)
                .map_err(|e| format!("cannot write {}: {e}", folder.display()))?;
            self.0.save(&folder).map_err(|e| e.to_string())
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
            let r = softway::run(&sc, &opts);
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
        .map_err(|e| RunError::new_err(e.to_string()))?;
    if let (Some(cb), Some((label, pos, len))) = (&progress, watch.get()) {
        let _ = cb.call1(
            py,
            (label, pos.max(len * u64::from(!results.interrupted)), len),
        );
    }
    Ok((NativeResults(results), raised))
}

/// The engine of the Python package `softway`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("RunError", m.py().get_type::<RunError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<NativeResults>()?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(set_key, m)?)?;
    m.add_function(wrap_pyfunction!(check_file, m)?)?;
    m.add_function(wrap_pyfunction!(json_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    Ok(())
}
