//! The bad-input catalogue (issue 12): every case is refused by the command line with one
//! line naming the file, the key (or the mesh entity and its tag) and what is allowed, a
//! non-zero exit, no panic and nothing written in the output folder.
//!
//! `SOFTWAY_CATALOGUE=/tmp/c.tsv cargo test --test bad_input` lists the messages.

mod common;

use common::{
    assert_nothing_written, assert_one_line_error, cli, fresh_dir, run_err, run_file_err, scenario,
    scenario_bytes, BAR,
};
use softway::mesh::generators::disk_rings;
use softway::mesh::Cells;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A refused bar scenario: `$name.toml` is the bar with `$from` replaced by `$to`; the
/// message holds the file name and every string of `$must`.
macro_rules! bar_refused {
    ($name:ident, $from:expr, $to:expr, [$($must:expr),*]) => {
        #[test]
        fn $name() {
            let text = BAR.replace($from, $to);
            assert_ne!(text, BAR, "the replacement did nothing");
            let (c, e) = run_err(stringify!($name), &text);
            assert_one_line_error(c, &e, &[concat!(stringify!($name), ".toml"), $($must),*]);
        }
    };
}

/// A refused scenario given whole.
macro_rules! refused {
    ($name:ident, $text:expr, [$($must:expr),*]) => {
        #[test]
        fn $name() {
            let (c, e) = run_err(stringify!($name), &$text);
            assert_one_line_error(c, &e, &[concat!(stringify!($name), ".toml"), $($must),*]);
        }
    };
}

// ---------------------------------------------------------------- scenario: keys, types

bar_refused!(
    unknown_top_level_key,
    "kind =",
    "nmae = \"x\"\nkind =",
    ["nmae", "expected one of"]
);
bar_refused!(unknown_table, "[bar]", "[solver]\nx = 1\n[bar]", ["solver"]);
bar_refused!(
    misspelt_key_in_time,
    "t_end = 1.0",
    "t_end = 1.0\ntend = 2.0",
    ["tend", "t_end"]
);
bar_refused!(
    step_as_a_string,
    "h = 0.1",
    "h = \"0.1\"",
    ["h", "\"0.1\"", "expected f64"]
);
bar_refused!(
    elements_as_a_float,
    "elements = 8",
    "elements = 8.5",
    ["elements", "8.5", "expected i64"]
);
bar_refused!(
    plots_as_a_string,
    "elements = 8",
    "elements = 8\n[output]\nplots = \"yes\"",
    ["plots", "bool"]
);
bar_refused!(
    table_given_as_a_number,
    "kind = \"bar_impact\"",
    "kind = \"bar_impact\"\ncontact = 3",
    ["`contact = 3`", "expected a table"]
);
bar_refused!(
    duplicate_key,
    "h = 0.1",
    "h = 0.1\nh = 0.2",
    ["duplicate key", "h"]
);
bar_refused!(missing_kind, "kind = \"bar_impact\"", "", ["kind"]);
bar_refused!(
    unknown_kind,
    "\"bar_impact\"",
    "\"plate\"",
    ["`kind`", "\"plate\"", "\"wheel\""]
);
bar_refused!(misspelt_table, "[bar]", "[bars]", ["bars"]);
bar_refused!(
    missing_bar_table,
    "[bar]",
    "[two_bars]",
    ["`two_bars`", "not by kind = \"bar_impact\"", "reads [bar]"]
);
bar_refused!(missing_t_end, "t_end = 1.0", "", ["time.t_end", "end time"]);
bar_refused!(
    kind_with_a_line_break,
    "\"bar_impact\"",
    "\"bar\\nimpact\"",
    ["`kind` = \"bar\\nimpact\"", "allowed"]
);
bar_refused!(
    no_elements_anywhere,
    "elements = 8",
    "",
    ["missing `bar.elements`", "or runs[0].elements"]
);
bar_refused!(
    name_dot,
    "kind =",
    "name = \".\"\nkind =",
    ["`name` = \".\"", "not \".\" or \"..\""]
);
bar_refused!(
    name_with_a_slash,
    "kind =",
    "name = \"../x\"\nkind =",
    ["`name`", "without slashes"]
);

// ---------------------------------------------------------------- scenario: values

bar_refused!(
    nan_step,
    "h = 0.1",
    "h = nan",
    ["`time.h` = NaN", "finite number > 0"]
);
bar_refused!(
    infinite_end_time,
    "t_end = 1.0",
    "t_end = inf",
    ["`time.t_end` = inf", "finite"]
);
bar_refused!(
    minus_infinite_speed,
    "speed = 1.0",
    "speed = -inf",
    ["`bar.speed` = -inf", "> 0"]
);
bar_refused!(
    zero_stiffness,
    "ea = 1.0",
    "ea = 0.0",
    ["`bar.ea` = 0", "> 0"]
);
bar_refused!(
    negative_density,
    "rho_a = 1.0",
    "rho_a = -1.0",
    ["`bar.rho_a` = -1", "> 0"]
);
bar_refused!(
    tiny_length_shown_compactly,
    "length = 1.0",
    "length = -1e-300",
    ["`bar.length` = -1e-300", "> 0"]
);
bar_refused!(
    negative_gap,
    "gap = 0.5",
    "gap = -0.5",
    ["`bar.gap` = -0.5", ">= 0"]
);
bar_refused!(
    absurd_elements,
    "elements = 8",
    "elements = 10000000",
    ["`bar.elements` = 10000000", "1 to 1000000"]
);
bar_refused!(
    negative_elements,
    "elements = 8",
    "elements = -3",
    ["`bar.elements` = -3", "whole number"]
);
bar_refused!(
    step_longer_than_the_run,
    "h = 0.1",
    "h = 2.0",
    ["`time.h` = 2", "must not exceed time.t_end"]
);
bar_refused!(
    zero_history_stride,
    "elements = 8",
    "elements = 8\n[output]\nhistory_stride = 0",
    ["`output.history_stride` = 0", "1 to"]
);
bar_refused!(
    restitution_above_one,
    "elements = 8",
    "elements = 8\n[contact]\nmethod = \"moreau_jean\"\nrestitution = 2.0",
    ["`contact.restitution` = 2", "[0, 1]"]
);
bar_refused!(
    friction_on_a_bar,
    "elements = 8",
    "elements = 8\n[contact]\nmethod = \"exact\"\nfriction = 0.3",
    ["`contact.friction` = 0.3"]
);
bar_refused!(
    empty_sweep_values,
    "elements = 8",
    "elements = 8\n[sweep]\nkey = \"bar.speed\"\nvalues = []",
    ["`sweep.values`", "at least one value"]
);
bar_refused!(
    sweep_ladder_of_one_rung,
    "elements = 8",
    "elements = 8\n[sweep]\nkey = \"bar.speed\"\nvalues = [1.0, 2.0]\nladder = { key = \"bar.elements\", values = [8] }",
    ["`sweep.ladder.values`", "at least two rungs"]
);
bar_refused!(
    sweep_ladder_on_the_swept_key,
    "elements = 8",
    "elements = 8\n[sweep]\nkey = \"bar.speed\"\nvalues = [1.0, 2.0]\nladder = { key = \"bar.speed\", values = [1, 2] }",
    ["`sweep.ladder.key`", "other than sweep.key"]
);

bar_refused!(
    sweep_ladder_linked_key_of_another_length,
    "elements = 8",
    "elements = 8\n[sweep]\nkey = \"bar.speed\"\nvalues = [1.0, 2.0]\nladder = { key = \"bar.elements\", values = [8, 16], with = { \"time.h\" = [0.1] } }",
    ["`sweep.ladder.with.\"time.h\"`", "one value a rung: 2 values"]
);
bar_refused!(
    sweep_ladder_linked_to_the_swept_key,
    "elements = 8",
    "elements = 8\n[sweep]\nkey = \"bar.speed\"\nvalues = [1.0, 2.0]\nladder = { key = \"bar.elements\", values = [8, 16], with = { \"bar.speed\" = [1, 2] } }",
    ["`sweep.ladder.with.\"bar.speed\"`", "other than sweep.key"]
);

/// A step of 1e-12 s: 1e12 steps, refused with the estimate (steps, time, memory, disk)
/// and the key, unless `--yes`.
#[test]
fn a_run_of_days_is_refused_with_its_estimate() {
    let p = scenario("tiny_step", &BAR.replace("h = 0.1", "h = 1e-12"));
    let (c, e) = run_file_err(&p);
    assert_one_line_error(
        c,
        &e,
        &[
            "tiny_step.toml",
            "steps",
            "days",
            "of memory",
            "`time.h`",
            "--yes",
        ],
    );
}

/// `--yes` confirms a run beyond the limits: it starts (and is stopped here by SIGINT,
/// keeping what it computed).
#[test]
fn yes_runs_what_the_estimate_refuses() {
    let p = scenario("yes_tiny_step", &BAR.replace("h = 0.1", "h = 1e-9"));
    let (c, e) = run_file_err(&p);
    assert_one_line_error(c, &e, &["yes_tiny_step.toml", "--yes"]);
    let out = p.with_extension("out");
    let mut child = common::softway()
        .arg("run")
        .arg(&p)
        .args(["--yes", "--quiet", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(400));
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    assert_eq!(child.wait().unwrap().code(), Some(130));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["interrupted"], true);
    assert!(s["steps"].as_u64().unwrap() > 0);
}

/// The largest graded wheel allowed (100,000 rim nodes): refused for its memory and time.
#[test]
fn a_wheel_that_would_exhaust_memory_is_refused_with_its_estimate() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml"))
            .unwrap();
    let text = text.replace("rim_nodes = 288", "rim_nodes = 100000");
    let (c, e) = run_err("huge_wheel", &text);
    assert_one_line_error(
        c,
        &e,
        &["huge_wheel.toml", "`wheel.rim_nodes`", "dofs", "--yes"],
    );
}

#[test]
fn a_flattening_below_the_contacts_resolution_is_refused_before_the_run() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml"))
            .unwrap();
    for d in ["1e-300", "1e-9"] {
        let t = text.replace("flattening = 1e-3 ", &format!("flattening = {d} "));
        assert!(t.contains(d));
        let (c, e) = run_err("tiny_flattening", &t);
        assert_one_line_error(
            c,
            &e,
            &[
                "tiny_flattening.toml",
                "`rolling.flattening`",
                "at least 1e-6 wheel.radius",
            ],
        );
    }
}

/// What no confirmation can make runnable: more memory than the machine has (the contact
/// solver's dense blocks grow with the square of the rim: 100,000 rim nodes need ~170 GB),
/// or more steps than can be run (`h = 5e-324`: infinitely many). Refused with `--yes` too,
/// before anything is written.
#[test]
fn runs_beyond_the_machine_are_refused_even_when_confirmed() {
    let wheel =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml"))
            .unwrap()
            .replace("rim_nodes = 288", "rim_nodes = 100000");
    let bar = common::BAR.replace("h = ", "h = 5e-324 #");
    for (name, text, must) in [
        (
            "huge_wheel_yes",
            wheel,
            vec![
                "more than this machine",
                "`wheel.rim_nodes`",
                "with or without --yes",
            ],
        ),
        (
            "tiny_step_yes",
            bar,
            vec!["inf steps", "h` = 5e-324", "with or without --yes"],
        ),
    ] {
        let p = common::scenario(name, &text);
        let out = p.with_extension("out");
        let o = common::cli([
            "run".as_ref(),
            p.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
            "--yes".as_ref(),
        ]);
        common::assert_nothing_written(&out);
        let mut all = vec![format!("{name}.toml")];
        all.extend(must.iter().map(|m| m.to_string()));
        let refs: Vec<&str> = all.iter().map(|s| s.as_str()).collect();
        assert_one_line_error(o.code, &o.stderr, &refs);
    }
}

// ---------------------------------------------------------------- scenario: the track

fn track_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/track-moving-load.toml"
    ))
    .unwrap()
}

/// The wheel rolling on the track (scenarios/track.toml).
fn rolling_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/track.toml")).unwrap()
}

refused!(
    track_unknown_set,
    track_text().replace("set = \"uic60\"", "set = \"zhai\""),
    ["`track.set` = \"zhai\"", "\"uic60\""]
);
refused!(
    track_unknown_theory,
    track_text().replace("set = \"uic60\"", "theory = \"rayleigh\""),
    ["`track.theory` = \"rayleigh\"", "\"euler_bernoulli\""]
);
refused!(
    track_negative_pad,
    track_text().replace("set = \"uic60\"", "pad_stiffness = -1.0"),
    ["`track.pad_stiffness` = -1", "> 0"]
);
refused!(
    track_negative_ballast_damping,
    track_text().replace("set = \"uic60\"", "ballast_damping = -5.0"),
    ["`track.ballast_damping` = -5", ">= 0"]
);
refused!(
    track_poisson_half,
    track_text().replace("set = \"uic60\"", "poisson = 0.5"),
    ["`track.poisson` = 0.5", "(-1, 0.5)"]
);
refused!(
    track_zero_elements_per_bay,
    track_text().replace("elements_per_bay = 6", "elements_per_bay = 0"),
    ["`track.elements_per_bay` = 0", "1 to 1000"]
);
refused!(
    track_one_bay,
    track_text().replace("bays = 100", "bays = 1"),
    ["`track.bays` = 1", "at least 2"]
);
refused!(
    track_huge_rail,
    track_text()
        .replace("bays = 100", "bays = 1000000")
        .replace("elements_per_bay = 6", "elements_per_bay = 1000"),
    ["`track.elements_per_bay` = 1000", "at most 2000000"]
);
refused!(
    track_absorbing_zones_overlap,
    track_text().replace("bays = 100", "bays = 100\nend_bays = 50"),
    ["`track.end_bays` = 50", "2 end_bays < track.bays = 100"]
);
refused!(
    track_unknown_ends,
    track_text().replace("bays = 100", "bays = 100\nends = \"periodic\""),
    ["`track.ends` = \"periodic\"", "\"absorbing\""]
);
refused!(
    track_end_damping_on_free_ends,
    track_text().replace(
        "bays = 100",
        "bays = 100\nends = \"free\"\nend_damping = 10.0"
    ),
    ["`track.end_damping` = 10", "ends = \"absorbing\""]
);
refused!(
    track_misspelt_key,
    track_text().replace("set = \"uic60\"", "pad_stifness = 1e8"),
    ["pad_stifness", "pad_stiffness"]
);
refused!(
    track_travel_into_the_sponge,
    track_text().replace("travel_bays = 6", "travel_bays = 50"),
    [
        "`vehicle.travel_bays` = 50",
        "absorbing zones",
        "25 bays before the middle, 20 there"
    ]
);
refused!(
    track_missing_speed,
    track_text().replace("speed = 30.0", ""),
    ["`vehicle.speed`", "m/s"]
);
refused!(
    track_zero_speed,
    track_text().replace("speed = 30.0", "speed = 0.0"),
    ["`vehicle.speed` = 0", "> 0"]
);
refused!(
    track_negative_unsprung_mass,
    track_text().replace("unsprung_mass = 800.0", "unsprung_mass = -800.0"),
    ["`vehicle.unsprung_mass` = -800", "> 0"]
);
refused!(
    track_receptance_upside_down,
    track_text().replace("f_max = 3000.0", "f_max = 10.0"),
    ["`receptance.f_max` = 10", "above receptance.f_min = 20"]
);
refused!(
    track_receptance_two_points,
    track_text().replace("points = 400", "points = 2"),
    ["`receptance.points` = 2", "at least 3"]
);
refused!(
    track_with_t_end,
    track_text().replace("h = 5e-5", "h = 5e-5\nt_end = 1.0"),
    ["`time.t_end`", "remove time.t_end"]
);
refused!(
    track_with_contact,
    format!("{}\n[contact]\nmethod = \"exact\"\n", track_text()),
    ["`contact`", "no contact", "moving_load"]
);
refused!(
    track_run_with_a_method,
    format!("{}\n[[runs]]\nmethod = \"exact\"\n", track_text()),
    ["`runs[0].method`", "no contact"]
);
refused!(
    track_explicit,
    track_text().replace("h = 5e-5", "h = 5e-5\nintegrator = \"central_difference\""),
    [
        "`time.integrator` = \"central_difference\"",
        "\"space_time\""
    ]
);
refused!(
    track_with_a_bar_table,
    format!(
        "{}\n[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n",
        track_text()
    ),
    ["`bar`", "not by kind = \"track\""]
);
refused!(
    track_table_on_a_bar,
    format!("{}\n[vehicle]\nspeed = 30.0\n", common::BAR),
    ["`vehicle`", "read by kind = \"track\" only"]
);

refused!(
    rolling_with_the_soft_way_restoring,
    rolling_text().replace("method = \"exact\"", "method = \"soft_way\""),
    [
        "`contact.method` = \"soft_way\"",
        "\"soft_way_no_restore\"",
        "momentum back"
    ]
);
refused!(
    rolling_with_friction_and_no_suspension,
    rolling_text().replace("method = \"exact\"", "method = \"exact\"\nfriction = 0.3"),
    [
        "`contact.friction` = 0.3",
        "vehicle.suspension_stiffness > 0",
        "along the track"
    ]
);
refused!(
    rolling_with_friction_and_no_numerical_dissipation,
    rolling_text()
        .replace("method = \"exact\"", "method = \"exact\"\nfriction = 0.3")
        .replace(
            "speed_km_h = 100.0",
            "speed_km_h = 100.0\nsuspension_stiffness = 1e7"
        ),
    ["`time.gamma` = 0", "time.gamma > 0", "falls short of mu P"]
);
refused!(
    rolling_creepage_out_of_range,
    rolling_text().replace("speed_km_h = 100.0", "speed_km_h = 100.0\ncreepage = 2.0"),
    ["`vehicle.creepage` = 2", "[-0.5, 0.5]"]
);
refused!(
    rolling_with_two_speeds,
    rolling_text().replace("speed_km_h = 100.0", "speed_km_h = 100.0\nspeed = 27.0"),
    ["`vehicle.speed`", "not both"]
);
refused!(
    rolling_unknown_model,
    rolling_text().replace("model = \"wheel\"", "model = \"bogie\""),
    ["`vehicle.model` = \"bogie\"", "\"moving_load\""]
);
refused!(
    rolling_step_too_long,
    rolling_text().replace("gamma = 0.0", "gamma = 0.0\nh = 1e-4"),
    ["`time.h` = 0.0001", "rim node passes", "at most half"]
);
refused!(
    rolling_hub_bigger_than_the_wheel,
    rolling_text().replace(
        "wheel_thickness = 0.02",
        "wheel_thickness = 0.02\nwheel_hub_radius = 0.5"
    ),
    ["`vehicle.wheel_hub_radius` = 0.5", "below"]
);
refused!(
    rolling_rim_band_thinner_than_the_pitch,
    rolling_text().replace(
        "wheel_thickness = 0.02",
        "wheel_thickness = 0.02\nwheel_rim_band = 0.001"
    ),
    [
        "`vehicle.wheel_rim_band` = 0.001",
        "at least the rim's pitch"
    ]
);
refused!(
    rolling_rim_band_deeper_than_the_wheel,
    rolling_text().replace(
        "wheel_thickness = 0.02",
        "wheel_thickness = 0.02\nwheel_rim_band = 0.4"
    ),
    ["`vehicle.wheel_rim_band` = 0.4", "the hub, left inside"]
);
refused!(
    rolling_settle_into_the_sponge,
    rolling_text().replace("settle_bays = 4", "settle_bays = 15"),
    ["`vehicle.settle_bays` = 15", "absorbing zones"]
);
/// A measured irregularity read from a CSV file whose every cell is quoted (as some
/// spreadsheets export them, RFC 4180) gives the same points as the plain file.
#[test]
fn a_measured_irregularity_reads_quoted_cells() {
    let dir = fresh_dir("irregularity", "quoted");
    let points = |name: &str, body: &str| {
        let f = dir.join(name);
        std::fs::write(&f, body).unwrap();
        let text = format!(
            "{}\n[irregularity]\ntype = \"measured\"\nfile = \"{}\"\n",
            rolling_text(),
            f.display()
        );
        let sc = softway::scenario::Scenario::from_str(&text, &dir.join("t.toml")).unwrap();
        let Some(t) = sc.runs[0].model.get::<softway::scenario::TrackScenario>() else {
            panic!("a track")
        };
        match &t.irregularity {
            Some(softway::scenario::Irregularity::Measured { points, .. }) => points.clone(),
            other => panic!("{other:?}"),
        }
    };
    let plain = points("plain.csv", "x_m,r_m\n0,0\n0.5,1e-5\n1.0,-2e-5\n");
    let quoted = points(
        "quoted.csv",
        "\"x_m\",\"r_m\"\n\"0\",\"0\"\n\"0.5\", \"1e-5\"\n\"1.0\",\"-2e-5\"\n",
    );
    assert_eq!(plain, [(0.0, 0.0), (0.5, 1e-5), (1.0, -2e-5)]);
    assert_eq!(quoted, plain);
}

refused!(
    rolling_irregularity_of_unknown_type,
    format!("{}\n[irregularity]\ntype = \"sawtooth\"\n", rolling_text()),
    ["`irregularity.type` = \"sawtooth\"", "\"harmonic\""]
);
refused!(
    rolling_irregularity_without_wavelength,
    format!("{}\n[irregularity]\namplitude = 1e-5\n", rolling_text()),
    ["`irregularity.wavelength`"]
);
refused!(
    rolling_irregularity_key_of_another_type,
    format!(
        "{}\n[irregularity]\ntype = \"harmonic\"\namplitude = 1e-5\nwavelength = 0.05\nseed = 3\n",
        rolling_text()
    ),
    [
        "`irregularity.seed`",
        "not used with irregularity.type = \"harmonic\""
    ]
);
refused!(
    rolling_irregularity_file_missing,
    format!(
        "{}\n[irregularity]\ntype = \"measured\"\nfile = \"no-such-profile.csv\"\n",
        rolling_text()
    ),
    [
        "`irregularity.file`",
        "no-such-profile.csv",
        "cannot be read"
    ]
);
refused!(
    moving_load_with_an_irregularity,
    format!(
        "{}\n[irregularity]\namplitude = 1e-5\nwavelength = 0.05\n",
        track_text()
    ),
    ["`irregularity`", "moving load"]
);
refused!(
    moving_load_with_wheel_keys,
    track_text().replace("travel_bays = 6", "travel_bays = 6\nwheel_rim_nodes = 1440"),
    [
        "`vehicle.wheel_rim_nodes`",
        "only used with vehicle.model = \"wheel\""
    ]
);

#[test]
fn receptance_of_a_bar() {
    refused_on_bar(
        "receptance_bar",
        "receptance",
        &[],
        &["receptance_bar.toml", "needs a track scenario"],
    );
}

// ---------------------------------------------------------------- scenario: wheels

fn wheel_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/wheel-paper-mesh.toml"
    ))
    .unwrap()
}

refused!(
    wheel_rings_absurd,
    wheel_text().replace("rings = 12", "rings = 100000"),
    ["`wheel.rings` = 100000", "1 to 400"]
);
refused!(
    wheel_too_few_rim_nodes,
    wheel_text().replace("rings = 12", "rim_nodes = 5"),
    ["`wheel.rim_nodes` = 5", "at least 12"]
);
refused!(
    wheel_two_meshes,
    wheel_text().replace("rings = 12", "rings = 12\nmesh = \"a.msh\""),
    ["`wheel.mesh`", "give one of"]
);
refused!(
    wheel_grading_out_of_range,
    wheel_text().replace("rings = 12", "rim_nodes = 72\ngrading = 3.0"),
    ["`wheel.grading` = 3", "[1, 2]"]
);
refused!(
    wheel_poisson_half,
    wheel_text().replace("poisson = 0.3", "poisson = 0.5"),
    ["`material.poisson` = 0.5", "(-1, 0.5)"]
);
refused!(
    wheel_young_nan,
    wheel_text().replace("young = 2.05e11", "young = nan"),
    ["`material.young` = NaN", "> 0"]
);
refused!(
    wheel_flattening_beyond_radius,
    wheel_text().replace("flattening = 1e-3", "flattening = 0.2"),
    ["`rolling.flattening` = 0.2", "smaller than wheel.radius"]
);
refused!(
    wheel_hub_beyond_radius,
    wheel_text().replace(
        "support = \"centre\"",
        "support = \"hub\"\nhub_radius = 0.5"
    ),
    ["`wheel.hub_radius` = 0.5", "smaller than wheel.radius"]
);
refused!(
    wheel_zero_speed,
    wheel_text().replace("omega = 300.0", "omega = 0.0"),
    ["`rolling.omega` = 0", "> 0"]
);
fn block_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/wheel-on-block.toml"
    ))
    .unwrap()
}

refused!(
    block_poisson_half,
    block_text().replace(
        "poisson = 0.3\ndensity = 7830.0        # kg",
        "poisson = 0.5\ndensity = 7830.0        # kg"
    ),
    ["`block.poisson` = 0.5", "(-1, 0.5)"]
);
refused!(
    block_shallower_than_the_flattening,
    block_text().replace("depth = 0.05 ", "depth = 0.001 "),
    [
        "`block.depth` = 0.001",
        "deeper than twice rolling.flattening"
    ]
);
refused!(
    block_grading_out_of_range,
    block_text().replace("grading = 1.2", "grading = 2.5"),
    ["`block.grading` = 2.5", "[1, 2]"]
);
refused!(
    block_misspelt_key,
    block_text().replace("margin = 0.06", "margni = 0.06"),
    ["margni", "margin"]
);
refused!(
    block_with_friction,
    block_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\nfriction = 0.3"
    ),
    ["`block`", "contact.friction"]
);
refused!(
    block_under_a_bar,
    format!("{}\n[block]\ndepth = 0.05\n", common::BAR),
    ["`block`", "kind = \"wheel\""]
);

refused!(
    wheel_with_an_end_time,
    wheel_text().replace("h = 2e-6", "h = 2e-6\nt_end = 1.0"),
    ["`time.t_end`", "remove time.t_end"]
);
refused!(
    wheel_zero_fields_per_turn,
    wheel_text().replace("fields_per_turn = 8", "fields_per_turn = 0"),
    ["`rolling.fields_per_turn` = 0", "1 to 1000"]
);
refused!(
    wheel_negative_friction,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\nfriction = -0.2"
    ),
    ["`contact.friction` = -0.2"]
);
refused!(
    wheel_negative_tangential_stiffness,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\nfriction = 0.3\ntangential_stiffness = -1e9"
    ),
    ["`contact.tangential_stiffness` = -1000000000", "> 0"]
);
refused!(
    wheel_tangential_stiffness_without_friction,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\ntangential_stiffness = 1e9"
    ),
    ["`contact.tangential_stiffness`", "needs contact.friction"]
);
refused!(
    wheel_unknown_coupling,
    wheel_text().replace("turns = 5", "turns = 5\ncoupling = \"loose\""),
    [
        "`rolling.coupling` = \"loose\"",
        "\"coupled\"",
        "\"uncoupled\""
    ]
);
refused!(
    wheel_uncoupled_without_friction,
    wheel_text().replace("turns = 5", "turns = 5\ncoupling = \"uncoupled\""),
    ["`rolling.coupling`", "contact.friction > 0"]
);
refused!(
    wheel_uncoupled_on_segments,
    wheel_text()
        .replace("turns = 5", "turns = 5\ncoupling = \"uncoupled\"")
        .replace(
            "method = \"soft_way\"",
            "method = \"soft_way\"\nfriction = 0.3"
        )
        .replace("[wheel]", "[wheel]\ncontact_surface = \"segments\""),
    ["`rolling.coupling`", "wheel.contact_surface"]
);
refused!(
    wheel_friction_with_subdivision,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"subdivision\"\nfriction = 0.3"
    ),
    [
        "`contact.friction` = 0.3",
        "subdivision",
        "mass_redistribution"
    ]
);
refused!(
    wheel_a_billion_turns,
    wheel_text().replace("turns = 5", "turns = 1e9"),
    ["`time.h`", "steps", "with or without --yes"]
);

// ---------------------------------------------------------------- scenario: [[runs]]

refused!(
    runs_unknown_key,
    format!("{BAR}\n[[runs]]\nstep = 0.05\n"),
    ["step", "runs"]
);
refused!(
    runs_negative_step,
    format!("{BAR}\n[[runs]]\nh = 0.05\n[[runs]]\nh = -1.0\n"),
    ["`runs[1].h` = -1", "> 0"]
);
// A label is a column of history.csv and a line of a legend: a comma or a quote is written
// quoted (tests/results.rs), a line break or another control character is refused.
refused!(
    runs_label_with_a_line_break,
    format!("{BAR}\n[[runs]]\nlabel = \"h = 0.1, soft way\"\n[[runs]]\nlabel = \"two\\nlines\"\n"),
    ["`runs[1].label` = \"two\\nlines\"", "one line of text"]
);
refused!(
    runs_label_with_a_tab,
    format!("{BAR}\n[[runs]]\nlabel = \"a\\tb\"\n"),
    ["`runs[0].label`", "control character"]
);
refused!(
    runs_unknown_method,
    format!("{BAR}\n[[runs]]\nmethod = \"glue\"\n"),
    ["`runs[0].method` = \"glue\"", "allowed"]
);
refused!(
    runs_not_tables,
    BAR.replace("kind =", "runs = 3\nkind ="),
    ["runs", "expected a sequence"]
);
refused!(
    runs_elements_on_a_wheel,
    format!("{}\n[[runs]]\nelements = 4\n", wheel_text()),
    ["`runs[0].elements` = 4", "only bar scenarios"]
);

// ---------------------------------------------------------------- scenario: every key used

/// The shipped `scenarios/<name>.toml`.
fn shipped_text(name: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{name}.toml")),
    )
    .unwrap()
}

/// The bar without `time.alpha` (for the classic integrators, which do not use it).
fn bar_classic(integrator: &str) -> String {
    BAR.replace("alpha = 0.8\n", &format!("integrator = \"{integrator}\"\n"))
        + "[contact]\nmethod = \"exact\"\n"
}

const ROLLING: &str =
    "[rolling]\nomega = 300.0\nflattening = 1e-3\nsettle_time = 5e-3\nturns = 1\n";

refused!(
    bar_table_in_a_wheel,
    format!(
        "{}\n[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n",
        wheel_text()
    ),
    [
        "`bar` = (a table)",
        "read by kind = \"bar_impact\" only, not by kind = \"wheel\"",
        "remove [bar]"
    ]
);
refused!(
    two_bars_table_in_a_wheel,
    format!("{}\n[two_bars]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n", wheel_text()),
    ["`two_bars`", "not by kind = \"wheel\""]
);
refused!(
    rolling_table_in_a_bar,
    format!("{BAR}{ROLLING}"),
    [
        "`rolling`",
        "read by kind = \"wheel\", kind = \"rolling3d\" only, not by kind = \"bar_impact\""
    ]
);
refused!(
    material_table_in_a_bar,
    format!("{BAR}[material]\nyoung = 2.05e11\npoisson = 0.3\ndensity = 7830.0\n"),
    ["`material`", "not by kind = \"bar_impact\""]
);
refused!(
    contact_table_in_an_oscillator,
    shipped_text("sdof") + "[contact]\nmethod = \"exact\"\n",
    [
        "`contact`",
        "not by kind = \"sdof\"",
        "the oscillator has no contact"
    ]
);
refused!(
    runs_method_in_an_oscillator,
    shipped_text("sdof").replace(
        "label = \"h = 0.1, gamma 0\"",
        "label = \"h = 0.1, gamma 0\"\nmethod = \"exact\""
    ),
    [
        "`runs[1].method` = \"exact\"",
        "the oscillator has no contact"
    ]
);
refused!(
    penalty_with_the_soft_way,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\npenalty = 1e9"
    ),
    [
        "`contact.penalty` = 1000000000",
        "the stiffness of method = \"penalty\"",
        "not used by method = \"soft_way\""
    ]
);
refused!(
    restitution_with_the_default_soft_way,
    format!("{BAR}[contact]\nrestitution = 0.5\n"),
    [
        "`contact.restitution` = 0.5",
        "not used by method = \"soft_way\""
    ]
);
refused!(
    runs_penalty_with_exact,
    format!("{BAR}[[runs]]\nmethod = \"exact\"\npenalty = 1e4\n"),
    [
        "`runs[0].penalty` = 10000",
        "not used by method = \"exact\""
    ]
);
refused!(
    a_second_run_in_a_wheel,
    format!(
        "{}\n[[runs]]\nlabel = \"a\"\n[[runs]]\nlabel = \"b\"\n",
        wheel_text()
    ),
    ["`runs[1]`", "a wheel scenario runs one run", "sweep --set"]
);
refused!(
    alpha_with_newmark,
    bar_classic("newmark").replace("h = 0.1", "h = 0.1\nalpha = 0.8"),
    [
        "`time.alpha` = 0.8",
        "alpha of the space-time scheme",
        "not used by integrator = \"newmark\""
    ]
);
refused!(
    gamma_with_hht,
    bar_classic("hht").replace("h = 0.1", "h = 0.1\ngamma = 0.2"),
    ["`time.gamma` = 0.2", "not used by integrator = \"hht\""]
);
refused!(
    runs_alpha_with_generalized_alpha,
    format!(
        "{}[[runs]]\nalpha = 0.5\n",
        bar_classic("generalized_alpha")
    ),
    [
        "`runs[0].alpha` = 0.5",
        "not used by integrator = \"generalized_alpha\""
    ]
);
refused!(
    gamma_n_with_newmark,
    bar_classic("newmark").replace("h = 0.1", "h = 0.1\ngamma_n = 0.6"),
    [
        "`time.gamma_n` = 0.6",
        "not used by integrator = \"newmark\""
    ]
);
refused!(
    coriolis_on_a_bar,
    BAR.replace("h = 0.1", "h = 0.1\ncoriolis = \"extrapolated\""),
    [
        "`time.coriolis` = \"extrapolated\"",
        "only a rotating wheel"
    ]
);
refused!(
    coriolis_on_a_wheel_without_its_rotating_frame,
    wheel_text()
        .replace("h = 2e-6", "h = 2e-6\ncoriolis = \"extrapolated\"")
        .replace("[wheel]", "[wheel]\nrotating_frame = false"),
    ["`time.coriolis`", "wheel.rotating_frame = false"]
);
refused!(
    step_that_every_run_overrides,
    format!("{BAR}[[runs]]\nh = 0.05\n[[runs]]\nh = 0.02\n"),
    ["`time.h` = 0.1", "every [[runs]] entry sets its own h"]
);
refused!(
    elements_that_every_run_overrides,
    format!("{BAR}[[runs]]\nelements = 4\n[[runs]]\nelements = 16\n"),
    [
        "`bar.elements` = 8",
        "every [[runs]] entry sets its own elements"
    ]
);
refused!(
    step_beside_cfl,
    bar_classic("central_difference").replace("h = 0.1", "h = 0.1\ncfl = 0.5"),
    ["`time.h` = 0.1", "the step is set by time.cfl"]
);
refused!(
    runs_step_beside_its_cfl,
    format!(
        "{}[[runs]]\nh = 0.05\ncfl = 0.5\n",
        bar_classic("central_difference").replace("h = 0.1\n", "")
    ),
    ["`runs[0].h` = 0.05", "the step is set by runs[0].cfl"]
);
refused!(
    consistent_mass_with_the_central_difference,
    bar_classic("central_difference")
        .replace("elements = 8", "elements = 8\nmass = \"consistent\""),
    ["`bar.mass` = \"consistent\"", "lumped mass"]
);
refused!(
    stress_stiffening_without_the_rotating_frame,
    wheel_text().replace(
        "[wheel]",
        "[wheel]\nrotating_frame = false\nstress_stiffening = true"
    ),
    [
        "`wheel.stress_stiffening` = true",
        "wheel.rotating_frame = false"
    ]
);
refused!(
    grading_with_a_refined_zone,
    shipped_text("wheel-zone").replace("rim_nodes = 144", "rim_nodes = 144\ngrading = 1.2"),
    [
        "`wheel.grading` = 1.2",
        "not used by the refined zone's mesh"
    ]
);
refused!(
    settle_gamma_without_settling,
    wheel_text().replace(
        "settle_time = 5e-3",
        "settle_time = 0.0\nsettle_gamma = 0.5"
    ),
    ["`rolling.settle_gamma` = 0.5", "rolling.settle_time = 0"]
);
refused!(
    settle_gamma_with_a_classic_integrator,
    wheel_text()
        .replace("alpha = 0.8\ngamma = 0.2\n", "integrator = \"hht\"\n")
        .replace("method = \"soft_way\"", "method = \"exact\"")
        .replace(
            "settle_time = 5e-3",
            "settle_time = 5e-3\nsettle_gamma = 0.5"
        ),
    ["`rolling.settle_gamma` = 0.5", "classic integrator"]
);
refused!(
    fields_per_turn_on_a_block,
    block_text().replace("turns = 0.5", "turns = 0.5\nfields_per_turn = 4"),
    ["`rolling.fields_per_turn` = 4", "[block]"]
);
refused!(
    tangential_stiffness_without_friction,
    wheel_text().replace(
        "method = \"soft_way\"",
        "method = \"soft_way\"\nfriction = 0.0\ntangential_stiffness = 1e9"
    ),
    ["`contact.tangential_stiffness`", "contact.friction = 0"]
);
refused!(
    trapezoidal_newmark_with_exact_contact_on_the_wheel,
    wheel_text()
        .replace("alpha = 0.8\ngamma = 0.2\n", "integrator = \"newmark\"\n")
        .replace("method = \"soft_way\"", "method = \"exact\""),
    [
        "`time.integrator` = \"newmark\"",
        "period-2h mode undamped",
        "newmark_dissipative"
    ]
);

/// `sweep --set KEY=...` of a key every `[[runs]]` entry overrides (every point would be the
/// same), and `converge` likewise: refused before anything is written.
#[test]
fn sweep_of_a_key_every_run_overrides() {
    let text = format!(
        "{}[[runs]]\nh = 0.05\nelements = 8\n[[runs]]\nh = 0.02\nelements = 16\n",
        BAR.replace("h = 0.1\n", "").replace("elements = 8\n", "")
    );
    let p = scenario("sweep_shadowed", &text);
    let out = p.with_extension("out");
    for (command, set, must) in [
        ("sweep", "time.h=0.1,0.2", "`time.h` = 0.1"),
        ("converge", "bar.elements=4,8,16", "`bar.elements` = 4"),
    ] {
        let key = set.split('=').next().unwrap();
        cli_refused(
            &[
                command,
                p.to_str().unwrap(),
                "--set",
                set,
                "--out",
                out.to_str().unwrap(),
            ],
            &[
                "sweep_shadowed.toml",
                must,
                &format!(
                    "every [[runs]] entry sets its own {}",
                    &key[key.find('.').unwrap() + 1..]
                ),
            ],
        );
        assert_nothing_written(&out);
    }
}

// ---------------------------------------------------------------- scenario: files

#[test]
fn empty_file() {
    let (c, e) = run_file_err(&scenario("empty_file", ""));
    assert_one_line_error(c, &e, &["empty_file.toml", "kind"]);
}

#[test]
fn binary_file() {
    let bytes: Vec<u8> = (0..=255u8).cycle().take(2048).collect();
    let (c, e) = run_file_err(&scenario_bytes("binary_file", &bytes));
    assert_one_line_error(c, &e, &["binary_file.toml", "UTF-8"]);
}

#[test]
fn non_utf8_file() {
    // "name = \"r\xe9sultat\"" in Latin-1.
    let mut bytes = BAR.as_bytes().to_vec();
    bytes.extend(b"\nname = \"r\xe9sultat\"\n");
    let (c, e) = run_file_err(&scenario_bytes("latin1", &bytes));
    assert_one_line_error(c, &e, &["latin1.toml", "UTF-8"]);
}

#[test]
fn a_directory_in_place_of_the_scenario() {
    let dir = fresh_dir("cli", "dir_scenario").join("scenario.toml");
    std::fs::create_dir_all(&dir).unwrap();
    let (c, e) = run_file_err(&dir);
    assert_one_line_error(
        c,
        &e,
        &[
            "scenario.toml",
            "cannot read the scenario",
            "is a directory, not a scenario file",
        ],
    );
}

/// A device that never ends (`/dev/zero`) is refused before it is read.
#[test]
fn a_device_in_place_of_the_scenario() {
    let out = fresh_dir("cli", "dev_zero").join("out");
    let o = cli(["run", "/dev/zero", "--out", out.to_str().unwrap()]);
    assert_one_line_error(o.code, &o.stderr, &["/dev/zero", "not a regular file"]);
    assert_nothing_written(&out);
}

/// A scenario of 17 MiB (a sparse file of zeros) is refused without being parsed.
#[test]
fn an_absurdly_large_scenario() {
    let p = scenario("huge_file", "");
    std::fs::File::options()
        .write(true)
        .open(&p)
        .unwrap()
        .set_len(17 << 20)
        .unwrap();
    let (c, e) = run_file_err(&p);
    assert_one_line_error(c, &e, &["huge_file.toml", "larger than 16 MiB"]);
}

// ---------------------------------------------------------------- meshes

/// A disk of `rings` hexagonal rings (radius 0.1 m) in Gmsh terms: nodes (tag, x, y), the
/// rim's node tags in order, the centre's tag and the triangles' node tags.
#[derive(Clone)]
struct Disk {
    nodes: Vec<(u64, [f64; 2])>,
    rim: Vec<u64>,
    centre: u64,
    tris: Vec<[u64; 3]>,
}

fn disk() -> Disk {
    let mesh = disk_rings(0.1, 3).unwrap();
    let Cells::Tri3(tris) = &mesh.cells else {
        unreachable!()
    };
    Disk {
        nodes: (0..mesh.n_nodes())
            .map(|i| (i as u64 + 1, [mesh.point(i)[0], mesh.point(i)[1]]))
            .collect(),
        rim: mesh
            .node_set("rim")
            .unwrap()
            .iter()
            .map(|&i| i as u64 + 1)
            .collect(),
        centre: mesh.node_set("centre").unwrap()[0] as u64 + 1,
        tris: tris
            .iter()
            .map(|t| [t[0] as u64 + 1, t[1] as u64 + 1, t[2] as u64 + 1])
            .collect(),
    }
}

impl Disk {
    fn xy(&self, tag: u64) -> [f64; 2] {
        self.nodes.iter().find(|n| n.0 == tag).unwrap().1
    }

    /// ASCII MSH 4.1 (version `version` in the header): a point entity (the centre,
    /// physical "centre"), a curve (the rim's line elements, physical "rim") and a surface
    /// holding every node but the centre.
    fn ascii(&self, version: &str) -> String {
        let mut s = format!("$MeshFormat\n{version} 0 8\n$EndMeshFormat\n");
        s.push_str(
            "$PhysicalNames\n3\n0 1 \"centre\"\n1 2 \"rim\"\n2 3 \"body\"\n$EndPhysicalNames\n",
        );
        s.push_str("$Entities\n1 1 1 0\n1 0 0 0 1 1\n1 -0.1 -0.1 0 0.1 0.1 0 1 2 0\n1 -0.1 -0.1 0 0.1 0.1 0 1 3 0\n$EndEntities\n");
        let (min, max) = (
            self.nodes.iter().map(|n| n.0).min().unwrap(),
            self.nodes.iter().map(|n| n.0).max().unwrap(),
        );
        let c_at = self.nodes.iter().position(|n| n.0 == self.centre).unwrap();
        let others: Vec<&(u64, [f64; 2])> = (0..self.nodes.len())
            .filter(|&i| i != c_at)
            .map(|i| &self.nodes[i])
            .collect();
        let _ = writeln!(s, "$Nodes\n2 {} {min} {max}", self.nodes.len());
        let c = self.nodes[c_at].1;
        let _ = writeln!(s, "0 1 0 1\n{}\n{} {} 0", self.centre, c[0], c[1]);
        let _ = writeln!(s, "2 1 0 {}", others.len());
        for n in &others {
            let _ = writeln!(s, "{}", n.0);
        }
        for n in &others {
            let _ = writeln!(s, "{} {} 0", n.1[0], n.1[1]);
        }
        s.push_str("$EndNodes\n");
        let (r, m) = (self.rim.len(), self.tris.len());
        let total = 1 + r + m;
        let _ = writeln!(s, "$Elements\n3 {total} 1 {total}");
        let _ = writeln!(s, "0 1 15 1\n1 {}", self.centre);
        let _ = writeln!(s, "1 1 1 {r}");
        for k in 0..r {
            let _ = writeln!(s, "{} {} {}", 2 + k, self.rim[k], self.rim[(k + 1) % r]);
        }
        let _ = writeln!(s, "2 1 2 {m}");
        for (e, t) in self.tris.iter().enumerate() {
            let _ = writeln!(s, "{} {} {} {}", 2 + r + e, t[0], t[1], t[2]);
        }
        s.push_str("$EndElements\n");
        s
    }

    /// Binary MSH 4.1 (little endian): one surface entity holding every node and triangle.
    fn binary(&self) -> Vec<u8> {
        let mut b: Vec<u8> = b"$MeshFormat\n4.1 1 8\n".to_vec();
        b.extend(1i32.to_le_bytes());
        b.extend(b"\n$EndMeshFormat\n$Entities\n");
        for n in [0u64, 0, 1, 0] {
            b.extend(n.to_le_bytes());
        }
        b.extend(1i32.to_le_bytes());
        for v in [-0.1f64, -0.1, 0.0, 0.1, 0.1, 0.0] {
            b.extend(v.to_le_bytes());
        }
        b.extend(0u64.to_le_bytes());
        b.extend(0u64.to_le_bytes());
        b.extend(b"\n$EndEntities\n$Nodes\n");
        let n = self.nodes.len() as u64;
        for v in [1u64, n, 1, n] {
            b.extend(v.to_le_bytes());
        }
        for v in [2i32, 1, 0] {
            b.extend(v.to_le_bytes());
        }
        b.extend(n.to_le_bytes());
        for node in &self.nodes {
            b.extend(node.0.to_le_bytes());
        }
        for node in &self.nodes {
            for v in [node.1[0], node.1[1], 0.0] {
                b.extend(v.to_le_bytes());
            }
        }
        b.extend(b"\n$EndNodes\n$Elements\n");
        let m = self.tris.len() as u64;
        for v in [1u64, m, 1, m] {
            b.extend(v.to_le_bytes());
        }
        for v in [2i32, 1, 2] {
            b.extend(v.to_le_bytes());
        }
        b.extend(m.to_le_bytes());
        for (e, t) in self.tris.iter().enumerate() {
            for v in [e as u64 + 1, t[0], t[1], t[2]] {
                b.extend(v.to_le_bytes());
            }
        }
        b.extend(b"\n$EndElements\n");
        b
    }
}

/// A short wheel run (centre pinned) on the mesh file `mesh.msh` holding `bytes`; the
/// folder, the scenario and its output folder.
fn wheel_on_mesh(name: &str, bytes: &[u8]) -> (PathBuf, PathBuf) {
    let dir = fresh_dir("mesh", name);
    std::fs::write(dir.join("mesh.msh"), bytes).unwrap();
    let text = wheel_text()
        .replace("rings = 12", "mesh = \"mesh.msh\"")
        .replace("turns = 5", "turns = 0.02")
        // The coarse test disks (18 rim nodes) need 1.5 mm for the base's chord to span a
        // rim pitch (a shallower flattening is refused before the run).
        .replace("flattening = 1e-3", "flattening = 2e-3")
        .replace("settle_time = 5e-3", "settle_time = 2e-4")
        .replace("h = 2e-6", "h = 1e-5")
        .replace("history_stride = 5", "history_stride = 5\nplots = false");
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    (dir, p)
}

/// [`wheel_on_mesh`] held by a hub on the disk's first ring (r = R/3) instead of the pinned
/// centre: the 18-node rim of the coarse test disks rocks its free rigid rotation past a
/// quarter of the flattening within a millisecond, which stops a pinned run
/// ([`softway::guard::Cause::Turned`]); the cases that must run are held.
fn held_wheel_on_mesh(name: &str, bytes: &[u8]) -> (PathBuf, PathBuf) {
    let (dir, p) = wheel_on_mesh(name, bytes);
    let text = std::fs::read_to_string(&p).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("support = \"centre\""))
        .unwrap()
        .to_string();
    std::fs::write(
        &p,
        text.replace(&line, "support = \"hub\"\nhub_radius = 0.0334"),
    )
    .unwrap();
    (dir, p)
}

/// A mesh case: the scenario `$name.toml` names `mesh.msh` (holding `$bytes`) as its
/// `wheel.mesh`; the message names the scenario, the key, the mesh file and `$must`.
macro_rules! mesh_refused {
    ($name:ident, $bytes:expr, [$($must:expr),*]) => {
        #[test]
        fn $name() {
            let bytes: Vec<u8> = $bytes;
            let (_dir, p) = wheel_on_mesh(stringify!($name), &bytes);
            let (c, e) = run_file_err(&p);
            assert_one_line_error(
                c,
                &e,
                &[concat!(stringify!($name), ".toml"), "`wheel.mesh`", "mesh.msh", $($must),*],
            );
        }
    };
}

fn ascii(d: &Disk) -> Vec<u8> {
    d.ascii("4.1").into_bytes()
}

/// The disk with `f` applied.
fn disk_with(f: impl FnOnce(&mut Disk)) -> Disk {
    let mut d = disk();
    f(&mut d);
    d
}

#[test]
fn the_disk_files_of_these_tests_are_valid_meshes() {
    // The unmodified ASCII and binary disks read as the generator's disk (37 nodes, 54
    // triangles, 6 * 3 = 18 nodes on its outermost ring at the radius 0.1 m: ring 3 of 3,
    // the next ring in lies at 2/3 of the radius), so every refusal below is due to its one
    // change. The ASCII file's "rim" group is that ring, counted independently of the group
    // from the nodes' radii; the binary file has no physical groups (one surface entity).
    for (name, bytes) in [("a", ascii(&disk())), ("b", disk().binary())] {
        let p = fresh_dir("mesh", &format!("valid-{name}")).join("d.msh");
        std::fs::write(&p, bytes).unwrap();
        let m = softway::mesh::gmsh::read_msh(&p).unwrap();
        assert_eq!((m.n_nodes(), m.cells.len()), (37, 54));
        let outer: Vec<usize> = (0..m.n_nodes())
            .filter(|&i| (m.point(i)[0].hypot(m.point(i)[1]) / 0.1 - 1.0).abs() < 1e-9)
            .collect();
        assert_eq!(outer.len(), 6 * 3, "{name}");
        if name == "a" {
            let mut rim = m.node_set("rim").expect("the rim group").to_vec();
            rim.sort_unstable();
            assert_eq!(rim, outer);
        } else {
            assert!(m.node_set("rim").is_none(), "the binary disk has no groups");
        }
    }
}

#[test]
fn mesh_file_missing() {
    let (dir, p) = wheel_on_mesh("mesh_file_missing", b"");
    std::fs::remove_file(dir.join("mesh.msh")).unwrap();
    let (c, e) = run_file_err(&p);
    assert_one_line_error(
        c,
        &e,
        &[
            "mesh_file_missing.toml",
            "`wheel.mesh`",
            "mesh.msh",
            "No such file",
        ],
    );
}

#[test]
fn mesh_is_a_directory() {
    let (dir, p) = wheel_on_mesh("mesh_is_a_directory", b"");
    std::fs::remove_file(dir.join("mesh.msh")).unwrap();
    std::fs::create_dir(dir.join("mesh.msh")).unwrap();
    let (c, e) = run_file_err(&p);
    assert_one_line_error(
        c,
        &e,
        &[
            "mesh_is_a_directory.toml",
            "`wheel.mesh`",
            "mesh.msh",
            "directory",
        ],
    );
}

#[test]
fn mesh_is_a_device() {
    let dir = fresh_dir("mesh", "mesh_is_a_device");
    let text = wheel_text().replace("rings = 12", "mesh = \"/dev/zero\"");
    let p = dir.join("mesh_is_a_device.toml");
    std::fs::write(&p, text).unwrap();
    let (c, e) = run_file_err(&p);
    assert_one_line_error(
        c,
        &e,
        &[
            "mesh_is_a_device.toml",
            "`wheel.mesh`",
            "/dev/zero",
            "not a regular file",
        ],
    );
}

mesh_refused!(
    mesh_not_gmsh,
    BAR.as_bytes().to_vec(),
    ["not a Gmsh mesh file"]
);
mesh_refused!(mesh_empty, Vec::new(), ["not a Gmsh mesh file"]);
mesh_refused!(
    mesh_truncated_ascii,
    {
        let a = ascii(&disk());
        a[..a.len() * 6 / 10].to_vec()
    },
    ["invalid Gmsh MSH 4.1 file"]
);
mesh_refused!(
    mesh_truncated_binary,
    {
        let b = disk().binary();
        b[..b.len() * 6 / 10].to_vec()
    },
    ["invalid Gmsh MSH 4.1 file", "at byte"]
);
mesh_refused!(
    mesh_msh_2_2,
    disk().ascii("2.2").into_bytes(),
    ["version 2.2", "only 4.1"]
);
mesh_refused!(
    mesh_msh_4_0,
    disk().ascii("4.0").into_bytes(),
    ["version 4.0", "only 4.1"]
);
mesh_refused!(
    mesh_3d_only,
    b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n".to_vec(),
    ["element 1", "type 4 (Tet4)", "3D", "only 3-node triangles"]
);
mesh_refused!(
    mesh_of_quads,
    b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n$Elements\n1 1 7 7\n2 1 3 1\n7 1 2 3 4\n$EndElements\n".to_vec(),
    ["element 7", "type 3 (Qua4)", "only 3-node triangles"]
);
mesh_refused!(
    mesh_inverted_triangle,
    ascii(&disk_with(|d| d.tris[10].swap(1, 2))),
    ["triangle 30 is inverted", "1 of 54"]
);
mesh_refused!(
    mesh_zero_area_triangle,
    ascii(&disk_with(|d| d.tris[4][2] = d.tris[4][1])),
    ["triangle 24 is degenerate", "area 0"]
);
mesh_refused!(
    mesh_duplicate_node_tag,
    ascii(&disk_with(|d| {
        let c = d.centre;
        let other = d.nodes.iter_mut().find(|n| n.0 == 37).unwrap();
        other.0 = c;
    })),
    ["node 1 appears twice", "unique"]
);
mesh_refused!(
    mesh_coincident_nodes,
    ascii(&disk_with(|d| {
        let p = d.xy(2);
        d.nodes.iter_mut().find(|n| n.0 == 3).unwrap().1 = p;
    })),
    ["nodes 2 and 3 are both at", "merge duplicate nodes"]
);
mesh_refused!(
    mesh_unreferenced_node,
    ascii(&disk_with(|d| d.nodes.push((100, [0.05, 0.0101])))),
    ["node 100 (group \"body\") belongs to no triangle"]
);
mesh_refused!(
    mesh_group_node_outside_the_triangles,
    ascii(&disk_with(|d| {
        // The centre is in the group "centre" but in no triangle any more.
        let c = d.centre;
        d.tris.retain(|t| !t.contains(&c));
        let ring: Vec<u64> = (2..=7).collect();
        for k in 0..4 {
            d.tris.push([ring[0], ring[k + 1], ring[k + 2]]);
        }
    })),
    ["node 1 (group \"centre\") belongs to no triangle"]
);
mesh_refused!(
    mesh_off_centre,
    ascii(&disk_with(|d| d
        .nodes
        .iter_mut()
        .for_each(|n| n.1[0] += 0.01))),
    ["radius", "about the axle (0, 0)", "wheel.radius = 0.1"]
);
mesh_refused!(
    mesh_in_millimetres,
    ascii(&disk_with(|d| d.nodes.iter_mut().for_each(|n| {
        n.1[0] *= 1000.0;
        n.1[1] *= 1000.0;
    }))),
    ["the farthest from the axle", "wheel.radius = 0.1"]
);
mesh_refused!(
    mesh_out_of_round,
    ascii(&disk_with(|d| {
        let t = d.rim[3];
        let n = d.nodes.iter_mut().find(|n| n.0 == t).unwrap();
        n.1 = [n.1[0] * 0.97, n.1[1] * 0.97];
    })),
    ["on the outer boundary", "wheel.radius = 0.1"]
);
mesh_refused!(
    mesh_rim_group_off_the_rim,
    ascii(&disk_with(|d| d.rim[5] = d.centre)),
    ["node 1", "in the group \"rim\""]
);
mesh_refused!(
    mesh_header_claims_more_nodes,
    ascii(&disk()).replace_first(b"$Nodes\n2 37 1 37", b"$Nodes\n2 370000 1 370000"),
    ["the $Nodes header announces 370000 nodes, its blocks hold 37"]
);
mesh_refused!(
    mesh_header_claims_absurd_elements,
    ascii(&disk()).replace_first(
        b"$Elements\n3 73 1 73",
        b"$Elements\n3 18446744073709551615 1 73"
    ),
    ["the $Elements header announces 18446744073709551615 elements, its blocks hold 73"]
);
mesh_refused!(
    mesh_block_claims_more_nodes,
    ascii(&disk()).replace_first(b"\n2 1 0 36\n", b"\n2 1 0 3600000000\n"),
    ["invalid Gmsh MSH 4.1 file"]
);

// Meshes that lie (issue 33): each would run to exit 0 with a wrong answer.

mesh_refused!(
    mesh_every_triangle_twice,
    ascii(&disk_with(|d| {
        let again = d.tris.clone();
        d.tris.extend(again);
    })),
    ["triangles 20 and 74 have the same nodes", "listed twice"]
);
mesh_refused!(
    mesh_overlapping_triangles,
    ascii(&disk_with(|d| {
        // A node inside the first triangle and a triangle on its first edge: the two cover
        // the same area.
        let t = d.tris[0];
        let (a, b, c) = (d.xy(t[0]), d.xy(t[1]), d.xy(t[2]));
        d.nodes.push((
            100,
            [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0],
        ));
        d.tris.push([t[0], t[1], 100]);
    })),
    ["triangles 20 and 74 overlap", "same side of their edge"]
);
mesh_refused!(
    mesh_disk_and_a_separate_annulus,
    ascii(&disk_with(|d| {
        // The annulus: the disk without its centre's triangles; the disk: the centre and six
        // new nodes at 1 cm. Only the centre is pinned.
        let c = d.centre;
        d.tris.retain(|t| !t.contains(&c));
        for k in 0..6u64 {
            let a = std::f64::consts::PI / 3.0 * k as f64;
            d.nodes.push((100 + k, [0.01 * a.cos(), 0.01 * a.sin()]));
        }
        for k in 0..6u64 {
            d.tris.push([c, 100 + k, 100 + (k + 1) % 6]);
        }
    })),
    [
        "in 2 parts",
        "36 nodes (node 2 among them) has no path to the support",
        "the pinned centre, node 1"
    ]
);
mesh_refused!(
    mesh_not_planar,
    {
        let d = disk();
        let p = d.xy(5);
        ascii(&d).replace_first(
            format!("\n{} {} 0\n", p[0], p[1]).as_bytes(),
            format!("\n{} {} 0.004\n", p[0], p[1]).as_bytes(),
        )
    },
    ["node 5 is at z = 4e-3", "plane z = 0"]
);

/// Round-off in z (1e-12 of the radius) is no reason to refuse a mesh.
#[test]
fn mesh_with_round_off_in_z_runs() {
    let d = disk();
    let p = d.xy(5);
    let bytes = ascii(&d).replace_first(
        format!("\n{} {} 0\n", p[0], p[1]).as_bytes(),
        format!("\n{} {} 1e-13\n", p[0], p[1]).as_bytes(),
    );
    let (_dir, p) = held_wheel_on_mesh("round_off_z", &bytes);
    let out = p.with_extension("out");
    let o = cli([
        "run".as_ref(),
        p.as_os_str(),
        "--quiet".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
}

/// Non-contiguous node tags (every tag times 7, plus 3) are fine: the run goes through.
#[test]
fn mesh_with_non_contiguous_tags_runs() {
    let d = disk_with(|d| {
        let f = |t: u64| 7 * t + 3;
        d.nodes.iter_mut().for_each(|n| n.0 = f(n.0));
        d.rim.iter_mut().for_each(|t| *t = f(*t));
        d.centre = f(d.centre);
        d.tris.iter_mut().flatten().for_each(|t| *t = f(*t));
    });
    let (_dir, p) = held_wheel_on_mesh("sparse_tags", &ascii(&d));
    let out = p.with_extension("out");
    let o = cli([
        "run".as_ref(),
        p.as_os_str(),
        "--quiet".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["nodes"], 37);
}

/// A mesh without a "rim" group is fine: the rim is the nodes at the outer radius, the same
/// nodes as the group's, so the run is the same.
#[test]
fn mesh_without_a_rim_group_runs_as_with_it() {
    let with = ascii(&disk());
    let without = with.replace_first(
        b"$PhysicalNames\n3\n0 1 \"centre\"\n1 2 \"rim\"\n",
        b"$PhysicalNames\n2\n0 1 \"centre\"\n",
    );
    let mut forces = Vec::new();
    for (name, bytes) in [("rim_group", with), ("no_rim_group", without)] {
        let (_dir, p) = held_wheel_on_mesh(name, &bytes);
        let out = p.with_extension("out");
        let o = cli([
            "run".as_ref(),
            p.as_os_str(),
            "--quiet".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert_eq!(o.code, 0, "{name}: {}", o.stderr);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        forces.push(s["mean_contact_force"].as_f64().unwrap());
    }
    assert!(forces[0] > 0.0, "{forces:?}");
    assert_eq!(forces[0], forces[1]);
}

trait ReplaceFirst {
    fn replace_first(&self, from: &[u8], to: &[u8]) -> Vec<u8>;
}

impl ReplaceFirst for Vec<u8> {
    fn replace_first(&self, from: &[u8], to: &[u8]) -> Vec<u8> {
        let at = self
            .windows(from.len())
            .position(|w| w == from)
            .unwrap_or_else(|| panic!("{:?} not found", String::from_utf8_lossy(from)));
        let mut v = self[..at].to_vec();
        v.extend_from_slice(to);
        v.extend_from_slice(&self[at + from.len()..]);
        v
    }
}

// ---------------------------------------------------------------- command line

fn cli_refused(args: &[&str], must: &[&str]) -> String {
    let o = cli(args);
    assert_one_line_error(o.code, &o.stderr, must);
    assert!(o.stdout.is_empty(), "{}", o.stdout);
    o.stderr
}

/// `softway COMMAND BAR_SCENARIO EXTRA... --out OUT` (the bar scenario saved as `name`) is
/// refused with one line holding `must`, and nothing is written.
fn refused_on_bar(name: &str, command: &str, extra: &[&str], must: &[&str]) {
    let p = scenario(name, BAR);
    let out = p.with_extension("out");
    let mut args = vec![command, p.to_str().unwrap()];
    args.extend_from_slice(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    cli_refused(&args, must);
    assert_nothing_written(&out);
}

#[test]
fn no_command() {
    cli_refused(&[], &["no command given", "run|sweep"]);
}

#[test]
fn run_without_its_scenario() {
    cli_refused(
        &["run"],
        &["required arguments", "<SCENARIO>", "usage: softway run"],
    );
}

#[test]
fn unknown_command() {
    cli_refused(&["frobnicate"], &["unrecognized subcommand 'frobnicate'"]);
}

#[test]
fn misspelt_flag() {
    cli_refused(&["run", "x.toml", "--outt", "y"], &["'--outt'", "--out"]);
}

#[test]
fn out_is_a_file() {
    let p = scenario("out_file", BAR);
    let f = p.with_file_name("a-file");
    std::fs::write(&f, "keep me").unwrap();
    let args = ["run", p.to_str().unwrap(), "--out", f.to_str().unwrap()];
    cli_refused(&args, &["a-file", "is a file, not a folder"]);
    assert_eq!(std::fs::read_to_string(&f).unwrap(), "keep me");
    cli_refused(&[&args[..], &["--force"]].concat(), &["is a file"]);
}

#[test]
fn out_in_an_unwritable_place() {
    let p = scenario("out_unwritable", BAR);
    for place in ["/proc/softway-out/x", "/dev/null/x"] {
        if place.starts_with("/dev") {
            let o = cli(["run", p.to_str().unwrap(), "--out", place]);
            assert!(
                o.stderr.contains("/dev/null is not a folder"),
                "{}",
                o.stderr
            );
        }
        cli_refused(
            &["run", p.to_str().unwrap(), "--out", place],
            &[place, "cannot create"],
        );
    }
}

#[test]
fn out_a_folder_of_other_files() {
    let p = scenario("out_foreign", BAR);
    let d = p.with_file_name("mine");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("thesis.tex"), "x").unwrap();
    cli_refused(
        &["run", p.to_str().unwrap(), "--out", d.to_str().unwrap()],
        &["mine", "not written by softway", "--force"],
    );
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    // --force replaces it whole.
    let o = cli([
        "run",
        p.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
        "--force",
        "--quiet",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(!d.join("thesis.tex").exists() && d.join("summary.json").exists());
}

/// An output folder of an older run is replaced whole: no stale file survives next to the
/// new ones, and no temporary folder is left beside it.
#[test]
fn older_results_are_never_mixed_with_new_ones() {
    let p = scenario("out_stale", BAR);
    let d = p.with_file_name("out");
    let run = |text: &str| {
        std::fs::write(&p, text).unwrap();
        let o = cli([
            "run",
            p.to_str().unwrap(),
            "--out",
            d.to_str().unwrap(),
            "--quiet",
        ]);
        assert_eq!(o.code, 0, "{}", o.stderr);
    };
    run(BAR);
    std::fs::write(d.join("stale_field.vtu"), "old").unwrap();
    run(&BAR.replace("speed = 1.0", "speed = 2.0"));
    assert!(!d.join("stale_field.vtu").exists());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["exact"]["rebound_velocity"], 2.0);
    // A failed run leaves the older results as they were.
    std::fs::write(&p, BAR.replace("speed = 1.0", "speed = -2.0")).unwrap();
    let o = cli([
        "run",
        p.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
        "--quiet",
    ]);
    assert_ne!(o.code, 0);
    assert!(d.join("summary.json").exists() && d.join("history.csv").exists());
    let names: Vec<String> = std::fs::read_dir(p.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("softway-")), "{names:?}");
}

/// `softway run SCENARIO --out OUT --force --quiet` in the folder `cwd` with `HOME` set to
/// `home`.
fn run_in(cwd: &Path, home: &Path, scenario: &Path, out: &str) -> common::Outcome {
    let o = common::softway()
        .current_dir(cwd)
        .env("HOME", home)
        .arg("run")
        .arg(scenario)
        .args(["--out", out, "--force", "--quiet"])
        .output()
        .unwrap();
    common::Outcome {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
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

/// `--out` never replaces the current folder, the home folder, the scenario's folder or a
/// parent of one, `--force` or not, however the path is written (absolute, relative, with
/// `..`, through a link): exit 2, one line, nothing written or removed.
#[test]
fn out_never_replaces_the_current_home_or_scenario_folder() {
    let dir = fresh_dir("cli", "out_protected");
    let study = dir.join("study");
    let (home, elsewhere) = (dir.join("home"), dir.join("elsewhere"));
    for d in [&study, &home, &elsewhere] {
        std::fs::create_dir_all(d).unwrap();
    }
    let sc = study.join("s.toml");
    std::fs::write(&sc, BAR).unwrap();
    std::fs::write(study.join("thesis.tex"), "keep me").unwrap();
    std::os::unix::fs::symlink(&study, dir.join("link")).unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let cases: [(&Path, String, &str); 10] = [
        (&study, s(&study), "the current folder"),
        (&study, ".".into(), "not a folder name"),
        (&study, "../study".into(), "the current folder"),
        (&study, "./../study/".into(), "the current folder"),
        // Through a folder that does not exist yet (made as a parent, then `..`).
        (&study, "../fresh/../study".into(), "the current folder"),
        (&study, s(&dir.join("link")), "the current folder"),
        (&study, s(&dir), "the current folder"),
        (&elsewhere, s(&study), "the scenario's folder"),
        (&elsewhere, "../link".into(), "the scenario's folder"),
        (&elsewhere, s(&home), "the home folder"),
    ];
    for (cwd, out, must) in cases {
        let o = run_in(cwd, &home, &sc, &out);
        assert_one_line_error(o.code, &o.stderr, &[&format!("--out {out}"), must]);
        assert!(o.stdout.is_empty(), "{}", o.stdout);
    }
    assert_eq!(names(&study), ["s.toml", "thesis.tex"]);
    assert_eq!(names(&dir), ["elsewhere", "home", "link", "study"]);
    assert!(names(&home).is_empty() && names(&elsewhere).is_empty());
    // A new folder beside the scenario is fine.
    let o = run_in(&study, &home, &sc, "results");
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(names(&study), ["results", "s.toml", "thesis.tex"]);
}

/// `--out LINK`, a link to an output folder: the folder it points to is replaced (no stale
/// file left there), the link stays a link; a link to nothing is refused.
#[test]
fn out_through_a_link_replaces_the_folder_it_points_to() {
    let p = scenario("out_link", BAR);
    let dir = p.parent().unwrap();
    let results = dir.join("results");
    let run = |out: &Path| {
        cli([
            "run".as_ref(),
            p.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
        ])
    };
    assert_eq!(run(&results).code, 0);
    std::fs::write(results.join("stale.csv"), "old").unwrap();
    let link = dir.join("latest");
    std::os::unix::fs::symlink("results", &link).unwrap();
    let o = run(&link);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(results.join("summary.json").exists() && !results.join("stale.csv").exists());
    assert_eq!(names(dir), ["latest", "out_link.toml", "results"]);
    let dangling = dir.join("dangling");
    std::os::unix::fs::symlink("nowhere", &dangling).unwrap();
    let o = run(&dangling);
    assert_one_line_error(o.code, &o.stderr, &["dangling", "symbolic link to nowhere"]);
    assert!(!dir.join("nowhere").exists());
    assert_eq!(
        names(dir),
        ["dangling", "latest", "out_link.toml", "results"]
    );
}

#[test]
fn sweep_set_without_values() {
    refused_on_bar(
        "sweep_noeq",
        "sweep",
        &["--set", "bar.speed"],
        &["--set bar.speed", "KEY=V1,V2"],
    );
}

#[test]
fn sweep_with_zero_jobs() {
    refused_on_bar(
        "sweep_jobs0",
        "sweep",
        &["--set", "bar.speed=1,2", "--jobs", "0"],
        &["--jobs 0", "at least one"],
    );
}

#[test]
fn run_with_zero_threads() {
    refused_on_bar(
        "run_threads0",
        "run",
        &["--threads", "0"],
        &["--threads 0", "at least one"],
    );
}

#[test]
fn sweep_bad_value() {
    refused_on_bar(
        "sweep_badvalue",
        "sweep",
        &["--set", "bar.speed=1,-2"],
        &[
            "sweep_badvalue.toml",
            "bar.speed = -2",
            "`bar.speed` = -2",
            "> 0",
        ],
    );
}

#[test]
fn sweep_value_given_twice() {
    refused_on_bar(
        "sweep_twice",
        "sweep",
        &["--set", "bar.speed=1,2,1"],
        &["bar.speed = 1", "given twice"],
    );
}

/// A value holding path separators cannot lead a point's folder out of the sweep's.
#[test]
fn sweep_value_with_slashes_stays_inside_the_sweep_folder() {
    let p = scenario("sweep_slash", BAR);
    let out = p.with_extension("out");
    let o = cli([
        "sweep",
        p.to_str().unwrap(),
        "--set",
        "description=a/../../../escaped,b",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(out
        .join("description=a_.._.._.._escaped")
        .join("summary.json")
        .exists());
    let parent = p.parent().unwrap();
    assert!(!parent.join("escaped").exists() && !parent.parent().unwrap().join("escaped").exists());
}

#[test]
fn converge_with_two_rungs() {
    refused_on_bar(
        "converge_two",
        "converge",
        &["--set", "bar.elements=8,16"],
        &["bar.elements", "three"],
    );
}

#[test]
fn modes_of_a_bar() {
    refused_on_bar(
        "modes_bar",
        "modes",
        &[],
        &["modes_bar.toml", "needs a wheel scenario"],
    );
}

#[test]
fn stability_gamma_out_of_range() {
    cli_refused(&["stability", "--gamma", "2"], &["--gamma 2", "[0, 1]"]);
    cli_refused(
        &["stability", "--spin-h", "0.5"],
        &["--spin-h 0.5", "(0, 0.1]"],
    );
}

#[test]
fn a_missing_scenario_path_is_named() {
    let dir = fresh_dir("cli", "missing_path");
    let p: PathBuf = dir.join("nothing.toml");
    let out = dir.join("out");
    let o = cli(["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_one_line_error(o.code, &o.stderr, &["nothing.toml", "No such file"]);
    assert_nothing_written(&out);
    assert!(Path::new(&dir).exists());
}

// ---------------------------------------------------------------- issue 33: messages

/// The shipped converged wheel (`scenarios/wheel.toml`: 288 rim nodes, a hub of 1 cm).
fn hub_wheel_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml")).unwrap()
}

/// A hub that leaves the graded disk no room (its limit is `R (1 - 4 pi / N)` = 95.6 mm for
/// 288 rim nodes) is the scenario's key, not the mesh generator's parameter.
#[test]
fn wheel_hub_without_room_names_the_key() {
    let (c, e) = run_err(
        "wheel_hub_without_room",
        &hub_wheel_text().replace("hub_radius = 0.01 ", "hub_radius = 0.0999 "),
    );
    assert_one_line_error(
        c,
        &e,
        &[
            "wheel_hub_without_room.toml",
            "`wheel.hub_radius` = 0.0999",
            "wheel.rim_nodes",
            "0.095637",
        ],
    );
    assert!(!e.contains("mesh parameter"), "{e}");
}

/// A wheel's step too long for the rim's passage names the key the step came from (the
/// run's own `runs[0].h`, or `time.h`) and `rolling.omega`, never keys the wheel has not
/// (`time.t_end`).
#[test]
fn wheel_step_too_long_names_the_key_it_came_from() {
    let from_runs = wheel_text().replace("h = 2e-6", "") + "\n[[runs]]\nh = 0.05\n";
    let (c, e) = run_err("wheel_step_from_runs", &from_runs);
    assert_one_line_error(
        c,
        &e,
        &[
            "wheel_step_from_runs.toml",
            "`runs[0].h` = 5e-2",
            "rolling.omega",
            "rim node",
        ],
    );
    assert!(!e.contains("time.h") && !e.contains("t_end"), "{e}");
    let (c, e) = run_err(
        "wheel_step_from_time",
        &wheel_text().replace("h = 2e-6", "h = 2e-4"),
    );
    assert_one_line_error(
        c,
        &e,
        &[
            "wheel_step_from_time.toml",
            "`time.h` = 2e-4",
            "rolling.omega",
        ],
    );
    assert!(!e.contains("runs[") && !e.contains("t_end"), "{e}");
}

/// A name with a NUL byte (no file may have one) is refused with the byte escaped: the
/// message holds `\0`, never the raw byte.
#[test]
fn a_nul_byte_in_the_name_is_refused_and_shown_escaped() {
    let (c, e) = run_err(
        "name_nul",
        &BAR.replace("kind =", "name = \"a\\u0000b\"\nkind ="),
    );
    assert_one_line_error(c, &e, &["name_nul.toml", "`name` = \"a\\0b\"", "NUL"]);
    assert!(!e.contains('\0'), "{e:?}");
}

/// A name longer than a folder's name may be (255 bytes) is refused as the key `name`.
#[test]
fn a_name_longer_than_255_bytes_is_refused() {
    let long = "n".repeat(256);
    let (c, e) = run_err(
        "name_256",
        &BAR.replace("kind =", &format!("name = \"{long}\"\nkind =")),
    );
    assert_one_line_error(c, &e, &["name_256.toml", "`name`", "255 bytes", "256"]);
}

/// A sweep value whose point folder (`<key>=<value>`) would be longer than a folder's name
/// may be is refused before any run, naming the key, with no temporary folder left (before:
/// the run failed at the end naming the deleted staging folder).
#[test]
fn a_sweep_value_too_long_for_a_folder_name_is_refused_before_any_run() {
    let p = scenario("sweep_long_value", BAR);
    let out = p.with_extension("out");
    let long = "x".repeat(250);
    let o = cli([
        "sweep".as_ref(),
        p.as_os_str(),
        "--set".as_ref(),
        format!("description=a,{long}").as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_one_line_error(
        o.code,
        &o.stderr,
        &[
            "sweep_long_value.toml",
            "description",
            "folder",
            "255",
            "sweep shorter values",
        ],
    );
    assert!(!o.stderr.contains("softway-tmp"), "{}", o.stderr);
    assert_nothing_written(&out);
}
