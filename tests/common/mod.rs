//! Helpers shared by the command-line tests: run the `softway` binary on scenario text and
//! check that bad input is refused on one line, with a non-zero exit, and nothing written.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The `softway` binary under test.
pub fn softway() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softway"))
}

/// A fresh, empty folder for one test (`<tmp>/softway-<tag>-<pid>-<name>`).
pub fn fresh_dir(tag: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("softway-{tag}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `text` as `<name>.toml` into a fresh folder of its own.
pub fn scenario(name: &str, text: &str) -> PathBuf {
    scenario_bytes(name, text.as_bytes())
}

/// Writes `bytes` as `<name>.toml` into a fresh folder of its own.
pub fn scenario_bytes(name: &str, bytes: &[u8]) -> PathBuf {
    let p = fresh_dir("cli", name).join(format!("{name}.toml"));
    std::fs::write(&p, bytes).unwrap();
    p
}

/// The paper's bar (Fig. 8) at a coarse step: a valid scenario that runs in milliseconds.
pub const BAR: &str = r#"
kind = "bar_impact"
[time]
alpha = 0.8
h = 0.1
t_end = 1.0
[bar]
length = 1.0
ea = 1.0
rho_a = 1.0
speed = 1.0
gap = 0.5
elements = 8
"#;

/// What a command did.
#[derive(Debug)]
pub struct Outcome {
    /// Exit code (-1: killed by a signal).
    pub code: i32,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

/// Runs `softway` with `args`.
pub fn cli<I, S>(args: I) -> Outcome
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    let o = softway().args(args).output().unwrap();
    let out = Outcome {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    };
    assert!(!out.stderr.contains("panicked"), "panic: {}", out.stderr);
    out
}

/// Asserts that `dir` holds no entry for the output folder `out` and no temporary folder or
/// file (nothing written for bad input).
pub fn assert_nothing_written(out: &Path) {
    assert!(!out.exists(), "{} was written for bad input", out.display());
    if let Some(parent) = out.parent().filter(|p| p.exists()) {
        for e in std::fs::read_dir(parent).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(
                !name.contains("softway-tmp") && !name.ends_with(".part"),
                "left behind: {name}"
            );
        }
    }
}

/// Runs `softway run` on the scenario file `p` into `<p>.out`; returns (exit code, stderr)
/// after checking that no panic happened and nothing was written.
pub fn run_file_err(p: &Path) -> (i32, String) {
    let out_dir = p.with_extension("out");
    let o = cli([
        "run".as_ref(),
        p.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_nothing_written(&out_dir);
    (o.code, o.stderr)
}

/// Runs `softway run` on the text; returns (exit code, stderr).
pub fn run_err(name: &str, text: &str) -> (i32, String) {
    run_file_err(&scenario(name, text))
}

/// Asserts the exit of an error (2) and exactly one line holding every string of `must`.
pub fn assert_one_line_error(code: i32, err: &str, must: &[&str]) {
    assert_eq!(code, 2, "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "expected one line, got: {err}");
    for m in must {
        assert!(err.contains(m), "`{m}` missing from: {err}");
    }
    record(err, code);
}

/// With `SOFTWAY_CATALOGUE=<file>` set, appends `code<TAB>message` to that file (the
/// bad-input catalogue of the docs is made from it).
fn record(err: &str, code: i32) {
    if let Ok(f) = std::env::var("SOFTWAY_CATALOGUE") {
        use std::io::Write as _;
        let case = std::thread::current()
            .name()
            .unwrap_or("?")
            .rsplit("::")
            .next()
            .unwrap_or("?")
            .to_string();
        if let Ok(mut file) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(f)
        {
            let _ = writeln!(file, "{case}\t{code}\t{}", err.trim());
        }
    }
}

/// Runs a valid scenario into `<file>.out`: the folder and its summary.
pub fn run_ok(p: &Path) -> (PathBuf, serde_json::Value) {
    let out = p.with_extension("out");
    let o = cli([
        "run".as_ref(),
        p.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    (out, s)
}

/// A fresh folder ([`fresh_dir`]) removed when dropped, unless the test is failing (then it
/// is kept for inspection).
pub struct TestDir(PathBuf);

impl TestDir {
    /// Creates the folder.
    pub fn new(tag: &str, name: &str) -> Self {
        TestDir(fresh_dir(tag, name))
    }
}

impl std::ops::Deref for TestDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

impl AsRef<Path> for TestDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

/// The shipped `scenarios/<name>.toml` with `keys` set (dotted keys, TOML literals): its
/// path, which anchors the scenario's relative mesh paths, and its text.
pub fn shipped(name: &str, keys: &[(&str, &str)]) -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"));
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (k, v) in keys {
        text = softway::scenario::set_key(&text, k, v).unwrap();
    }
    (path, text)
}

/// Runs scenario `text`, read as if it were the file `path`, in this process (the library,
/// no progress) into a fresh folder: the folder (removed when dropped) and its summary.
pub fn run_in_process(path: &Path, text: &str, name: &str) -> (TestDir, serde_json::Value) {
    use softway::scenario::Scenario;
    let sc = softway::build::resolve(&Scenario::from_str(text, path).unwrap()).unwrap();
    let dir = TestDir::new("lib", name);
    softway::run::run_scenario(&sc, &dir, &softway::run::RunOptions::default()).unwrap();
    let s =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    (dir, s)
}

/// Friction dissipates, from a run's `traction` block: the least slip speed that
/// a pair's dissipation implies (`min_slip_speed`, `slip_power / |F_t|`) is `>= 0` to the
/// round-off floor `1e3 eps omega R` of a sticking pair's end slip rate (a difference of
/// speeds of order `omega R`, held at 0 by its row; measured 1-30 `eps omega R`), and the
/// friction energy never falls in a step by more than those floors on the friction forces,
/// `h mu (2 P) 1e3 eps omega R` (`P` the mean normal force, doubled for the transients).
pub fn assert_dissipates(t: &serde_json::Value, omega: f64, h: f64) {
    let f = |k: &str| t[k].as_f64().unwrap();
    let floor = 1e3 * f64::EPSILON * omega * f("radius");
    let (speed, drop) = (f("min_slip_speed"), f("max_friction_energy_drop"));
    assert!(
        speed >= -floor,
        "a pair's dissipation implies a slip speed of {speed:e} m/s (floor -{floor:e})"
    );
    let drop_floor = h * f("friction") * 2.0 * f("normal").abs() * floor;
    assert!(
        drop <= drop_floor,
        "the friction energy falls by {drop:e} J in a step (floor {drop_floor:e})"
    );
}

/// The wheel-on-track tests' track (`tests/rolling.rs`, `tests/rolling_friction.rs`): UIC60
/// on `bays` bays, 20 of them absorbing at each end.
pub fn absorbing_track(bays: usize) -> softway::track::TrackSpec {
    softway::track::TrackSpec {
        bays,
        ends: softway::track::Ends::Absorbing {
            bays: 20,
            damping: 1000.0,
        },
        ..softway::track::TrackSpec::uic60()
    }
}

/// The wheel-on-track tests' wheel: 0.46 m of steel, 20 mm thick (plane strain), a graded
/// disk of `rim` rim nodes (grading 1.3) on a 0.1 m hub, turning at `speed / R_s`.
pub fn steel_wheel_at(rim: usize, speed: f64) -> softway::wheel::WheelModel {
    use softway::mesh::generators::{disk_graded, DiskOptions};
    use softway::wheel::{Support, WheelSpec};
    let mesh = disk_graded(
        0.46,
        rim,
        DiskOptions {
            hub: Some(0.1),
            grading: 1.3,
        },
    )
    .unwrap();
    let spec = WheelSpec {
        radius: 0.46,
        thickness: 0.02,
        plane: softway::material::PlaneModel::Strain,
        support: Support::Hub { radius: 0.1 },
        material: softway::material::Elastic {
            young: 2.1e11,
            poisson: 0.3,
            density: 7850.0,
        },
        ..WheelSpec::paper()
    };
    softway::track::rolling::wheel_at_speed(mesh, spec, speed).unwrap()
}

/// A bar run of about a second (15,000 steps of 2,001 dofs).
pub const LONG_BAR: &str = r#"
kind = "bar_impact"
[time]
alpha = 0.8
h = 2e-4
t_end = 3.0
[bar]
length = 1.0
ea = 1.0
rho_a = 1.0
speed = 1.0
gap = 0.25
elements = 2000
"#;

/// Asserts that no file or folder under `dir` (recursively) has a temporary name.
pub fn assert_no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        assert!(
            !(name.contains("softway-tmp")
                || name.contains("softway-old")
                || name.ends_with(".part")
                || name.ends_with(".tmp")
                || name.ends_with(".tmp.png")),
            "temporary left: {}",
            e.path().display()
        );
        if e.file_type().unwrap().is_dir() {
            assert_no_temporaries(&e.path());
        }
    }
}

/// The elastica of a cantilever of length 1 under a dead tip load `alpha = P L^2 / EI`
/// normal to its undeformed axis: `theta'' = -alpha cos theta`, `theta(0) = 0`,
/// `theta'(1) = 0`, shot on `theta'(0)` by bisection with RK4 on 4,000 steps (an
/// independent computation). Returns the tip's deflection and its shortening along the
/// axis, both over `L`, and the tip's rotation.
pub fn elastica(alpha: f64) -> (f64, f64, f64) {
    let n = 4000;
    let ds = 1.0 / n as f64;
    // State (theta, kappa, x, y).
    let run = |k0: f64| {
        let f = |s: [f64; 4]| [s[1], -alpha * s[0].cos(), s[0].cos(), s[0].sin()];
        let mut s = [0.0, k0, 0.0, 0.0];
        for _ in 0..n {
            let add = |a: [f64; 4], b: [f64; 4], h: f64| {
                [
                    a[0] + h * b[0],
                    a[1] + h * b[1],
                    a[2] + h * b[2],
                    a[3] + h * b[3],
                ]
            };
            let k1 = f(s);
            let k2 = f(add(s, k1, ds / 2.0));
            let k3 = f(add(s, k2, ds / 2.0));
            let k4 = f(add(s, k3, ds));
            for i in 0..4 {
                s[i] += ds / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        s
    };
    // kappa(1) is alpha-ish at k0 = 0 ... decreasing in k0: bracket [0, alpha].
    let (mut lo, mut hi) = (0.0, alpha);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if run(mid)[1] > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let s = run(0.5 * (lo + hi));
    (s[3], 1.0 - s[2], s[0])
}

/// A free body's problem for the space-time scheme at `gamma = 0` (`alpha = 0.8`, the
/// Coriolis term implicit): no supports, load, obstacle, pair or friction; `steps` steps of
/// `h` from `u0`, `v0`.
pub fn free_problem(
    dim: usize,
    reference: Vec<f64>,
    model: softway::model::LinearModel,
    h: f64,
    steps: usize,
    u0: Vec<f64>,
    v0: Vec<f64>,
) -> softway::simulation::Problem {
    use softway::time::{Coriolis, Integrator};
    softway::simulation::Problem {
        dim,
        reference,
        model,
        integrator: Integrator::SpaceTime {
            alpha: 0.8,
            gamma: 0.0,
            coriolis: Coriolis::Implicit,
        },
        h,
        gamma_schedule: Vec::new(),
        dirichlet: Vec::new(),
        load: Box::new(|_t: f64, f: &mut [f64]| f.fill(0.0)),
        obstacles: Vec::new(),
        interfaces: Vec::new(),
        pairs: Vec::new(),
        treatment: softway::contact::Treatment::SOFT_WAY,
        u0,
        v0,
        t0: 0.0,
        steps,
        gap_tol: 1e-12,
        energy_stiffness: None,
        friction: None,
    }
}
