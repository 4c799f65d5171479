//! Interruption and faults: SIGINT and SIGTERM at any moment leave complete, readable
//! outputs (summary.json parses, CSV rows complete, VTU well-formed, PNGs decode) and no
//! temporary files; SIGKILL leaves at most files under temporary names (removed by the next
//! run), never a truncated file under its final name; a full disk is an error, not a panic.

mod common;

use common::{assert_no_temporaries, softway, TestDir, LONG_BAR};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

/// Asserts that every result in `dir` is complete and readable.
fn assert_complete_outputs(dir: &Path) {
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(s["interrupted"].is_boolean(), "{s}");
    let mut kinds = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        match p.extension().and_then(|x| x.to_str()) {
            Some("csv") => {
                let text = std::fs::read_to_string(&p).unwrap();
                assert!(text.ends_with('\n'), "{}: last row cut", p.display());
                let rows: Vec<&str> = text.lines().collect();
                let n = rows[0].split(',').count();
                assert!(
                    rows.iter().all(|r| r.split(',').count() == n),
                    "{}: a row of another length",
                    p.display()
                );
                kinds |= 1;
            }
            Some("png") => {
                let decoder = png::Decoder::new(std::fs::File::open(&p).unwrap());
                let mut reader = decoder.read_info().unwrap();
                let mut buf = vec![0; reader.output_buffer_size()];
                reader.next_frame(&mut buf).unwrap();
                kinds |= 2;
            }
            Some("vtu") => {
                vtkio::Vtk::import(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                kinds |= 4;
            }
            _ => {}
        }
    }
    assert!(kinds & 1 != 0, "no CSV in {}", dir.display());
}

fn signal(pid: u32, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok || sig == "-KILL");
}

/// SIGINT, SIGTERM and SIGHUP, early and late: the run stops at the next step, writes what it has
/// and exits 130; or it finished first (0); or the signal came before the handler was set
/// (killed, nothing written). Never a half result, never a temporary file.
#[test]
fn sigint_and_sigterm_at_any_moment_leave_complete_results() {
    let dir = TestDir::new("int", "anytime");
    let sc = dir.join("long.toml");
    std::fs::write(&sc, LONG_BAR).unwrap();
    let mut interrupted = 0;
    for (k, (sig, delay_ms)) in [
        ("-INT", 0),
        ("-TERM", 30),
        ("-INT", 150),
        ("-HUP", 250),
        ("-TERM", 400),
        ("-TERM", 700),
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.join(format!("out{k}"));
        let mut child = softway()
            .arg("run")
            .arg(&sc)
            .arg("--quiet")
            .arg("--out")
            .arg(&out)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        signal(child.id(), sig);
        let status = child.wait().unwrap();
        match status.code() {
            Some(130) => {
                interrupted += 1;
                assert_complete_outputs(&out);
                let s: serde_json::Value = serde_json::from_str(
                    &std::fs::read_to_string(out.join("summary.json")).unwrap(),
                )
                .unwrap();
                assert_eq!(s["interrupted"], true, "{sig} after {delay_ms} ms");
            }
            Some(0) => assert_complete_outputs(&out),
            None => assert!(!out.exists(), "{sig} after {delay_ms} ms: {status:?}"),
            Some(c) => panic!("{sig} after {delay_ms} ms: exit {c}"),
        }
        assert_no_temporaries(&dir);
    }
    assert!(interrupted >= 2, "only {interrupted} runs interrupted");
}

/// True when a staged output folder in `dir` holds a history file in progress (under its
/// temporary name) with rows in it.
fn history_written(dir: &Path) -> bool {
    let staged = std::fs::read_dir(dir).into_iter().flatten().flatten();
    staged
        .filter(|e| e.file_name().to_string_lossy().starts_with(".softway-tmp-"))
        .flat_map(|e| std::fs::read_dir(e.path()).into_iter().flatten().flatten())
        .any(|f| {
            f.file_name().to_string_lossy().contains("history.csv")
                && f.metadata().is_ok_and(|m| m.len() > 1024)
        })
}

/// The wheel interrupted: its VTU, PNGs, CSVs and summary are complete.
#[test]
fn sigint_stops_the_wheel_run_and_keeps_its_results() {
    let dir = TestDir::new("int", "wheel");
    let mut child = softway()
        .args([
            "run",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml"),
            "--quiet",
            "--out",
        ])
        .arg(dir.join("out"))
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Interrupt once the time loop has written history rows (on a loaded machine the set-up
    // alone can take seconds), or after a minute in any case.
    let started = std::time::Instant::now();
    while started.elapsed() < Duration::from_secs(60) && !history_written(&dir) {
        std::thread::sleep(Duration::from_millis(50));
    }
    signal(child.id(), "-INT");
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "exit status {status:?}");
    let out = dir.join("out");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["interrupted"], true);
    let steps = s["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 54_860, "steps {steps}");
    assert_complete_outputs(&out);
    // The turn-averaged field is written however early the run stopped (and imported above).
    assert!(out.join("j2_turn_average.vtu").exists());
    assert!(out.join("contact_force.png").exists());
    assert_no_temporaries(&dir);
}

/// SIGKILL at several moments: the output folder is either absent or the older complete
/// results; anything else has a temporary name; the next run removes those.
#[test]
fn sigkill_leaves_only_temporary_names_and_the_next_run_cleans_them() {
    let dir = TestDir::new("int", "kill");
    let sc = dir.join("long.toml");
    std::fs::write(&sc, LONG_BAR).unwrap();
    let out = dir.join("out");
    for delay_ms in [20, 200, 500] {
        let mut child = softway()
            .arg("run")
            .arg(&sc)
            .arg("--quiet")
            .arg("--out")
            .arg(&out)
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        signal(child.id(), "-KILL");
        let _ = child.wait().unwrap();
        assert!(
            !out.exists(),
            "SIGKILL after {delay_ms} ms left {}",
            out.display()
        );
        for e in std::fs::read_dir(&dir).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(
                name == "long.toml" || name.starts_with(".softway-tmp-"),
                "{name}"
            );
        }
    }
    // The next run cleans the folders of the killed runs and writes complete results.
    let o = softway()
        .arg("run")
        .arg(&sc)
        .arg("--quiet")
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_complete_outputs(&out);
    assert_no_temporaries(&dir);
}

/// A full disk (a file size limit of 20 kB, RLIMIT_FSIZE with SIGXFSZ ignored: writes fail
/// with EFBIG as on a full tmpfs): one line naming the file, exit 2, nothing left behind.
#[test]
fn a_full_disk_is_an_error_not_a_panic() {
    let dir = TestDir::new("int", "full");
    let sc = dir.join("long.toml");
    std::fs::write(&sc, LONG_BAR.replace("t_end = 3.0", "t_end = 0.5")).unwrap();
    let out = dir.join("out");
    let o = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 40; exec \"$0\" run \"$1\" --quiet --out \"$2\"")
        .arg(env!("CARGO_BIN_EXE_softway"))
        .arg(&sc)
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("history.csv: File too large"), "{err}");
    assert!(!out.exists());
    assert_no_temporaries(&dir);
}

/// Runs `softway ARGS SCENARIO --out OUT` on a 20-element bar with piped standard output
/// and error, closing those `closed` says (`(stdout, stderr)`) at once; returns the exit
/// code, what reached standard error (if open) and the test's folder (`OUT` is its `out`).
fn with_closed_pipes(
    name: &str,
    args: &[&str],
    closed: (bool, bool),
) -> (Option<i32>, String, TestDir) {
    let dir = TestDir::new("int", name);
    let sc = dir.join("bar.toml");
    std::fs::write(&sc, LONG_BAR.replace("elements = 2000", "elements = 20")).unwrap();
    let out = dir.join("out");
    let mut child = softway()
        .args(args)
        .arg(&sc)
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    if closed.0 {
        drop(child.stdout.take());
    }
    if closed.1 {
        drop(child.stderr.take());
    }
    let o = child.wait_with_output().unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        dir,
    )
}

/// `softway run ... | head`: a closed standard output does not panic; the run completes.
#[test]
fn a_closed_stdout_is_not_a_panic() {
    let (code, err, dir) = with_closed_pipes("pipe", &["run"], (true, false));
    assert_eq!(code, Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
    assert_complete_outputs(&dir.join("out"));
}

/// `softway sweep ... 2>&1 | head`: closed standard output and error (the progress lines of a
/// sweep go to standard error) are not a panic; the sweep completes and its files are written.
#[test]
fn a_closed_stderr_is_not_a_panic() {
    let (code, _, dir) = with_closed_pipes(
        "pipe-err",
        &["sweep", "--set", "bar.elements=10,20,40", "--jobs", "2"],
        (true, true),
    );
    assert_eq!(code, Some(0));
    assert_eq!(
        std::fs::read_to_string(dir.join("out").join("sweep.csv"))
            .unwrap()
            .lines()
            .count(),
        4
    );
}

/// Runs `softway ARGS` (a sweep of `time.t_end` = 0.5, 60, 61 s over [`LONG_BAR`], one job:
/// the points in order) and sends SIGINT once the first point is done; returns the exit
/// status and standard error.
fn interrupt_sweep(args: &[&std::ffi::OsStr]) -> (std::process::ExitStatus, String) {
    let mut child = softway()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the first point is done (its line on standard error) and the second
    // has started, or after two minutes in any case.
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    let started = std::time::Instant::now();
    while started.elapsed() < Duration::from_secs(120) {
        let mut line = String::new();
        if std::io::BufRead::read_line(&mut err, &mut line).unwrap() == 0 {
            break;
        }
        seen.push_str(&line);
        if line.contains("time.t_end = 0.5: done") {
            break;
        }
    }
    std::thread::sleep(Duration::from_millis(300));
    signal(child.id(), "-INT");
    std::io::Read::read_to_string(&mut err, &mut seen).unwrap();
    (child.wait().unwrap(), seen)
}

/// Asserts the table of the interrupted sweep in `out`: the first point `complete` with its
/// figures, the other two `interrupted` with every figure cell empty (never the zeros of a
/// run that did not happen), in `sweep.csv` and `sweep.md`.
fn assert_interrupted_table(out: &Path) {
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    let col = |name: &str| {
        rows[0]
            .iter()
            .position(|c| *c == name)
            .unwrap_or_else(|| panic!("no column {name}: {csv}"))
    };
    let (status, steps, energy) = (col("status"), col("steps"), col("energy_final_J"));
    assert_eq!(rows.len(), 4, "{csv}");
    assert!(rows.iter().all(|r| r.len() == rows[0].len()), "{csv}");
    assert_eq!(rows[1][status], "complete", "{csv}");
    // The first point ran to t_end = 0.5 s at h = 2e-4: 2,500 steps.
    assert_eq!(rows[1][steps], "2500", "{csv}");
    assert!(rows[1][energy].parse::<f64>().unwrap() > 0.0, "{csv}");
    for r in &rows[2..] {
        assert_eq!(r[status], "interrupted", "{csv}");
        assert!(
            r.iter()
                .enumerate()
                .all(|(j, c)| j == 0 || j == status || c.is_empty()),
            "{csv}"
        );
    }
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert_eq!(md.matches("| interrupted |").count(), 2, "{md}");
}

/// SIGINT during `softway sweep`: the point that finished is `complete`, the one running and
/// the one not started are `interrupted`, their figures left empty; exit 130. The point that
/// ran wrote its (interrupted) summary, the one not started nothing. The same sweep as a
/// shard (`--shard 1/1`), gathered: `softway gather` carries the column.
#[test]
fn sigint_during_a_sweep_marks_the_points_that_did_not_complete() {
    let dir = TestDir::new("int", "sweep");
    let sc = dir.join("long.toml");
    std::fs::write(&sc, LONG_BAR).unwrap();
    let out = dir.join("out");
    let shard = dir.join("shard");
    for (folder, extra) in [(&out, &[][..]), (&shard, &["--shard", "1/1"][..])] {
        let mut args: Vec<&std::ffi::OsStr> = ["sweep", "--set", "time.t_end=0.5,60,61"]
            .iter()
            .chain(["--jobs", "1"].iter())
            .chain(extra)
            .map(std::ffi::OsStr::new)
            .collect();
        args.push(sc.as_os_str());
        args.push("--out".as_ref());
        args.push(folder.as_os_str());
        let (status, err) = interrupt_sweep(&args);
        assert_eq!(status.code(), Some(130), "{status:?}\n{err}");
        assert_interrupted_table(folder);
        let running: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(folder.join("time.t_end=60/summary.json")).unwrap(),
        )
        .unwrap();
        assert_eq!(running["interrupted"], true);
        assert!(!folder.join("time.t_end=61").exists());
    }
    let gathered = dir.join("gathered");
    let o = softway()
        .arg("gather")
        .arg(&shard)
        .arg("--out")
        .arg(&gathered)
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    assert_interrupted_table(&gathered);
    assert_no_temporaries(&dir);
}
