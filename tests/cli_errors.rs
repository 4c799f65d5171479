//! Bad input gives a one-line error naming the file and the key, a non-zero exit, no panic.

mod common;

use common::{assert_one_line_error, run_err, run_ok, scenario, softway, BAR};

#[test]
fn valid_bar_scenario_runs() {
    let p = scenario("ok", BAR);
    let (out, s) = run_ok(&p);
    assert_eq!(s["runs"].as_array().unwrap().len(), 1);
    assert!(out.join("history.csv").exists());
    assert!(out.join("bar_head.png").exists());
}

#[test]
fn unknown_key() {
    let (c, e) = run_err(
        "unknown",
        &BAR.replace("gap = 0.5", "gap = 0.5\nlenght = 2.0"),
    );
    assert_one_line_error(c, &e, &["unknown.toml", "lenght"]);
}

#[test]
fn negative_length() {
    let (c, e) = run_err("neglen", &BAR.replace("length = 1.0", "length = -1.0"));
    assert_one_line_error(c, &e, &["neglen.toml", "bar.length", "> 0"]);
}

#[test]
fn zero_and_negative_step() {
    for (name, h) in [("zeroh", "0.0"), ("negh", "-0.01")] {
        let (c, e) = run_err(name, &BAR.replace("h = 0.1", &format!("h = {h}")));
        assert_one_line_error(c, &e, &[name, "time.h", "> 0"]);
    }
}

#[test]
fn zero_elements() {
    let (c, e) = run_err("zeroel", &BAR.replace("elements = 8", "elements = 0"));
    assert_one_line_error(c, &e, &["zeroel.toml", "bar.elements", "1 to"]);
}

#[test]
fn alpha_and_gamma_out_of_range() {
    let (c, e) = run_err("alpha", &BAR.replace("alpha = 0.8", "alpha = 1.5"));
    assert_one_line_error(c, &e, &["time.alpha", "(0, 1]"]);
    let (c, e) = run_err(
        "gamma",
        &BAR.replace("alpha = 0.8", "alpha = 0.8\ngamma = -0.1"),
    );
    assert_one_line_error(c, &e, &["time.gamma", "[0, 1]"]);
}

#[test]
fn wrong_type_and_bad_syntax() {
    let (c, e) = run_err(
        "wrongtype",
        &BAR.replace("elements = 8", "elements = \"eight\""),
    );
    assert_one_line_error(c, &e, &["wrongtype.toml", "elements"]);
    let (c, e) = run_err("syntax", "kind = \"bar_impact\"\n[time\nh = 1");
    assert_one_line_error(c, &e, &["syntax.toml"]);
}

#[test]
fn missing_file() {
    let o = softway()
        .args(["run", "/nonexistent/dir/nothing.toml", "--quiet"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(0));
    assert!(
        err.contains("/nonexistent/dir/nothing.toml") && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn stability_bad_alpha() {
    let o = softway()
        .args(["stability", "--alpha", "0", "--gamma", "0.2"])
        .output()
        .unwrap();
    assert_ne!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--alpha"));
}

#[test]
fn stability_json_reports_the_limits() {
    let o = softway()
        .args(["stability", "--alpha", "0.75", "--gamma", "0.2", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["unconditionally_stable"], false);
    let lim = j["stability_limit_omega_h"].as_f64().unwrap();
    assert!(lim > 5.0 && lim < 6.0, "{lim}");
    let o = softway()
        .args(["stability", "--alpha", "0.8", "--gamma", "0.0", "--json"])
        .output()
        .unwrap();
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["unconditionally_stable"], true);
    assert!(j["stability_limit_omega_h"].is_null());
    assert!((j["rho_inf"].as_f64().unwrap() - 1.0).abs() < 1e-9);
}

/// `stability` on a full disk (`> /dev/full`): the result could not be written, so exit 2
/// with one line, never an empty file and exit 0; the table likewise.
#[test]
fn stability_on_a_full_disk_fails() {
    for args in [&["stability", "--json"][..], &["stability"][..]] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = softway().args(args).stdout(full).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_one_line_error(
            o.status.code().unwrap_or(-1),
            &err,
            &["standard output", "No space left on device"],
        );
    }
}

/// `--spin-h`: the two treatments of the Coriolis term side by side, the extrapolated one's
/// spectral radius no larger than the exact scheme's (or 1) anywhere on the ladder.
#[test]
fn stability_compares_the_coriolis_treatments() {
    let o = softway()
        .args([
            "stability",
            "--alpha",
            "0.8",
            "--gamma",
            "0.2",
            "--spin-h",
            "6e-4",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = j["gyroscopic"].as_array().unwrap();
    assert!(rows.len() > 30);
    for r in rows {
        let (ri, rx) = (
            r["rho_implicit"].as_f64().unwrap(),
            r["rho_extrapolated"].as_f64().unwrap(),
        );
        assert!(rx <= ri.max(1.0) + 1e-9, "{r}");
    }
}

#[test]
fn unknown_integrator_and_contact() {
    let (c, e) = run_err(
        "badinteg",
        &BAR.replace("[time]", "[time]\nintegrator = \"runge_kutta\""),
    );
    assert_one_line_error(
        c,
        &e,
        &["badinteg.toml", "time.integrator", "generalized_alpha"],
    );
    let (c, e) = run_err(
        "badcontact",
        &format!("{BAR}\n[contact]\nmethod = \"glue\"\n"),
    );
    assert_one_line_error(c, &e, &["badcontact.toml", "contact.method", "penalty"]);
}

#[test]
fn penalty_needs_its_stiffness() {
    let (c, e) = run_err(
        "nopen",
        &format!("{BAR}\n[contact]\nmethod = \"penalty\"\n"),
    );
    assert_one_line_error(c, &e, &["nopen.toml", "contact.penalty", "N/m"]);
    let (c, e) = run_err(
        "negpen",
        &format!("{BAR}\n[contact]\nmethod = \"penalty\"\npenalty = -5.0\n"),
    );
    assert_one_line_error(c, &e, &["negpen.toml", "contact.penalty", "> 0"]);
}

#[test]
fn combinations_that_do_not_exist_are_refused() {
    // The soft way is a space-time treatment.
    let (c, e) = run_err(
        "softnewmark",
        &BAR.replace("[time]", "[time]\nintegrator = \"newmark\""),
    );
    assert_one_line_error(c, &e, &["softnewmark.toml", "contact.method", "space_time"]);
    // Subdivision (Fig. 5) too.
    let (c, e) = run_err(
        "subhht",
        &format!(
            "{}\n[contact]\nmethod = \"subdivision\"\n",
            BAR.replace("[time]", "[time]\nintegrator = \"hht\"")
        ),
    );
    assert_one_line_error(c, &e, &["subhht.toml", "contact.method", "space-time"]);
    // A parameter of another integrator.
    let (c, e) = run_err(
        "rhonewmark",
        &format!(
            "{}\n[contact]\nmethod = \"exact\"\n",
            BAR.replace("[time]", "[time]\nintegrator = \"newmark\"\nrho_inf = 0.5")
                .replace("alpha = 0.8\n", "")
        ),
    );
    assert_one_line_error(
        c,
        &e,
        &["rhonewmark.toml", "time.rho_inf", "generalized_alpha"],
    );
    // rho_inf out of range.
    let (c, e) = run_err(
        "rhobad",
        &format!(
            "{}\n[contact]\nmethod = \"exact\"\n",
            BAR.replace(
                "[time]",
                "[time]\nintegrator = \"generalized_alpha\"\nrho_inf = 1.5"
            )
        ),
    );
    assert_one_line_error(c, &e, &["rhobad.toml", "time.rho_inf", "[0, 1]"]);
}

#[test]
fn a_refused_combination_in_runs_names_the_run_key() {
    let (c, e) = run_err(
        "runsmj",
        &format!(
            "{BAR}\n[[runs]]\nh = 0.05\n[[runs]]\nintegrator = \"central_difference\"\nmethod = \"moreau_jean\"\n"
        ),
    );
    assert_one_line_error(
        c,
        &e,
        &[
            "runsmj.toml",
            "`runs[1].method`",
            "\"moreau_jean\"",
            "implicit",
        ],
    );
    // The run sets the integrator only: the refused method is the default one, named by
    // the key it stands for.
    let (c, e) = run_err(
        "runsrc",
        &format!("{BAR}\n[[runs]]\nintegrator = \"newmark\"\n"),
    );
    assert_one_line_error(
        c,
        &e,
        &[
            "runsrc.toml",
            "`contact.method`",
            "\"soft_way\"",
            "not one of newmark",
        ],
    );
}

/// `softway run` builds the scenario before running it: `cfl` becomes
/// `h = cfl * 2 / omega_max = cfl * dx / c` of the lumped bar (8 elements of 1/8 m, c = 1).
#[test]
fn cfl_is_resolved_before_the_run() {
    let p = scenario(
        "cfl",
        &BAR.replace(
            "[time]",
            "[time]\nintegrator = \"central_difference\"\ncfl = 0.5",
        )
        .replace("h = 0.1\n", "")
        .replace("alpha = 0.8\n", "")
        .replace(
            "elements = 8",
            "elements = 8\n[contact]\nmethod = \"exact\"",
        ),
    );
    let (_, s) = run_ok(&p);
    let h = s["runs"][0]["h"].as_f64().unwrap();
    assert!((h - 0.5 * 0.125).abs() < 1e-9 * 0.0625, "h = {h}");
}

/// `softway matrix`: `A` in Matrix Market as `matrix.json` describes it (order, stored
/// entries, symmetry read from the entries), a free step timed over `--steps`; `--steps 0`
/// is refused in one line.
#[test]
fn matrix_writes_a_as_its_report_says() {
    let p = scenario("matrix", BAR);
    let out = p.parent().unwrap().join("m");
    let matrix = |steps: &str| {
        softway()
            .args(["matrix", p.to_str().unwrap(), "--out"])
            .args([out.to_str().unwrap(), "--steps", steps])
            .output()
            .unwrap()
    };
    let o = matrix("3");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("matrix.json")).unwrap()).unwrap();
    let text = std::fs::read_to_string(out.join("A.mtx")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let dims: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    let entries: std::collections::HashMap<(usize, usize), f64> = lines
        .map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            (
                (t[0].parse().unwrap(), t[1].parse().unwrap()),
                t[2].parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(dims[0], j["n"].as_u64().unwrap() as usize);
    assert_eq!(dims[2], j["nnz_a"].as_u64().unwrap() as usize);
    assert_eq!(entries.len(), dims[2]);
    let symmetric = entries.iter().all(|(&(r, c), v)| {
        entries
            .get(&(c, r))
            .is_some_and(|w| (v - w).abs() <= 1e-12 * v.abs())
    });
    assert_eq!(j["symmetric"].as_bool().unwrap(), symmetric);
    assert!(j["softway_step_us"].as_f64().unwrap() > 0.0);
    let o = matrix("0");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--steps"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `softway matrix` of a 3D model (the wheel pressed on the rail, 27,855 unknowns): its
/// Cholesky factor by nested dissection, named so, and no LU of its symmetric matrix
/// (minutes and gigabytes at 3D size); the factor holds at least the lower triangle of `A`
/// (fill only adds) and at most the press's cost estimate (within 3x of it), its time and
/// the peak memory are reported, and the parts of the split factor cover the unknowns.
#[test]
fn matrix_of_a_3d_model_reports_its_nested_dissection_factor() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/press.toml"),
    )
    .unwrap()
    .lines()
    .map(|l| {
        if l.starts_with("contact_size_mm") {
            "contact_size_mm = 3.0".to_string()
        } else if l.starts_with("zone_mm") {
            "zone_mm = [6.0, 12.0]".to_string()
        } else {
            l.to_string()
        }
    })
    .collect::<Vec<_>>()
    .join("\n");
    let p = scenario("matrix3d", &text);
    let out = p.parent().unwrap().join("m3d");
    let o = softway()
        .args(["matrix", p.to_str().unwrap(), "--out"])
        .args([out.to_str().unwrap(), "--steps", "2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("matrix.json")).unwrap()).unwrap();
    assert_eq!(j["factor"], "llt_nd");
    assert_eq!(j["factor_ordering"], "NestedDissection");
    assert!(j["symmetric"].as_bool().unwrap());
    let sizes = j["factor_nnz"].as_array().unwrap();
    assert_eq!(sizes.len(), 1, "{sizes:?}");
    assert_eq!(sizes[0][0], "llt_nd");
    let (n, nnz_a) = (j["n"].as_u64().unwrap(), j["nnz_a"].as_u64().unwrap());
    assert!(
        n > 5000,
        "a 3D model large enough for nested dissection: {n}"
    );
    let nnz_l = sizes[0][1].as_u64().unwrap();
    assert!(nnz_l >= (nnz_a + n) / 2);
    // The press's cost estimate bounds its factor (`kinds::press::factor_entries`).
    let bound = softway::kinds::press::factor_entries(n as f64);
    assert!(
        bound >= nnz_l as f64 && bound <= 3.0 * nnz_l as f64,
        "estimate {bound:.0} against nnz(L) {nnz_l}"
    );
    assert!(j["factor_s"].as_f64().unwrap() > 0.0);
    assert!(j["peak_rss_mib"].as_f64().unwrap() > 0.0);
    let parts: u64 = j["factor_parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(parts, n);
}

/// A scenario path that is a named pipe with no writer is refused at once (opening it would
/// wait for a writer forever).
#[test]
fn a_pipe_in_place_of_the_scenario_is_refused_at_once() {
    let dir = common::fresh_dir("cli", "fifo");
    let p = dir.join("pipe.toml");
    let made = std::process::Command::new("mkfifo").arg(&p).status();
    assert!(made.expect("mkfifo (coreutils)").success());
    let (c, e) = common::run_file_err(&p);
    assert_one_line_error(c, &e, &["pipe.toml", "not a regular file"]);
    assert_eq!(c, 2);
}

/// `--threads` and `--jobs` have a bound (20000 threads ran for minutes on an 8-element bar).
#[test]
fn thousands_of_threads_are_refused() {
    let p = scenario("threads", BAR);
    for (cmd, flag) in [("run", "--threads"), ("sweep", "--jobs")] {
        let mut args = vec![cmd.to_string(), p.display().to_string()];
        if cmd == "sweep" {
            args.extend(["--set".into(), "bar.elements=8,16".into()]);
        }
        args.extend([flag.into(), "20000".into()]);
        let o = common::cli(&args);
        assert_eq!(o.code, 2, "{}", o.stderr);
        assert_one_line_error(o.code, &o.stderr, &[flag, "20000", "at most 256"]);
    }
}

/// A name of 230 to 255 bytes is a legal folder name: the run writes `out/<name>` (the
/// staging folder beside it has a short name of its own).
#[test]
fn names_up_to_255_bytes_name_the_output_folder() {
    let dir = common::TestDir::new("cli", "long_names");
    for n in [230, 255] {
        let name = "n".repeat(n);
        let p = dir.join(format!("long{n}.toml"));
        std::fs::write(
            &p,
            BAR.replace("kind =", &format!("name = \"{name}\"\nkind =")),
        )
        .unwrap();
        let o = softway()
            .current_dir(&dir)
            .args(["run", "--quiet"])
            .arg(&p)
            .output()
            .unwrap();
        assert!(o.status.success(), "{n}: {o:?}");
        assert!(dir.join("out").join(&name).join("summary.json").is_file());
        for e in std::fs::read_dir(dir.join("out")).unwrap() {
            let f = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!f.contains("softway-tmp"), "left: {f}");
        }
    }
}

/// `cfl` alone sets the central difference's step (no `time.h` demanded); with a `time.h`
/// beside it, the `time.h` it would override is refused by its key.
#[test]
fn cfl_alone_sets_the_step_and_an_overridden_h_is_refused() {
    let cd = BAR
        .replace("alpha = 0.8\n", "")
        .replace("h = 0.1", "integrator = \"central_difference\"\ncfl = 0.5")
        + "[contact]\nmethod = \"exact\"\n";
    let p = scenario("cfl_alone", &cd);
    let (_, s) = run_ok(&p);
    // 8 elements of length 1/8, c = 1: the stable step 2/omega_max = 1/8 (lumped mass), half
    // of it taken.
    let h = s["runs"][0]["h"].as_f64().unwrap();
    assert!((h - 0.0625).abs() < 1e-12, "h = {h}: {s}");
    let (c, e) = run_err("cfl_and_h", &cd.replace("cfl = 0.5", "cfl = 0.5\nh = 0.01"));
    assert_one_line_error(c, &e, &["cfl_and_h.toml", "`time.h` = 0.01", "time.cfl"]);
}
