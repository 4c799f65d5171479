//! The promises every command makes about its output folder, tested once over the list of
//! commands (`softway::output::job`'s one path): for each command x each case,
//!
//! | case | expected |
//! |---|---|
//! | a folder of the user's files (a `summary.json` and a subfolder among them), no `--force` | exit 2 naming `--force`, the folder untouched, nothing beside it |
//! | the current folder, with `--force` | exit 2 naming the current folder, untouched |
//! | the home folder (`$HOME`), with `--force` | exit 2 naming the home folder, untouched |
//! | the folder of the command's input (the scenario, the shards), with `--force` | exit 2 naming it, untouched |
//! | SIGTERM mid-run | exit 130 within a bounded time, the folder written whole, its marker saying `interrupted`, no temporary left |
//! | a run beyond the cost limits, no `--yes` | exit 2 naming `--yes`, nothing written |
//!
//! A command to which a case cannot apply says why in [`COMMANDS`] (`stability` and
//! `shakedown` read no input file; `gather` and `stability` finish in milliseconds, before a
//! signal can land mid-run).

mod common;

use common::{assert_no_temporaries, softway, TestDir, LONG_BAR};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

/// A bar run of a few seconds (60,000 steps of 2,001 dofs): [`LONG_BAR`] at a quarter of
/// its step.
fn long_bar() -> String {
    LONG_BAR.replace("h = 2e-4", "h = 5e-5")
}

/// The inputs of the commands, in one folder of their own (`inputs`).
struct Fixture {
    root: TestDir,
    inputs: PathBuf,
}

impl Fixture {
    /// The inputs in a folder of the test `name`'s own (the tests run side by side).
    fn new(name: &str) -> Fixture {
        let root = TestDir::new("rules", name);
        let inputs = root.join("inputs");
        std::fs::create_dir_all(&inputs).unwrap();
        std::fs::write(inputs.join("bar.toml"), common::BAR).unwrap();
        std::fs::write(inputs.join("long.toml"), long_bar()).unwrap();
        let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
        for name in ["polygon", "wheel", "track"] {
            std::fs::copy(
                shipped.join(format!("{name}.toml")),
                inputs.join(format!("{name}.toml")),
            )
            .unwrap();
        }
        // A track whose receptance takes minutes (100,000 frequencies): for the signal.
        let track = std::fs::read_to_string(inputs.join("track.toml")).unwrap();
        std::fs::write(
            inputs.join("track-long.toml"),
            softway::scenario::set_key(&track, "receptance.points", "100000").unwrap(),
        )
        .unwrap();
        // The shards of a sweep, gathered by `gather`.
        let shards = root.join("shards");
        for i in 1..=2 {
            let o = softway()
                .arg("sweep")
                .arg(inputs.join("bar.toml"))
                .args([
                    "--set",
                    "time.h=0.1,0.05",
                    "--shard",
                    &format!("{i}/2"),
                    "--out",
                ])
                .arg(shards.join(format!("s{i}")))
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        Fixture { root, inputs }
    }

    fn input(&self, name: &str) -> OsString {
        self.inputs.join(name).into_os_string()
    }
}

/// What a command is run with: its arguments before `--out DIR`, for a quick run, a long
/// one (the signal), and one beyond the cost limits; `None` with the reason where a case
/// cannot apply.
struct Cmd {
    name: &'static str,
    quick: fn(&Fixture) -> Vec<OsString>,
    long: Result<fn(&Fixture) -> Vec<OsString>, &'static str>,
    costly: Result<fn(&Fixture) -> Vec<OsString>, &'static str>,
    /// The folder of the command's input (never replaced), or why it has none.
    input_folder: Result<fn(&Fixture) -> PathBuf, &'static str>,
}

fn os(v: &[&str]) -> Vec<OsString> {
    v.iter().map(OsString::from).collect()
}

fn with(first: &[&str], input: OsString, rest: &[&str]) -> Vec<OsString> {
    let mut v = os(first);
    v.push(input);
    v.extend(os(rest));
    v
}

fn scenario_folder(f: &Fixture) -> PathBuf {
    f.inputs.clone()
}

const COMMANDS: &[Cmd] = &[
    Cmd {
        name: "run",
        quick: |f| with(&["run"], f.input("bar.toml"), &["--quiet"]),
        long: Ok(|f| with(&["run"], f.input("long.toml"), &["--quiet"])),
        costly: Ok(|f| {
            with(
                &["run"],
                f.input("long.toml"),
                &["--quiet", "--set", "time.h=1e-9"],
            )
        }),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "sweep",
        quick: |f| {
            with(
                &["sweep"],
                f.input("bar.toml"),
                &["--set", "time.h=0.1,0.05"],
            )
        },
        long: Ok(|f| {
            with(
                &["sweep"],
                f.input("long.toml"),
                &["--set", "time.h=5e-5,2.5e-5", "--jobs", "1"],
            )
        }),
        costly: Ok(|f| {
            with(
                &["sweep"],
                f.input("long.toml"),
                &["--set", "time.h=1e-9,2e-9"],
            )
        }),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "sweep --shard",
        quick: |f| {
            with(
                &["sweep"],
                f.input("bar.toml"),
                &["--set", "time.h=0.1,0.05", "--shard", "1/2"],
            )
        },
        long: Ok(|f| {
            with(
                &["sweep"],
                f.input("long.toml"),
                &[
                    "--set",
                    "time.h=5e-5,2.5e-5,1.25e-5",
                    "--shard",
                    "1/1",
                    "--jobs",
                    "1",
                ],
            )
        }),
        costly: Ok(|f| {
            with(
                &["sweep"],
                f.input("long.toml"),
                &["--set", "time.h=1e-9,2e-9", "--shard", "1/2"],
            )
        }),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "gather",
        quick: |f| {
            let s = f.root.join("shards");
            vec!["gather".into(), s.join("s1").into(), s.join("s2").into()]
        },
        long: Err("joins finished shards in milliseconds: no signal lands mid-run"),
        costly: Err("runs nothing: it joins the shards' tables"),
        input_folder: Ok(|f| f.root.join("shards").join("s1")),
    },
    Cmd {
        name: "converge",
        quick: |f| {
            with(
                &["converge"],
                f.input("bar.toml"),
                &["--set", "bar.elements=4,8,16"],
            )
        },
        long: Ok(|f| {
            with(
                &["converge"],
                f.input("long.toml"),
                &["--set", "bar.elements=500,1000,2000", "--jobs", "1"],
            )
        }),
        costly: Ok(|f| {
            with(
                &["converge"],
                f.input("long.toml"),
                &["--set", "time.h=4e-9,2e-9,1e-9"],
            )
        }),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "compare",
        quick: |f| with(&["compare"], f.input("bar.toml"), &[]),
        long: Ok(|f| with(&["compare"], f.input("long.toml"), &[])),
        costly: Ok(|f| {
            with(
                &["compare"],
                f.input("long.toml"),
                &["--set", "time.h=1e-9"],
            )
        }),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "grow",
        quick: |f| {
            with(
                &["grow"],
                f.input("polygon.toml"),
                &[
                    "--passes",
                    "1",
                    "--set",
                    "wheel.rim_nodes=96",
                    "--set",
                    "rolling.settle_time=5e-4",
                    "--set",
                    "growth.reference=false",
                ],
            )
        },
        long: Ok(|f| {
            with(
                &["grow"],
                f.input("polygon.toml"),
                &[
                    "--passes",
                    "40",
                    "--set",
                    "wheel.rim_nodes=96",
                    "--set",
                    "rolling.settle_time=5e-4",
                ],
            )
        }),
        costly: Ok(|f| with(&["grow"], f.input("polygon.toml"), &["--passes", "100000"])),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "modes",
        quick: |f| {
            with(
                &["modes"],
                f.input("wheel.toml"),
                &["--count", "2", "--set", "wheel.rim_nodes=96"],
            )
        },
        long: Ok(|f| with(&["modes"], f.input("wheel.toml"), &["--count", "12"])),
        costly: Err(
            "one eigensolve of a model that `run` would build: bounded by the model's validation",
        ),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "receptance",
        quick: |f| with(&["receptance"], f.input("track.toml"), &[]),
        long: Ok(|f| with(&["receptance"], f.input("track-long.toml"), &[])),
        costly: Err("at most 100,000 frequencies of a track the validation bounds"),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "matrix",
        quick: |f| with(&["matrix"], f.input("bar.toml"), &["--steps", "5"]),
        long: Ok(|f| with(&["matrix"], f.input("long.toml"), &["--steps", "200000"])),
        costly: Err("writes one model's matrices; --steps is bounded by its parser"),
        input_folder: Ok(scenario_folder),
    },
    Cmd {
        name: "stability",
        quick: |_| os(&["stability"]),
        long: Err("an analytic table computed in microseconds: no signal lands mid-run"),
        costly: Err("an analytic table: nothing to estimate"),
        input_folder: Err("reads no input file"),
    },
    Cmd {
        name: "shakedown",
        quick: |_| {
            os(&[
                "shakedown",
                "--p0-over-k",
                "3",
                "--passes",
                "1",
                "--h-over-a",
                "0.5",
            ])
        },
        long: Ok(|_| os(&["shakedown", "--p0-over-k", "5", "--passes", "1000"])),
        costly: Err("--passes is bounded by its parser (1,000)"),
        input_folder: Err("reads no input file"),
    },
];

/// Runs `softway ARGS --out OUT [extra]` in `cwd` with `$HOME` = `home`; its exit code and
/// standard error.
fn run_in(args: &[OsString], out: &Path, extra: &[&str], cwd: &Path, home: &Path) -> (i32, String) {
    let o = softway()
        .args(args)
        .arg("--out")
        .arg(out)
        .args(extra)
        .current_dir(cwd)
        .env("HOME", home)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!err.contains("panicked"), "panic: {err}");
    (o.status.code().unwrap_or(-1), err)
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A folder of the user's own files: a `summary.json` (a name softway writes), notes, a
/// subfolder.
fn users_folder(at: &Path) {
    std::fs::create_dir_all(at.join("figures")).unwrap();
    std::fs::write(at.join("summary.json"), "{\"mine\": true}").unwrap();
    std::fs::write(at.join("notes.txt"), "my notes").unwrap();
    std::fs::write(at.join("figures").join("fig1.txt"), "mine").unwrap();
}

fn assert_users_folder(at: &Path, what: &str) {
    assert_eq!(
        names(at),
        ["figures", "notes.txt", "summary.json"],
        "{what}"
    );
    assert_eq!(
        std::fs::read_to_string(at.join("notes.txt")).unwrap(),
        "my notes",
        "{what}"
    );
    assert_eq!(names(&at.join("figures")), ["fig1.txt"], "{what}");
}

/// Every command refuses, with or without `--force` as the case says, the folders it must
/// never replace, and leaves them as they were.
#[test]
fn every_command_keeps_the_users_folders() {
    let f = Fixture::new("folders");
    let mut checked = 0;
    for cmd in COMMANDS {
        let args = (cmd.quick)(&f);
        let base = f
            .root
            .join(format!("case-{}", cmd.name.replace([' ', '-'], "")));
        std::fs::create_dir_all(&base).unwrap();
        let home = base.join("home");
        users_folder(&home);

        // A folder of the user's files, without --force.
        let mine = base.join("mine");
        users_folder(&mine);
        let (code, err) = run_in(&args, &mine, &[], &base, &home);
        let what = format!("{}: a folder of the user's files", cmd.name);
        assert_eq!(code, 2, "{what}: {err}");
        assert!(
            err.contains("--force") && err.lines().count() == 1,
            "{what}: {err}"
        );
        assert_users_folder(&mine, &what);
        assert_eq!(
            names(&base),
            ["home", "mine"],
            "{what}: something written beside it"
        );

        // The current folder, even with --force.
        let cwd = base.join("cwd");
        users_folder(&cwd);
        let (code, err) = run_in(&args, &cwd, &["--force"], &cwd, &home);
        let what = format!("{}: the current folder", cmd.name);
        assert_eq!(code, 2, "{what}: {err}");
        assert!(err.contains("the current folder"), "{what}: {err}");
        assert_users_folder(&cwd, &what);

        // The home folder, even with --force.
        let (code, err) = run_in(&args, &home, &["--force"], &base, &home);
        let what = format!("{}: the home folder", cmd.name);
        assert_eq!(code, 2, "{what}: {err}");
        assert!(err.contains("the home folder"), "{what}: {err}");
        assert_users_folder(&home, &what);

        // The input's folder, even with --force.
        match cmd.input_folder {
            Ok(folder) => {
                let folder = folder(&f);
                let before = names(&folder);
                let (code, err) = run_in(&args, &folder, &["--force"], &base, &home);
                let what = format!("{}: the input's folder", cmd.name);
                assert_eq!(code, 2, "{what}: {err}");
                assert!(err.contains("the scenario's folder"), "{what}: {err}");
                assert_eq!(names(&folder), before, "{what}");
            }
            Err(why) => eprintln!("{}: no input folder: {why}", cmd.name),
        }

        // And the quick run itself writes a marked folder of its own.
        let fresh = base.join("fresh");
        let (code, err) = run_in(&args, &fresh, &[], &base, &home);
        assert_eq!(code, 0, "{}: {err}", cmd.name);
        let marker = std::fs::read_to_string(fresh.join(".softway")).unwrap_or_else(|e| {
            panic!(
                "{}: no marker in {}: {e}: {:?}",
                cmd.name,
                fresh.display(),
                names(&base)
            )
        });
        assert!(!marker.contains("interrupted"), "{}: {marker}", cmd.name);
        checked += 1;
    }
    assert_eq!(checked, COMMANDS.len());
}

/// Every command beyond the cost limits is refused before anything is written, and names
/// `--yes`.
#[test]
fn every_command_checks_its_cost_up_front() {
    let f = Fixture::new("cost");
    let mut checked = 0;
    for cmd in COMMANDS {
        let Ok(costly) = cmd.costly else {
            eprintln!(
                "{}: no cost case: {}",
                cmd.name,
                cmd.costly.err().unwrap_or_default()
            );
            continue;
        };
        let base = f
            .root
            .join(format!("cost-{}", cmd.name.replace([' ', '-'], "")));
        std::fs::create_dir_all(&base).unwrap();
        let out = base.join("out");
        let started = Instant::now();
        let (code, err) = run_in(&costly(&f), &out, &[], &base, &base);
        assert_eq!(code, 2, "{}: {err}", cmd.name);
        assert!(
            err.contains("--yes") && err.lines().count() == 1,
            "{}: {err}",
            cmd.name
        );
        assert!(!out.exists(), "{}: wrote {}", cmd.name, out.display());
        assert_eq!(names(&base), Vec::<String>::new(), "{}", cmd.name);
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "{}: the refusal took {:?}",
            cmd.name,
            started.elapsed()
        );
        checked += 1;
    }
    assert!(checked >= 6, "{checked}");
}

/// SIGTERM in the middle of every command that runs long enough: it stops at its next
/// step, pass, point or frequency, writes what it computed into its folder, marks the folder
/// interrupted and exits 130.
#[test]
fn every_command_stops_on_a_signal_and_marks_what_it_wrote() {
    let f = Fixture::new("signal");
    let mut checked = 0;
    for cmd in COMMANDS {
        let Ok(long) = cmd.long else {
            eprintln!(
                "{}: no signal case: {}",
                cmd.name,
                cmd.long.err().unwrap_or_default()
            );
            continue;
        };
        let base = f
            .root
            .join(format!("signal-{}", cmd.name.replace([' ', '-'], "")));
        std::fs::create_dir_all(&base).unwrap();
        let out = base.join("out");
        let mut child = softway()
            .args(long(&f))
            .arg("--out")
            .arg(&out)
            .current_dir(&base)
            .env("HOME", &base)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(700));
        let signalled = Instant::now();
        assert!(std::process::Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap()
            .success());
        // The work stops at its next step, pass, point or frequency; the slowest unit here
        // is a shakedown pass (about 6 s) or the modes' one solve.
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            if signalled.elapsed() > Duration::from_secs(60) {
                let _ = child.kill();
                panic!("{}: still running 60 s after SIGTERM", cmd.name);
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let mut err = String::new();
        use std::io::Read as _;
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        assert!(!err.contains("panicked"), "{}: {err}", cmd.name);
        assert_eq!(status.code(), Some(130), "{}: {err}", cmd.name);
        let marker = std::fs::read_to_string(out.join(".softway"))
            .unwrap_or_else(|e| panic!("{}: no marker in {}: {e}", cmd.name, out.display()));
        assert!(
            marker.lines().any(|l| l == "interrupted"),
            "{}: the marker does not say interrupted: {marker}",
            cmd.name
        );
        assert!(
            names(&out).len() > 1,
            "{}: nothing written: {:?}",
            cmd.name,
            names(&out)
        );
        assert_no_temporaries(&base);
        checked += 1;
    }
    assert!(checked >= 9, "{checked}");
}

/// Every kind's `summary.json` reports the process's peak memory (`peak_rss_mib`), stamped
/// in one place after every run: the one-degree-of-freedom scheme lacked it.
#[test]
fn every_kinds_summary_reports_its_peak_memory() {
    let dir = TestDir::new("rules", "peak");
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    for name in [
        "sdof",
        "bar-impact",
        "compare-two-bars",
        "track-moving-load",
    ] {
        let out = dir.join(name);
        let o = softway()
            .arg("run")
            .arg(shipped.join(format!("{name}.toml")))
            .args(["--quiet", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let mib = s["peak_rss_mib"].as_f64();
        // A process holds at least its binary's resident pages, and these runs far less than
        // a gigabyte.
        assert!(
            mib.is_some_and(|m| m > 1.0 && m < 1024.0),
            "{name}: peak_rss_mib = {:?}",
            s["peak_rss_mib"]
        );
    }
}
