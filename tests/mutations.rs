//! Property test (issue 33): random mutations of the shipped scenarios (`scenarios/*.toml`)
//! run through the command line never end in a panic, an abort, a signal or a hang, and
//! never in exit 0 with a result outside physical bounds.
//!
//! Each case takes one shipped scenario, shrinks it so that a run is short (one turn, a
//! coarse rim, a coarse bar), then applies one to three mutations drawn from a SplitMix64
//! generator of a fixed seed: a number scaled by `10^u`, `u` uniform in [-6, 6]; a sign
//! flipped; a key moved to another table; a key deleted. Cases whose estimated cost
//! ([`softway::build::estimate`]) is beyond a few seconds are counted and not run (a
//! mutation that shrinks the step by 1e6 makes a legitimate run of hours). The others run
//! with `softway run --quiet`, killed after [`TIME_LIMIT`], and must end in
//!
//! - exit 2 with one error line naming the scenario file (warnings before it allowed), or
//! - exit 0 with a summary whose figures are finite and physical: the energy of a model on
//!   which nothing works (the oscillator, the bars against a fixed wall, the wheel held by
//!   its hub, frictionless and elastic, after settling on a base that only turns; the base
//!   works on a pinned disk through its torque, on a plastic rim left out of round and
//!   through friction, and there the guard's bound with that work is the run's own) not
//!   above `kappa` times its initial energy plus
//!   the floor, [`softway::guard::ENERGY_FACTOR`] and [`softway::guard::ENERGY_FLOOR`], the
//!   divergence guard's own bound; contact forces that push (never pull); the penetration
//!   within the treatment's bound: a penalty spring's peak force over its stiffness, or
//!   (every treatment catches a node in the step it crosses) a step's travel at the
//!   approach speed (the bars' speed; the rim's `omega sqrt(2 R d)` under the turning
//!   base), with a factor 2.
//!
//! The same mutations go through `softway grow` (the elastic and the plastic wheel on the
//! rigid base, the wheel on the track: one or two passes) and `softway receptance` (issue
//! 47), each checked on its own outputs ([`check_growth`], [`check_receptance`]); every
//! command's CSV tables hold no `NaN` or `inf` cell.
//!
//! `SOFTWAY_MUTATIONS=N cargo test --release --test mutations` runs `N` cases of each
//! campaign (default [`DEFAULT_CASES`] runs and [`DEFAULT_COMMAND_CASES`] studies and
//! receptances, about a minute of CPU together).

mod common;

use common::{softway, TestDir};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use toml::{Table, Value};

/// Cases of a plain `cargo test`.
const DEFAULT_CASES: usize = 120;

/// A case is killed (and fails as a hang) after this long.
const TIME_LIMIT: Duration = Duration::from_secs(90);

/// Estimated run time (one core, [`softway::build::Estimate::seconds`]) above which a case
/// is not run.
const CASE_BUDGET_S: f64 = 1.0;

/// SplitMix64 (Steele, Lea, Flood 2014): a small generator whose sequence is fixed by its
/// seed on every platform.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A step of a path into the document: a table's key or an array's index.
#[derive(Debug, Clone, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

/// The paths of every leaf (a number, a bool, a string) and of every table.
fn walk(v: &Value, at: &mut Vec<Seg>, leaves: &mut Vec<Vec<Seg>>, tables: &mut Vec<Vec<Seg>>) {
    match v {
        Value::Table(t) => {
            tables.push(at.clone());
            for (k, x) in t {
                at.push(Seg::Key(k.clone()));
                walk(x, at, leaves, tables);
                at.pop();
            }
        }
        Value::Array(a) if a.iter().all(Value::is_table) && !a.is_empty() => {
            for (i, x) in a.iter().enumerate() {
                at.push(Seg::Index(i));
                walk(x, at, leaves, tables);
                at.pop();
            }
        }
        _ => leaves.push(at.clone()),
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.as_table_mut()?.get_mut(k),
        Seg::Index(i) => v.as_array_mut()?.get_mut(*i),
    })
}

fn show(path: &[Seg]) -> String {
    path.iter()
        .map(|s| match s {
            Seg::Key(k) => k.clone(),
            Seg::Index(i) => i.to_string(),
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Applies one random mutation to `doc`; returns what it did.
fn mutate(doc: &mut Value, rng: &mut SplitMix) -> String {
    let (mut leaves, mut tables) = (Vec::new(), Vec::new());
    walk(doc, &mut Vec::new(), &mut leaves, &mut tables);
    if leaves.is_empty() {
        return "nothing to mutate".into();
    }
    let path = leaves[rng.below(leaves.len())].clone();
    let (parent, Some(Seg::Key(key))) = (&path[..path.len() - 1], path.last().cloned()) else {
        return "an array element: left".into();
    };
    let leaf = get_mut(doc, &path).expect("a leaf found by walk").clone();
    let number = matches!(leaf, Value::Integer(_) | Value::Float(_));
    let op = if number {
        rng.below(4)
    } else {
        2 + rng.below(2)
    };
    let at = show(&path);
    match op {
        0 | 1 => {
            let factor = if op == 0 {
                10f64.powf(12.0 * rng.unit() - 6.0)
            } else {
                -1.0
            };
            let new = match leaf {
                Value::Integer(i) => {
                    let x = (i as f64 * factor).round();
                    if x.abs() < 9e18 {
                        Value::Integer(x as i64)
                    } else {
                        Value::Float(x)
                    }
                }
                Value::Float(x) => Value::Float(x * factor),
                other => other,
            };
            let shown = new.to_string();
            *get_mut(doc, &path).expect("the leaf") = new;
            format!("{at} = {shown}")
        }
        2 => {
            let to = tables[rng.below(tables.len())].clone();
            if let Some(t) = get_mut(doc, parent).and_then(Value::as_table_mut) {
                t.remove(&key);
            }
            if let Some(t) = get_mut(doc, &to).and_then(Value::as_table_mut) {
                t.insert(key.clone(), leaf);
            }
            let dest = show(&to);
            format!(
                "{at} moved to {}",
                if dest.is_empty() { "the top" } else { &dest }
            )
        }
        _ => {
            if let Some(t) = get_mut(doc, parent).and_then(Value::as_table_mut) {
                t.remove(&key);
            }
            format!("{at} deleted")
        }
    }
}

/// Makes a scenario's run short before it is mutated: one turn of the wheel on a coarse rim
/// (96 rim nodes: on 48 the plastic wheel's base chord spans less than a pitch, refused)
/// (and a step to match), at most 100 bar elements; a relative mesh path made absolute
/// (the case runs from another folder).
fn shrink(doc: &mut Table, dir: &Path) {
    let cap_int = |t: &mut Table, k: &str, max: i64| {
        if let Some(Value::Integer(i)) = t.get_mut(k) {
            *i = (*i).min(max);
        }
    };
    if let Some(Value::Table(r)) = doc.get_mut("rolling") {
        cap_int(r, "turns", 1);
    }
    let wheel = doc.get("kind").and_then(Value::as_str) == Some("wheel");
    if let Some(Value::Table(w)) = doc.get_mut("wheel") {
        cap_int(w, "rim_nodes", 96);
        cap_int(w, "rings", 4);
        if let Some(Value::String(m)) = w.get_mut("mesh") {
            if Path::new(m.as_str()).is_relative() {
                *m = dir.join(&*m).to_string_lossy().into_owned();
            }
        }
    }
    if wheel {
        // 96 rim nodes at 300 rad/s pass in 218 us: 10 us steps take 22 per passage.
        if let Some(Value::Table(t)) = doc.get_mut("time") {
            if let Some(Value::Float(h)) = t.get_mut("h") {
                *h = h.max(1e-5);
            }
        }
    }
    for table in ["bar", "two_bars"] {
        if let Some(Value::Table(b)) = doc.get_mut(table) {
            cap_int(b, "elements", 100);
        }
    }
    // The track: 30 bays (8 absorbing at each end), 2 recorded, a 360-node rim.
    if let Some(Value::Table(t)) = doc.get_mut("track") {
        cap_int(t, "bays", 30);
        cap_int(t, "end_bays", 8);
        // (The default absorbing ends, 30 bays each, would leave none between them.)
        t.entry("end_bays").or_insert(Value::Integer(8));
    }
    if let Some(Value::Table(v)) = doc.get_mut("vehicle") {
        cap_int(v, "travel_bays", 2);
        cap_int(v, "wheel_rim_nodes", 360);
    }
    if let Some(Value::Table(r)) = doc.get_mut("receptance") {
        cap_int(r, "points", 60);
    }
    // A growth study: one or two passes.
    if let Some(Value::Table(g)) = doc.get_mut("growth") {
        cap_int(g, "passes", 2);
    }
}

/// The outcome of one case, for the report.
#[derive(Debug, Default)]
struct Tally {
    ok: usize,
    refused: usize,
    long: usize,
}

/// Every run record of a summary: its `runs` entries, else the summary itself.
fn runs(s: &serde_json::Value) -> Vec<&serde_json::Value> {
    match s["runs"].as_array() {
        Some(a) if a.iter().all(|r| r.is_object()) && !a.is_empty() => a.iter().collect(),
        _ => vec![s],
    }
}

fn num(v: &serde_json::Value, k: &str) -> Option<f64> {
    v[k].as_f64()
}

/// The physical bounds a completed run's summary must meet (module docs); `Err` says which
/// is broken.
fn check_summary(s: &serde_json::Value, doc: &Table) -> Result<(), String> {
    use softway::guard::{ENERGY_FACTOR, ENERGY_FLOOR};
    let kind = s["kind"].as_str().unwrap_or("");
    // The penalty spring's stiffness, N/m, as the run's `contact` names it: `penalty(1e4)`.
    let penalty = |r: &serde_json::Value| -> Option<f64> {
        r["contact"]
            .as_str()?
            .strip_prefix("penalty(")?
            .strip_suffix(')')?
            .parse()
            .ok()
    };
    for r in runs(s) {
        let label = r["label"].as_str().unwrap_or("run");
        let finite = |k: &str| -> Result<f64, String> {
            match num(r, k) {
                Some(x) if x.is_finite() => Ok(x),
                _ => Err(format!("{label}: `{k}` is {} (not a finite number)", r[k])),
            }
        };
        match kind {
            "sdof" | "bar_impact" | "two_bars" => {
                let (e0, e1) = (finite("energy_initial")?, finite("energy_final")?);
                if e1 > ENERGY_FACTOR * e0 + ENERGY_FLOOR {
                    return Err(format!(
                        "{label}: energy {e0:e} -> {e1:e} J with no work done on the system"
                    ));
                }
                if kind == "sdof" {
                    continue;
                }
                let (mean, peak) = (finite("mean_contact_force")?, finite("peak_contact_force")?);
                if mean < 0.0 || peak < 0.0 {
                    return Err(format!(
                        "{label}: contact force pulls (mean {mean:e}, peak {peak:e} N)"
                    ));
                }
                // A node caught in the step it crosses the wall has gone at most a step's
                // travel past it (the bars' relative speed: at most twice the speed); a
                // penalty spring holds the peak force at `F / k`, give or take a step's
                // travel (the force reported is the step's, the penetration its end's).
                let pen = finite("max_penetration")?;
                let travel = 2.0 * bar_speed(doc) * finite("h")?;
                let bound = 1.01 * penalty(r).map_or(travel, |k| travel + peak / k) + 1e-12;
                if pen > bound {
                    return Err(format!(
                        "{label}: penetration {pen:e} m beyond the treatment's bound {bound:e} m"
                    ));
                }
            }
            "wheel" => {
                let (e0, e1) = (finite("energy_after_settling")?, finite("energy_final")?);
                // The turning base works on a wheel through friction, on a rim that plastic
                // flow has left out of round, and on a pinned disk through its torque about
                // the pin (its rigid rotation, which only the contact holds): for those the
                // bound is the guard's, which counts that work (the run enforces it).
                let friction = doc.get("contact").and_then(|c| c.get("friction")).is_some();
                let plastic = doc
                    .get("material")
                    .and_then(|m| m.get("model"))
                    .and_then(Value::as_str)
                    .is_some_and(|m| m != "elastic");
                let pinned = doc
                    .get("wheel")
                    .and_then(|w| w.get("support"))
                    .and_then(Value::as_str)
                    .is_some_and(|s| s == "centre" || s == "center");
                if !(friction || plastic || pinned) && e1 > ENERGY_FACTOR * e0 + ENERGY_FLOOR {
                    return Err(format!(
                        "{label}: energy {e0:e} J after settling -> {e1:e} J at the end, on a base that only turns"
                    ));
                }
                let (min, max) = (finite("min_contact_force")?, finite("max_contact_force")?);
                if min < -1e-9 * max.abs() - 1e-9 {
                    return Err(format!(
                        "{label}: contact force pulls (min {min:e} N, max {max:e} N)"
                    ));
                }
                let pen = finite("max_penetration")?;
                let radius = s["radius"]
                    .as_f64()
                    .or_else(|| {
                        doc.get("wheel")
                            .and_then(|w| w.get("radius"))
                            .and_then(Value::as_float)
                    })
                    .unwrap_or(0.1);
                // A rim node meets the turning base at about omega a (a = sqrt(2 R d), the
                // patch's half-width): caught within the step, it is at most a step's travel
                // (twice that, for margin) inside; a penalty spring holds `F / k`.
                let omega = finite("omega")?.abs();
                let d = finite("flattening_m")?.abs();
                let travel = 2.0 * omega * (2.0 * radius * d).sqrt() * finite("h")?;
                let bound = 1.01 * travel.max(penalty(r).map_or(0.0, |k| max / k)) + 1e-12;
                if pen > bound {
                    return Err(format!(
                        "{label}: penetration {pen:e} m beyond the treatment's bound {bound:e} m"
                    ));
                }
            }
            _ => {
                for k in r
                    .as_object()
                    .map(|o| o.keys().cloned().collect::<Vec<_>>())
                    .unwrap_or_default()
                {
                    // A figure the run does not have is null (the moving load's dominant
                    // amplitude on a record too short for a peak); a number must be finite.
                    if (k.ends_with("_m") || k.ends_with("_N")) && !r[&k].is_null() {
                        finite(&k)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// A growth study's summary: the passes it was asked for, profile RMS finite and not
/// negative, every band's and order's rate finite where it has one (`null` where the
/// initial profile leaves the band empty), the profile's change bounded by what the wear
/// can do (the final RMS within the initial plus the uniform loss's order, a factor 1e3).
fn check_growth(s: &serde_json::Value, out: &Path) -> Result<(), String> {
    let passes = s["passes"].as_u64().unwrap_or(0);
    if passes == 0 || s["interrupted"] != false {
        return Err(format!("{passes} passes, interrupted {}", s["interrupted"]));
    }
    let f = |k: &str| -> Result<f64, String> {
        match s[k].as_f64() {
            Some(x) if x.is_finite() && x >= 0.0 => Ok(x),
            _ => Err(format!("`{k}` = {}", s[k])),
        }
    };
    let (r0, r1) = (f("rms_initial_m")?, f("rms_final_m")?);
    let loss = s["uniform_loss_m"].as_f64().unwrap_or(f64::NAN);
    if !loss.is_finite() || r1 > 1e3 * (r0 + loss.abs()) + 1e-12 {
        return Err(format!(
            "a profile RMS {r0:e} -> {r1:e} m with a uniform loss of {loss:e} m"
        ));
    }
    for list in ["bands", "orders"] {
        for b in s[list].as_array().into_iter().flatten() {
            let r = &b["rate_db_per_1e5"];
            if !(r.is_null() || r.as_f64().is_some_and(f64::is_finite)) {
                return Err(format!("a rate of {r} in {list}"));
            }
        }
    }
    if !out.join("checkpoint.json").is_file() {
        return Err("no checkpoint.json".into());
    }
    Ok(())
}

/// A receptance: every magnitude positive and finite, every phase finite.
fn check_receptance(out: &Path) -> Result<(), String> {
    let t = std::fs::read_to_string(out.join("receptance.csv"))
        .map_err(|e| format!("no receptance.csv: {e}"))?;
    let mut lines = t.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let mut rows = 0;
    for line in lines {
        rows += 1;
        for (h, c) in head.iter().zip(line.split(',')) {
            let x: f64 = c.parse().map_err(|_| format!("`{c}` under {h}"))?;
            if !x.is_finite() || (h.contains("mag") && x <= 0.0) {
                return Err(format!("{h} = {x}"));
            }
        }
    }
    if rows < 2 {
        return Err(format!("{rows} rows in receptance.csv"));
    }
    Ok(())
}

/// No cell of the folder's CSV tables is `NaN` or infinite (an empty cell is no value).
fn finite_tables(out: &Path) -> Result<(), String> {
    for e in std::fs::read_dir(out).map_err(|e| e.to_string())? {
        let p = e.map_err(|e| e.to_string())?.path();
        if p.extension().is_none_or(|x| x != "csv") {
            continue;
        }
        let t = std::fs::read_to_string(&p).map_err(|e| e.to_string())?;
        for (i, line) in t.lines().enumerate().skip(1) {
            if let Some(c) = line.split(',').find(|c| {
                let c = c.trim().to_ascii_lowercase();
                c.contains("nan") || c.contains("inf")
            }) {
                return Err(format!("`{c}` in {} line {}", p.display(), i + 1));
            }
        }
    }
    Ok(())
}

/// The bar's speed (m/s) as the scenario gives it (1 m/s, the paper's, if not found).
fn bar_speed(doc: &Table) -> f64 {
    ["bar", "two_bars"]
        .iter()
        .find_map(|t| doc.get(*t)?.get("speed")?.as_float())
        .map_or(1.0, f64::abs)
}

/// Runs `softway ARGS` with the time limit; `None` when killed at the limit.
fn run_limited(cmd: &mut Command) -> Option<std::process::Output> {
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = std::io::Read::read_to_end(&mut err, &mut s);
        s
    });
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let stderr = reader.join().unwrap();
            return Some(std::process::Output {
                status,
                stdout: Vec::new(),
                stderr,
            });
        }
        if start.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// One case: scenario `k mod n`, seed `0x5eed_0000 + k`. `Err` describes a failure.
fn case(k: usize, shipped: &[PathBuf], dir: &Path, tally: &mut Tally) -> Result<(), String> {
    case_of(k, &shipped[k % shipped.len()], dir, tally)
}

/// The command a case runs its mutated scenario through.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cmd {
    /// `softway run`.
    Run,
    /// `softway grow` (its passes as the shrunk scenario says: one or two).
    Grow,
    /// `softway receptance`.
    Receptance,
}

impl Cmd {
    fn name(self) -> &'static str {
        match self {
            Cmd::Run => "run",
            Cmd::Grow => "grow",
            Cmd::Receptance => "receptance",
        }
    }
}

/// Case `k`'s mutations (seeded by `k`) of the scenario `src`, through `softway run`.
fn case_of(k: usize, src: &Path, dir: &Path, tally: &mut Tally) -> Result<(), String> {
    case_with(Cmd::Run, k, src, dir, tally)
}

/// Case `k`'s mutations (seeded by `k`) of the scenario `src`, through `cmd`.
fn case_with(cmd: Cmd, k: usize, src: &Path, dir: &Path, tally: &mut Tally) -> Result<(), String> {
    let mut rng = SplitMix(0x5eed_0000 + k as u64);
    let mut doc: Table = toml::from_str(&std::fs::read_to_string(src).unwrap()).unwrap();
    shrink(&mut doc, src.parent().unwrap());
    let mut value = Value::Table(doc);
    let what: Vec<String> = (0..1 + rng.below(3))
        .map(|_| mutate(&mut value, &mut rng))
        .collect();
    let Value::Table(doc) = value else {
        unreachable!("the document stays a table")
    };
    let stem = src.file_stem().unwrap().to_string_lossy();
    let name = match cmd {
        Cmd::Run => format!("case{k}-{stem}"),
        other => format!("{}{k}-{stem}", other.name()),
    };
    let path = dir.join(format!("{name}.toml"));
    let text = toml::to_string(&doc).unwrap();
    std::fs::write(&path, &text).unwrap();
    let tag = format!("{} case {k} ({stem}: {})", cmd.name(), what.join("; "));
    // Too long for the suite: counted, not run (a study: its passes and its reference
    // pass, each a run).
    if let Ok(sc) = softway::scenario::Scenario::from_str(&text, &path) {
        if let Ok(built) = softway::build::resolve(&sc) {
            let runs = match (cmd, &sc.growth) {
                (Cmd::Grow, Some(g)) => g.passes as f64 + f64::from(u8::from(g.reference)),
                _ => 1.0,
            };
            if cmd != Cmd::Receptance
                && runs * softway::build::estimate(&built, None).seconds
                    > CASE_BUDGET_S * runs.min(4.0)
            {
                tally.long += 1;
                return Ok(());
            }
        }
    }
    let out = dir.join(format!("{name}.out"));
    let mut command = softway();
    command.arg(cmd.name()).arg(&path).arg("--out").arg(&out);
    match cmd {
        Cmd::Run => {
            command.arg("--quiet");
        }
        Cmd::Grow => {
            command.args(["--threads", "1"]);
        }
        Cmd::Receptance => {}
    }
    let Some(o) = run_limited(&mut command) else {
        return Err(format!("{tag}: no end after {TIME_LIMIT:?} (a hang)"));
    };
    let err = String::from_utf8_lossy(&o.stderr);
    match o.status.code() {
        None => Err(format!("{tag}: killed by a signal: {:?}\n{err}", o.status)),
        Some(0) => {
            let s: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(out.join("summary.json"))
                    .map_err(|e| format!("{tag}: exit 0 without a summary: {e}"))?,
            )
            .map_err(|e| format!("{tag}: summary.json: {e}"))?;
            match cmd {
                Cmd::Run => check_summary(&s, &doc),
                Cmd::Grow => check_growth(&s, &out),
                Cmd::Receptance => check_receptance(&out),
            }
            .and_then(|()| finite_tables(&out))
            .map_err(|m| format!("{tag}: exit 0 with {m}"))?;
            tally.ok += 1;
            let _ = std::fs::remove_dir_all(&out);
            Ok(())
        }
        Some(2) => {
            let errors: Vec<&str> = err
                .lines()
                .filter(|l| !l.trim().is_empty() && !l.starts_with("softway: warning: "))
                .collect();
            if errors.len() != 1
                || !errors[0].starts_with("softway: error: ")
                || !errors[0].contains(&format!("{name}.toml"))
            {
                return Err(format!(
                    "{tag}: exit 2 without one error line naming the file:\n{err}"
                ));
            }
            // A study stopped by its keys after a pass keeps its folder and checkpoint (the
            // README's "written in place"); any other refusal writes nothing.
            let stopped = cmd == Cmd::Grow && errors[0].contains(": pass ");
            if out.exists() && !stopped {
                return Err(format!("{tag}: exit 2 with {} written", out.display()));
            }
            tally.refused += 1;
            Ok(())
        }
        Some(c) => Err(format!("{tag}: exit {c}\n{err}")),
    }
}

/// The shipped scenarios, sorted.
fn shipped() -> Vec<PathBuf> {
    let scenarios = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut shipped: Vec<PathBuf> = std::fs::read_dir(&scenarios)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    shipped.sort();
    shipped
}

/// Case 95 of the campaign (`creep-curve.toml` with `wheel.radius = 402.88`, a wheel of
/// 400 m whose traction profile has no bin in the patch): it panicked in the traction
/// plot (an index into the empty profile, exit 101); now it is refused before the run, in
/// one line naming the file (its spin stretches the rim 97 times its radius).
#[test]
fn a_creep_curve_wheel_of_400_m_is_not_a_panic() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/creep-curve.toml");
    let dir = TestDir::new("mut", "case95");
    case_of(95, &src, &dir, &mut Tally::default()).unwrap();
}

/// Cases of the 2,000-case campaign that ended outside bounds, now refused or stopped in one
/// line naming the file:
/// - 1185 (`polygon.toml` with `rolling.settle_time` = 6 ns): the base pressed 1 mm in within
///   a step struck the wheel (0.67 mm of penetration, 0.002 J -> 523 J, exit 0); a settling
///   shorter than one period of the wheel's bounce on its support and contact is refused;
/// - 1649 (`wheel-plastic.toml` with `wheel.hub_radius` = 2.7 um): the hub concentrated the
///   plastic flow without bound (113 iterations a step, 192 unconverged solves, a plastic
///   strain of 180, 75 s instead of the estimated second); a solve whose plastic iteration
///   does not converge stops the run;
/// - 1801 (`bar-impact.toml` with `bar.gap` = 31 m): the bar never reached the wall before
///   `t_end` and the summary's contact figures were null (exit 0); refused before the run;
///
/// and of the 5,000-case campaign:
/// - 3266 (`compare-bar.toml` with `bar.length` = 375 km): the central difference's `cfl`
///   step (8,447 s) exceeded the run (4 s), nothing was computed and the contact figures
///   were null (exit 0); a `cfl` step beyond `t_end` is refused;
/// - 4312 (`wheel-paper-mesh.toml` on 4 rings, `rolling.settle_time` = 1.4 us): the base
///   struck the wheel (0.004 J -> 516 J) where the bounce's mode is not found (the rim too
///   coarse to hold a node), so the settling is checked against the time a compression
///   wave takes to cross the disk there.
#[test]
fn the_campaigns_cases_outside_bounds_are_refused() {
    let dir = TestDir::new("mut", "campaign2000");
    let scenarios = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    for (k, name) in [
        (1185, "polygon.toml"),
        (1649, "wheel-plastic.toml"),
        (1801, "bar-impact.toml"),
        (3266, "compare-bar.toml"),
        (4312, "wheel-paper-mesh.toml"),
    ] {
        let mut tally = Tally::default();
        case_of(k, &scenarios.join(name), &dir, &mut tally).unwrap();
        assert_eq!((tally.refused, tally.ok, tally.long), (1, 0, 0), "case {k}");
    }
}

#[test]
fn mutated_scenarios_end_in_a_physical_result_or_a_one_line_refusal() {
    let n: usize = std::env::var("SOFTWAY_MUTATIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let shipped = shipped();
    let dir = TestDir::new("mut", "cases");
    let mut tally = Tally::default();
    let mut failures = Vec::new();
    for k in 0..n {
        if let Err(m) = case(k, &shipped, &dir, &mut tally) {
            failures.push(m);
        }
    }
    eprintln!(
        "mutations: {n} cases: {} ran to a result within bounds, {} refused on one line, {} too long for the suite (estimate > {CASE_BUDGET_S} s); {} failures",
        tally.ok,
        tally.refused,
        tally.long,
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // The suite exercises both outcomes.
    if n >= DEFAULT_CASES {
        assert!(tally.ok > 0 && tally.refused > 0, "{tally:?}");
    }
}

/// The scenarios of each command beyond `run`: the growth studies (elastic and plastic on
/// the rigid base, the rail's) through `softway grow`, the track through `softway
/// receptance`. (The track's and the block's runs are among the shipped scenarios of
/// [`mutated_scenarios_end_in_a_physical_result_or_a_one_line_refusal`], shrunk.)
fn commands() -> Vec<(Cmd, PathBuf)> {
    let s = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    vec![
        (Cmd::Grow, s.join("polygon.toml")),
        (Cmd::Grow, s.join("polygon-plastic.toml")),
        (Cmd::Grow, s.join("corrugation.toml")),
        (Cmd::Grow, s.join("corrugation-friction.toml")),
        (Cmd::Grow, s.join("polygon-track.toml")),
        (Cmd::Receptance, s.join("track.toml")),
        (Cmd::Receptance, s.join("track-traction.toml")),
    ]
}

/// Cases of a plain `cargo test` over [`commands`] (about two minutes of CPU: a pass of
/// the plastic wheel takes seconds).
const DEFAULT_COMMAND_CASES: usize = 20;

#[test]
fn mutated_studies_and_receptances_end_in_a_physical_result_or_a_one_line_refusal() {
    let n: usize = std::env::var("SOFTWAY_MUTATIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_COMMAND_CASES);
    let commands = commands();
    let dir = TestDir::new("mut", "commands");
    let mut tallies: Vec<Tally> = commands.iter().map(|_| Tally::default()).collect();
    let mut failures = Vec::new();
    for k in 0..n {
        let j = k % commands.len();
        let (cmd, src) = &commands[j];
        if let Err(m) = case_with(*cmd, 10_000 + k, src, &dir, &mut tallies[j]) {
            failures.push(m);
        }
    }
    for ((cmd, src), t) in commands.iter().zip(&tallies) {
        eprintln!(
            "mutations: {} {}: {} within bounds, {} refused on one line, {} too long",
            cmd.name(),
            src.file_name().unwrap().to_string_lossy(),
            t.ok,
            t.refused,
            t.long
        );
    }
    eprintln!(
        "mutations: {n} cases over grow and receptance; {} failures",
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    if n >= DEFAULT_COMMAND_CASES {
        let ok: usize = tallies.iter().map(|t| t.ok).sum();
        let refused: usize = tallies.iter().map(|t| t.refused).sum();
        assert!(ok > 0 && refused > 0, "{tallies:?}");
    }
}

/// Case 10060 of the 250-case campaign over the commands (`polygon.toml` through `softway
/// grow` with `material.young` = 2.2e16 Pa): the wheel 1e5 times steel's stiffness under
/// the flattening wears 14 cm in a pass; the study stops by its wear keys after the pass,
/// and said "pass 0: ..." without the scenario file; it now names it.
#[test]
fn the_study_campaigns_case_outside_bounds_is_refused_naming_the_file() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let dir = TestDir::new("mut", "case10060");
    let mut tally = Tally::default();
    case_with(Cmd::Grow, 10_060, &src, &dir, &mut tally).unwrap();
    assert_eq!((tally.refused, tally.ok, tally.long), (1, 0, 0));
}
