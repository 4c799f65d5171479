#!/usr/bin/env python3
"""A hostile user's probe of the newer commands (issue 47): `grow` on the rigid base
(`polygon.toml`, `polygon-plastic.toml`) and on the track (`corrugation.toml`),
`receptance`, the track's `run`, `shakedown`, `sweep --shard` and `gather`, `converge`,
the block (`wheel-on-block.toml`) and `--set`.

Each case runs the release binary (`SOFTWAY_BIN`, else `target/release/softway`) with a
time limit and is classified:

- refusal: exit 2, one error line (warnings aside) naming the key the case expects, and no
  output folder made by a refused run;
- result: exit 0, every number of the folder's JSON and CSV files finite, and the case's
  own physical check (a growth study's rates finite, a track's mean force near its load,
  receptance magnitudes positive, ...);
- defect: a panic or a signal (exit 101, 134, negative), a hang (the time limit), exit 0
  with NaN, inf or an absurd figure, a refusal naming another key or on several lines, a
  refused run that wrote its folder, the user's files lost.

The cases are not those of issue 47's catalogue nor of `tests/bad_input.rs`,
`tests/hostile_track.rs`, `tests/growth_input.rs`: other values, other keys, other ways to
damage a checkpoint or a shard. Runs are kept short with `--set` (96 rim nodes, one pass,
30 bays, a tenth of a turn).

    python3 validation/hostile_probe.py [--jobs 2] [--only SUBSTRING] [--verbose]

prints one line per defect and the counts; exit 1 if any case is a defect.
"""

import argparse
import concurrent.futures as cf
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(os.environ.get("SOFTWAY_BIN", ROOT / "target/release/softway")).resolve()
SC = ROOT / "scenarios"
LIMIT = 120.0  # s: a case still running then is a hang

# Short runs of each command.
POLY = ["--passes", "1", "--threads", "1", "--set", "wheel.rim_nodes=96",
        "--set", "growth.reference=false", "--set", "rolling.settle_time=5e-4"]
TRACKSET = ["--set", "track.bays=30", "--set", "track.end_bays=8",
            "--set", "vehicle.travel_bays=2", "--set", "vehicle.wheel_rim_nodes=360"]
CORR = ["--passes", "1", "--threads", "1", "--set", "growth.reference=false"] + TRACKSET
BLOCK = ["--quiet", "--threads", "1", "--set", "wheel.rim_nodes=96", "--set", "rolling.turns=0.1"]


def sets(*kv):
    out = []
    for x in kv:
        out += ["--set", x]
    return out


class Case:
    def __init__(self, name, args, expect="either", key=None, setup=None, check=None,
                 custom=None, out=True, timeout=LIMIT):
        self.name = name
        self.args = args          # strings; "{d}" is the case's folder, "{sc}" the scenarios
        self.expect = expect      # "refuse", "ok" or "either"
        self.key = key            # a string or a tuple of strings the refusal must name
        self.setup = setup        # f(d): prepares files in the case's folder
        self.check = check        # f(d, out) -> None or the defect, for exit 0
        self.custom = custom      # f(d) -> (class, message): the case drives itself
        self.out = out            # append --out {d}/out
        self.timeout = timeout


# ----------------------------------------------------------------------------- helpers

NUM_BAD = re.compile(r"(?<![A-Za-z_])(nan|-?inf|-?infinity)(?![A-Za-z_])", re.I)


def nonfinite_in(folder):
    """The first non-finite number in the folder's JSON and CSV files, or None."""
    if not folder.is_dir():
        return None
    for p in sorted(folder.rglob("*")):
        if p.suffix == ".json" and p.name != "checkpoint.json":
            try:
                v = json.loads(p.read_text())
            except Exception as e:  # noqa: BLE001
                return f"{p.name}: not JSON ({e})"
            bad = _walk_json(v, p.name)
            if bad:
                return bad
        elif p.suffix == ".csv":
            for i, line in enumerate(p.read_text(errors="replace").splitlines()):
                if i == 0:
                    continue
                m = NUM_BAD.search(line)
                if m:
                    return f"{p.relative_to(folder)} line {i + 1}: {m.group(0)}"
    return None


def _walk_json(v, at):
    if isinstance(v, float) and not math.isfinite(v):
        return f"{at} = {v}"
    if isinstance(v, dict):
        for k, x in v.items():
            b = _walk_json(x, f"{at}.{k}")
            if b:
                return b
    if isinstance(v, list):
        for i, x in enumerate(v):
            b = _walk_json(x, f"{at}[{i}]")
            if b:
                return b
    return None


def summary(out):
    return json.loads((out / "summary.json").read_text())


def edited(src, changes, name="s.toml", drop_tables=()):
    """`src`'s text with `changes` {"table.key": "toml value" or None (removed)} applied
    line by line; returns a setup function writing it as `name`."""

    def setup(d):
        lines = Path(src).read_text().splitlines()
        out, table, done = [], "", set()
        skip = False
        for ln in lines:
            m = re.match(r"^\s*\[([A-Za-z_.]+)\]", ln)
            if m:
                # keys of the table just left that were not there: added at its end
                for k, v in changes.items():
                    t, key = k.rsplit(".", 1) if "." in k else ("", k)
                    if t == table and k not in done and v is not None:
                        out.append(f"{key} = {v}")
                        done.add(k)
                table = m.group(1)
                skip = table in drop_tables
                if skip:
                    continue
            if skip:
                continue
            km = re.match(r"^\s*([A-Za-z_0-9]+)\s*=", ln)
            if km:
                full = f"{table}.{km.group(1)}" if table else km.group(1)
                if full in changes:
                    done.add(full)
                    if changes[full] is not None:
                        out.append(f"{km.group(1)} = {changes[full]}")
                    continue
            out.append(ln)
        for k, v in changes.items():
            t, key = k.rsplit(".", 1) if "." in k else ("", k)
            if k not in done and v is not None:
                if t == table:
                    out.append(f"{key} = {v}")
                else:
                    out.append(f"[{t}]\n{key} = {v}")
        (d / name).write_text("\n".join(out) + "\n")

    return setup


def CSV(name):
    """The random roughness's keys replaced by a CSV file's."""
    return sets("growth.roughness=\"csv\"", "growth.level=", "growth.min_wavelength=",
                "growth.max_wavelength=", "growth.seed=", f"growth.file=\"{{d}}/{name}\"")


def rate_check(d, out):
    """A growth study: passes done, profile RMS finite and positive, band rates finite."""
    s = summary(out)
    for k in ("rms_initial_m", "rms_final_m"):
        x = s.get(k)
        if not isinstance(x, (int, float)) or not math.isfinite(x) or x < 0:
            return f"summary {k} = {x}"
    if s["rms_final_m"] > 1e3 * max(s["rms_initial_m"], 1e-12) + 1e-3:
        return f"rms grew from {s['rms_initial_m']} to {s['rms_final_m']} m"
    for b in s.get("bands", []):
        r = b.get("rate_db_per_1e5")
        if r is not None and (not math.isfinite(r) or abs(r) > 1e5):
            return f"band rate {r} dB per 1e5 passes"
    if s.get("interrupted"):
        return "summary says interrupted"
    return None


def track_check(d, out):
    """A track run: the mean contact force within 20 % of the axle load."""
    s = summary(out)
    load = s.get("axle_load_n") or s.get("axle_load")
    mean = s.get("mean_contact_force_n") or s.get("mean_contact_force")
    if load and mean is not None and abs(mean - load) > 0.2 * abs(load):
        return f"mean contact force {mean} N against a load of {load} N"
    return None


def receptance_check(d, out):
    rows = (out / "receptance.csv").read_text().splitlines()
    head = rows[0].split(",")
    mags = [i for i, h in enumerate(head) if "mag" in h or "receptance" in h and "phase" not in h]
    if len(rows) < 3:
        return "receptance.csv has no rows"
    for r in rows[1:]:
        c = r.split(",")
        for i in mags:
            x = float(c[i])
            if not (math.isfinite(x) and x > 0):
                return f"receptance magnitude {x} ({head[i]})"
    return None


def block_check(d, out):
    s = summary(out)
    for k, v in s.items():
        if "force" in k and isinstance(v, (int, float)) and v < -1e-6 * 1e6:
            return f"{k} = {v} pulls"
    return None


def shakedown_check(d, out):
    return None


# ----------------------------------------------------------------------------- runners

def run(args, d, timeout, stdin=None):
    start = time.time()
    try:
        p = subprocess.run([str(BIN)] + args, cwd=d, capture_output=True, text=True,
                           timeout=timeout, stdin=stdin if stdin is not None else subprocess.DEVNULL)
        return p.returncode, p.stdout, p.stderr, time.time() - start
    except subprocess.TimeoutExpired:
        return None, "", "", time.time() - start


def judge_refusal(case, err, out, existed):
    lines = [ln for ln in err.splitlines()
             if ln.strip() and not ln.startswith("softway: warning: ")]
    if len(lines) != 1 or not lines[0].startswith("softway: error: "):
        return "defect", f"exit 2 on {len(lines)} lines: {err.strip()[:400]}"
    keys = case.key if isinstance(case.key, tuple) else ((case.key,) if case.key else ())
    missing = [k for k in keys if k not in lines[0]]
    if missing:
        return "defect", f"refusal does not name {missing}: {lines[0][:400]}"
    # a study stopped by its wear keys after a pass ran keeps its folder (and checkpoint)
    stopped = re.search(r": pass \d+: ", lines[0]) is not None
    if out is not None and not existed and out.exists() and not stopped:
        return "defect", f"refused but wrote {out.name}/: {lines[0][:300]}"
    if case.expect == "ok":
        return "defect", f"a valid input refused: {lines[0][:300]}"
    return "refusal", lines[0]


def run_case(case, base):
    d = base / re.sub(r"[^A-Za-z0-9_.-]+", "_", case.name)
    d.mkdir(parents=True)
    if case.setup:
        case.setup(d)
    if case.custom:
        try:
            return case.custom(d)
        except Exception as e:  # noqa: BLE001
            return "defect", f"probe error: {e!r}"
    args = [a.replace("{d}", str(d)).replace("{sc}", str(SC)) for a in case.args]
    out = d / "out"
    if case.out:
        args += ["--out", str(out)]
    existed = out.exists()
    code, _, err, took = run(args, d, case.timeout)
    return classify(case, code, err, out if case.out else None, existed, d, took)


def classify(case, code, err, out, existed, d, took):
    if code is None:
        return "defect", f"hang: no end after {case.timeout:.0f} s"
    if "panicked" in err or code in (101, 134) or code < 0:
        return "defect", f"crash: exit {code}: {err.strip()[-400:]}"
    if code == 2:
        return judge_refusal(case, err, out, existed)
    if code == 0:
        if case.expect == "refuse":
            return "defect", f"exit 0 where a refusal was due ({err.strip()[-200:]})"
        if out is not None:
            bad = nonfinite_in(out)
            if bad:
                return "defect", f"exit 0 with {bad}"
        if case.check:
            try:
                bad = case.check(d, out)
            except Exception as e:  # noqa: BLE001
                bad = f"check failed: {e!r}"
            if bad:
                return "defect", f"exit 0 with {bad}"
        return "result", f"{took:.1f} s"
    return "defect", f"exit {code}: {err.strip()[-300:]}"


# ----------------------------------------------------------------------------- the cases

def grow_cases():
    P = str(SC / "polygon.toml")
    PP = str(SC / "polygon-plastic.toml")
    C = str(SC / "corrugation.toml")
    cs = []

    def g(name, src, base, extra, expect="either", key=None, **kw):
        cs.append(Case(name, ["grow", src] + base + extra, expect, key,
                       check=kw.pop("check", rate_check), **kw))

    # the rigid base, elastic
    for v, exp in [("0", "refuse"), ("-3", "refuse"), ("2.5", "refuse"), ("\"ten\"", "refuse"),
                   ("true", "refuse"), ("1e9", "refuse")]:
        g(f"poly growth.passes={v}", P, POLY, sets(f"growth.passes={v}"), expect="either" if v == "1e9" else exp, key="growth.passes")
    for v in ["0", "-100", "nan", "inf", "-inf", "1e-300", "\"100\""]:
        g(f"poly passes_per_pass={v}", P, POLY, sets(f"growth.passes_per_pass={v}"),
          expect="either" if v == "1e-300" else "refuse", key="growth.passes_per_pass")
    for v in ["-5e-3", "nan", "inf", "0"]:
        g(f"poly smoothing={v}", P, POLY, sets(f"growth.smoothing={v}"),
          expect="either" if v == "0" else "refuse", key="growth.smoothing")
    for v in ["0", "-1e-2", "nan", "inf", "1e-12"]:
        g(f"poly cutoff={v}", P, POLY, sets(f"growth.cutoff={v}"),
          expect="refuse" if v in ("nan", "inf", "-1e-2") else "either", key="growth.cutoff")
    for v in ["nan", "inf", "-inf", "400", "-400", "1e6"]:
        g(f"poly level={v}", P, POLY, sets(f"growth.level={v}"),
          expect="refuse" if v in ("nan", "inf", "-inf", "400", "1e6") else "either",
          key="growth.level")
    g("poly min>max wavelength", P, POLY, sets("growth.min_wavelength=0.5", "growth.max_wavelength=0.01"),
      "refuse", "wavelength")
    g("poly min_wavelength=0", P, POLY, sets("growth.min_wavelength=0"), "refuse", "growth.min_wavelength")
    g("poly min_wavelength=-5e-3", P, POLY, sets("growth.min_wavelength=-5e-3"), "refuse", "growth.min_wavelength")
    g("poly max_wavelength=nan", P, POLY, sets("growth.max_wavelength=nan"), "refuse", "growth.max_wavelength")
    g("poly max_wavelength=1e300", P, POLY, sets("growth.max_wavelength=1e300"), "either", "growth.max_wavelength")
    g("poly seed=-1", P, POLY, sets("growth.seed=-1"), "refuse", "growth.seed")
    g("poly seed=1.5", P, POLY, sets("growth.seed=1.5"), "refuse", "growth.seed")
    g("poly seed=\"a\"", P, POLY, sets("growth.seed=\"a\""), "refuse", "growth.seed")
    g("poly roughness=bogus", P, POLY, sets("growth.roughness=\"bogus\""), "refuse", "growth.roughness")
    g("poly roughness=42", P, POLY, sets("growth.roughness=42"), "refuse", "growth.roughness")
    g("poly roughness=[]", P, POLY, sets("growth.roughness=[]"), "refuse", "growth.roughness")
    harm = sets("growth.roughness=\"harmonic\"", "growth.level=", "growth.min_wavelength=",
                "growth.max_wavelength=", "growth.seed=")
    g("poly harmonic no amplitude", P, POLY, harm + sets("growth.wavelength=0.0785"), "refuse", "growth.amplitude")
    g("poly harmonic amplitude=nan", P, POLY, harm + sets("growth.wavelength=0.0785", "growth.amplitude=nan"),
      "refuse", "growth.amplitude")
    g("poly harmonic amplitude=-1e-6", P, POLY, harm + sets("growth.wavelength=0.0785", "growth.amplitude=-1e-6"),
      "either", "growth.amplitude")
    g("poly harmonic amplitude=1 m", P, POLY, harm + sets("growth.wavelength=0.0785", "growth.amplitude=1.0"),
      "refuse", "growth.amplitude")
    g("poly harmonic wavelength=0", P, POLY, harm + sets("growth.wavelength=0", "growth.amplitude=1e-6"),
      "refuse", "growth.wavelength")
    g("poly harmonic wavelength=-0.1", P, POLY, harm + sets("growth.wavelength=-0.1", "growth.amplitude=1e-6"),
      "refuse", "growth.wavelength")
    g("poly harmonic wavelength=1e3", P, POLY, harm + sets("growth.wavelength=1e3", "growth.amplitude=1e-6"),
      "refuse", "growth.wavelength")
    g("poly harmonic with level left", P, POLY,
      sets("growth.roughness=\"harmonic\"", "growth.wavelength=0.0785", "growth.amplitude=1e-6"),
      "refuse", "growth.")
    g("poly growth.bogus key", P, POLY, sets("growth.bogus=1"), "refuse", "growth.bogus")
    g("poly wear.law=bogus", P, POLY, sets("wear.law=\"bogus\""), "refuse", "wear.law")
    g("poly wear.k_mass=-5e-9", P, POLY, sets("wear.k_mass=-5e-9"), "refuse", "wear.k_mass")
    g("poly wear.k_mass=0", P, POLY, sets("wear.k_mass=0"), "either", "wear.k_mass")
    g("poly wear.k_mass=nan", P, POLY, sets("wear.k_mass=nan"), "refuse", "wear.k_mass")
    g("poly wear.k_mass missing (the default)", P, POLY, sets("wear.k_mass="), "ok", None)
    g("poly wear archard no hardness", P, POLY, sets("wear.law=\"archard\"", "wear.k_mass=", "wear.k=1e-4"),
      "refuse", "wear.hardness")
    g("poly wear archard hardness=0", P, POLY,
      sets("wear.law=\"archard\"", "wear.k_mass=", "wear.k=1e-4", "wear.hardness=0", "wear.density=7850"),
      "refuse", "wear.hardness")
    g("poly no [wear]", P, POLY, [], "refuse", "wear", setup=edited(P, {}, drop_tables=("wear",)))
    cs[-1].args = ["grow", "{d}/s.toml"] + POLY
    g("poly no [growth]", P, POLY, [], "either", None, setup=edited(P, {}, drop_tables=("growth",)))
    cs[-1].args = ["grow", "{d}/s.toml"] + POLY
    g("grow on wheel.toml (no growth)", str(SC / "wheel.toml"), ["--passes", "1"], [], "refuse", "growth")
    g("grow on bar-impact", str(SC / "bar-impact.toml"), ["--passes", "1"], [], "refuse", None)
    g("grow on sdof", str(SC / "sdof.toml"), ["--passes", "1"], [], "refuse", None)
    g("poly creepage=0", P, POLY, sets("rolling.creepage=0"), "either", "rolling.creepage")
    g("poly creepage=-0.01 (braking)", P, POLY, sets("rolling.creepage=-0.01"), "either", "rolling.creepage")
    g("poly creepage=5", P, POLY, sets("rolling.creepage=5"), "refuse", "rolling.creepage")
    g("poly friction=0", P, POLY, sets("contact.friction=0"), "either", "contact.friction")
    g("poly friction=-0.3", P, POLY, sets("contact.friction=-0.3"), "refuse", "contact.friction")
    g("poly omega=0", P, POLY, sets("rolling.omega=0"), "refuse", "rolling.omega")
    g("poly omega=-300", P, POLY, sets("rolling.omega=-300"), "either", "rolling.omega")
    g("poly flattening=0", P, POLY, sets("rolling.flattening=0"), "refuse", "rolling.flattening")
    g("poly flattening=0.05", P, POLY, sets("rolling.flattening=0.05"), "either", None)
    g("poly turns=2", P, POLY, sets("rolling.turns=2"), "either", "rolling.turns")
    g("poly --passes 0", P, ["--passes", "0"] + POLY[2:], [], "refuse", "passes")
    g("poly --passes -1", P, ["--passes", "-1"] + POLY[2:], [], "refuse", "-1")
    g("poly --passes 1e3x", P, ["--passes", "1e3x"] + POLY[2:], [], "refuse", "passes")
    g("poly --threads 0", P, POLY[:2] + ["--threads", "0"] + POLY[4:], [], "either", "threads")
    g("poly --threads 100000", P, POLY[:2] + ["--threads", "100000"] + POLY[4:], [], "either", "threads")
    g("poly rim_nodes=7", P, POLY, sets("wheel.rim_nodes=7"), "refuse", "wheel.rim_nodes")
    g("poly rim_nodes=97 (odd)", P, POLY, sets("wheel.rim_nodes=97"), "either", "wheel.rim_nodes")
    g("poly dx csv missing", P, POLY, CSV("none.csv"), "refuse", "none.csv")
    g("poly csv empty", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").write_text(""))
    g("poly csv one column", P, POLY, CSV("r.csv"), "either", "r.csv",
      setup=lambda d: (d / "r.csv").write_text("\n".join(f"{i * 1e-3}" for i in range(200)) + "\n"))
    g("poly csv with nan", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").write_text(
          "x,z\n" + "\n".join(f"{i * 6.5e-3},{'nan' if i == 5 else 1e-6}" for i in range(97)) + "\n"))
    g("poly csv huge z", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").write_text(
          "x,z\n" + "\n".join(f"{i * 6.5e-3},{1e3 * math.sin(i)}" for i in range(97)) + "\n"))
    g("poly csv x decreasing", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").write_text(
          "x,z\n" + "\n".join(f"{(96 - i) * 6.5e-3},1e-6" for i in range(97)) + "\n"))
    g("poly csv is a folder", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").mkdir())
    g("poly csv text junk", P, POLY, CSV("r.csv"), "refuse", "r.csv",
      setup=lambda d: (d / "r.csv").write_bytes(b"\x00\xff\xfe garbage\n" * 10))
    g("poly csv two rows", P, POLY, CSV("r.csv"), "either", "r.csv",
      setup=lambda d: (d / "r.csv").write_text("0,1e-6\n0.001,2e-6\n"))

    # the rigid base, plastic
    for k, v, exp in [("material.yield_stress", "0", "refuse"), ("material.yield_stress", "-1e9", "refuse"),
                      ("material.yield_stress", "nan", "refuse"), ("material.yield_stress", "1e300", "either"),
                      ("material.af_c", "-1e9", "refuse"), ("material.af_gamma", "-1", "refuse"),
                      ("material.af_gamma", "nan", "refuse"), ("material.plastic_tolerance", "0", "refuse"),
                      ("material.plastic_tolerance", "2", "refuse"), ("material.hardening", "\"bogus\"", "refuse"),
                      ("material.model", "\"j3\"", "refuse"), ("material.plane", "\"stress\"", "either")]:
        key = "wheel.plane" if k == "material.plane" else k
        extra = sets(f"wheel.plane={v}") if k == "material.plane" else sets(f"{k}={v}")
        g(f"plastic {k}={v}", PP, POLY, extra, exp, key)

    # the track
    for k, v, exp in [("growth.dx", "0", "refuse"), ("growth.dx", "-1e-3", "refuse"),
                      ("growth.dx", "nan", "refuse"), ("growth.dx", "10.0", "refuse"),
                      ("growth.dx", "1e-9", "refuse"),
                      ("growth.creepage", "nan", "refuse"), ("growth.creepage", "-0.005", "either"),
                      ("growth.creepage", "5.0", "refuse"), ("growth.traction_coefficient", "-0.3", "refuse"),
                      ("growth.traction_coefficient", "2.0", "either"),
                      ("growth.traction_coefficient", "nan", "refuse"), ("growth.patch", "\"bogus\"", "refuse"),
                      ("growth.patch", "\"nodes\"", "either"), ("wear.k", "-5e-4", "refuse"),
                      ("wear.k", "inf", "refuse"), ("wear.hardness", "0", "refuse"),
                      ("wear.density", "-7850", "refuse"), ("wear.density", "nan", "refuse"),
                      ("growth.passes_per_pass", "-2e3", "refuse"), ("growth.smoothing", "-1", "refuse"),
                      ("growth.cutoff", "nan", "refuse"), ("growth.level", "inf", "refuse"),
                      ("growth.min_wavelength", "1e-6", "refuse"), ("growth.max_wavelength", "100.0", "either"),
                      ("vehicle.travel_bays", "0", "refuse"), ("vehicle.settle_bays", "0", "refuse"),
                      ("vehicle.speed_km_h", "-100", "refuse"), ("vehicle.axle_load", "0", "either"),
                      ("wear.law", "\"frictional_power\"", "refuse"), ("growth.reference", "\"yes\"", "refuse")]:
        g(f"corr {k}={v}", C, CORR, sets(f"{k}={v}"), exp, "wear." if k == "wear.law" else k,
          check=rate_check, timeout=LIMIT)
    return cs


def checkpoint_cases():
    """Edited checkpoints and resumes, each on a fresh two-pass study of its own."""
    P = str(SC / "polygon.toml")
    PP = str(SC / "polygon-plastic.toml")
    C = str(SC / "corrugation.toml")
    cs = []

    def study(d, src, base, passes="1"):
        b = list(base)
        b[b.index("--passes") + 1] = passes
        code, _, err, _ = run(["grow", src] + b + ["--out", str(d / "out")], d, LIMIT)
        if code != 0:
            raise RuntimeError(f"the first study failed: {code} {err[-300:]}")

    def resume_case(name, edit, key, src=P, base=POLY, expect="refuse", extra=()):
        def custom(d):
            study(d, src, base)
            ck = d / "out" / "checkpoint.json"
            copy = (d / "out" / "scenario.toml").read_text()
            if edit:
                edit(ck, d)
            b = list(base)
            b[b.index("--passes") + 1] = "2"
            args = ["grow", src] + b + list(extra) + ["--resume", "--out", str(d / "out")]
            code, _, err, took = run(args, d, LIMIT)
            c = Case(name, [], expect, key, check=rate_check)
            kind, msg = classify(c, code, err, d / "out", True, d, took)
            if code == 2 and (d / "out" / "scenario.toml").read_text() != copy:
                return "defect", "refused resume overwrote scenario.toml"
            if code == 2 and not (d / "out" / "checkpoint.json").exists() and edit is not None \
                    and "missing" not in name:
                return "defect", "refused resume lost checkpoint.json"
            return kind, msg
        cs.append(Case(name, [], custom=custom))

    def jedit(f):
        def e(ck, d):
            s = json.loads(ck.read_text())
            f(s)
            ck.write_text(json.dumps(s))
        return e

    resume_case("ckpt truncated JSON", lambda ck, d: ck.write_text(ck.read_text()[: len(ck.read_text()) // 2]),
                "checkpoint.json")
    resume_case("ckpt empty file", lambda ck, d: ck.write_text(""), "checkpoint.json")
    resume_case("ckpt is []", lambda ck, d: ck.write_text("[]"), "checkpoint.json")
    resume_case("ckpt is a folder", lambda ck, d: (ck.unlink(), ck.mkdir()), "checkpoint.json")
    resume_case("ckpt missing", lambda ck, d: ck.unlink(), "checkpoint.json")
    resume_case("ckpt symlink to /dev/zero", lambda ck, d: (ck.unlink(), ck.symlink_to("/dev/zero")),
                "checkpoint.json")
    resume_case("ckpt huge file", lambda ck, d: ck.write_text(" " * 300_000_000 + "{}"), "checkpoint.json")
    resume_case("ckpt passes as object", jedit(lambda s: s.__setitem__("passes", {})), "passes")
    resume_case("ckpt passes dropped", jedit(lambda s: s.pop("passes")), "passes")
    resume_case("ckpt pass z as strings",
                jedit(lambda s: s["passes"][0].__setitem__("z", ["a"] * len(s["passes"][0]["z"]))), "z")
    resume_case("ckpt initial inf bits", jedit(lambda s: s["initial"].__setitem__(0, 0x7FF0000000000000)),
                "initial")
    resume_case("ckpt dx doubled", jedit(lambda s: s.__setitem__("dx", _scale_bits(s["dx"], 2.0))), "dx")
    resume_case("ckpt x0 negative", jedit(lambda s: s.__setitem__("x0", _scale_bits(s["x0"], -1.0) if s["x0"] else s["x0"])),
                None, expect="either")
    resume_case("ckpt z scaled 1e6", jedit(lambda s: s["passes"][0].__setitem__("z", _scale_bits(s["passes"][0]["z"], 1e6))),
                "z")
    resume_case("ckpt extra pass copied",
                jedit(lambda s: s["passes"].append(dict(s["passes"][0]))), None, expect="either")
    resume_case("ckpt negative bits field", jedit(lambda s: s["initial"].__setitem__(0, -5)), "checkpoint.json")
    resume_case("ckpt version bumped", jedit(lambda s: s.__setitem__("version", 999) if "version" in s else s.__setitem__("format", 999)),
                None, expect="either")
    resume_case("resume with a changed --set", None, "scenario", extra=sets("growth.passes_per_pass=50"))
    resume_case("resume with a changed scenario file", None, "scenario",
                extra=[])  # replaced below by the edited-file case
    cs.pop()

    def changed_file(d):
        edited(P, {})(d)
        s = str(d / "s.toml")
        study(d, s, POLY)
        txt = (d / "s.toml").read_text().replace("passes_per_pass = 100.0", "passes_per_pass = 300.0")
        (d / "s.toml").write_text(txt)
        b = list(POLY)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", s] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", "scenario"), code, err, d / "out", True, d, took)
    cs.append(Case("resume with a changed scenario file", [], custom=changed_file))

    def fewer_passes(d):
        study(d, P, POLY, "2")
        code, _, err, took = run(["grow", P] + POLY + ["--resume", "--out", str(d / "out")], d, LIMIT)
        c = Case("", [], "either", "passes", check=rate_check)
        return classify(c, code, err, d / "out", True, d, took)
    cs.append(Case("resume with fewer --passes than done", [], custom=fewer_passes))

    def resume_fresh(d):
        code, _, err, took = run(["grow", P] + POLY + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", "--out"), code, err, d / "out", False, d, took)
    cs.append(Case("resume with no folder", [], custom=resume_fresh))

    def plastic_on_elastic(d):
        study(d, PP, POLY)
        b = list(POLY)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", P] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", None), code, err, d / "out", True, d, took)
    cs.append(Case("resume a plastic folder as the elastic study", [], custom=plastic_on_elastic))

    def track_ck(d):
        study(d, C, CORR)
        ck = d / "out" / "checkpoint.json"
        s = json.loads(ck.read_text())
        s["passes"][0]["z"] = s["passes"][0]["z"][:3]
        ck.write_text(json.dumps(s))
        b = list(CORR)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", C] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", ("checkpoint.json", "z")), code, err, d / "out", True, d, took)
    cs.append(Case("track ckpt short z", [], custom=track_ck))

    def plastic_state(d):
        study(d, PP, POLY)
        ck = d / "out" / "checkpoint.json"
        s = json.loads(ck.read_text())
        keys = [k for k in s if k == "runner" and s[k]]
        if not keys:
            return "result", "no plastic state in the checkpoint to damage"
        k = keys[0]
        v = s[k]
        s[k] = [] if isinstance(v, list) else ({} if isinstance(v, dict) else None)
        ck.write_text(json.dumps(s))
        b = list(POLY)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", PP] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", ("checkpoint.json",)), code, err, d / "out", True, d, took)
    cs.append(Case("plastic ckpt state emptied", [], custom=plastic_state))

    def plastic_state_nan(d):
        study(d, PP, POLY)
        ck = d / "out" / "checkpoint.json"
        t = ck.read_text()
        s = json.loads(t)
        keys = [k for k in s if k == "runner" and s[k]]
        if not keys:
            return "result", "no plastic state"
        k = keys[0]
        # every number in the plastic state: NaN's bits if stored as bits, else 1e300
        def poison(v):
            if isinstance(v, list):
                return [poison(x) for x in v]
            if isinstance(v, dict):
                return {a: poison(b) for a, b in v.items()}
            if isinstance(v, int) and not isinstance(v, bool):
                return 0x7FF8000000000000 if v > 1 << 52 else v
            if isinstance(v, float):
                return 1e300
            return v
        s[k] = poison(s[k])
        ck.write_text(json.dumps(s))
        b = list(POLY)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", PP] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "refuse", ("checkpoint.json",)), code, err, d / "out", True, d, took)
    cs.append(Case("plastic ckpt state poisoned", [], custom=plastic_state_nan))

    # signals: a study stopped mid-pass, then resumed, ends where an uninterrupted one does
    def sig_resume(src, base, sig, name):
        def custom(d):
            b = list(base)
            b[b.index("--passes") + 1] = "3"
            ref = run(["grow", src] + b + ["--out", str(d / "ref")], d, LIMIT)
            if ref[0] != 0:
                return "defect", f"the reference study failed: {ref[2][-300:]}"
            p = subprocess.Popen([str(BIN), "grow", src] + b + ["--out", str(d / "out")], cwd=d,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            # stop it during its second pass
            deadline = time.time() + LIMIT
            while time.time() < deadline and p.poll() is None:
                ck = d / "out" / "checkpoint.json"
                if ck.exists():
                    try:
                        if len(json.loads(ck.read_text()).get("passes", [])) >= 1:
                            break
                    except Exception:  # noqa: BLE001
                        pass
                time.sleep(0.02)
            time.sleep(0.1)
            if p.poll() is None:
                p.send_signal(sig)
            try:
                _, err = p.communicate(timeout=LIMIT)
            except subprocess.TimeoutExpired:
                p.kill()
                return "defect", "hang after the signal"
            if p.returncode not in (0, 130):
                return "defect", f"exit {p.returncode} after {sig}: {err[-300:]}"
            code, _, err, took = run(["grow", src] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
            if code != 0:
                return "defect", f"resume after the signal: exit {code}: {err[-300:]}"
            a, r = summary(d / "out"), summary(d / "ref")
            for k in ("rms_final_m", "uniform_loss_m"):
                if not math.isclose(a[k], r[k], rel_tol=1e-9, abs_tol=1e-18):
                    return "defect", f"resumed {k} = {a[k]} against {r[k]} uninterrupted"
            if a.get("interrupted"):
                return "defect", "a resumed and finished study says interrupted"
            return "result", "resumed = uninterrupted"
        cs.append(Case(name, [], custom=custom))

    sig_resume(P, POLY, signal.SIGTERM, "SIGTERM mid-study then resume (elastic)")
    sig_resume(PP, POLY, signal.SIGINT, "SIGINT mid-study then resume (plastic)")
    sig_resume(C, CORR, signal.SIGTERM, "SIGTERM mid-study then resume (track)")
    return cs


def _scale_bits(v, f):
    """A checkpoint's float (stored as its bits, or as a number) times `f`."""
    import struct

    def one(x):
        if isinstance(x, int) and not isinstance(x, bool) and x > (1 << 32):
            y = struct.unpack("<d", struct.pack("<Q", x))[0] * f
            return struct.unpack("<Q", struct.pack("<d", y))[0]
        if isinstance(x, (int, float)) and not isinstance(x, bool):
            return x * f
        return x
    if isinstance(v, list):
        return [one(x) for x in v]
    return one(v)


def track_cases():
    T = str(SC / "track.toml")
    TT = str(SC / "track-traction.toml")
    ML = str(SC / "track-moving-load.toml")
    base = ["run", T, "--quiet", "--threads", "1"] + TRACKSET
    cs = []
    for k, v, exp in [("vehicle.speed_km_h", "0", "refuse"), ("vehicle.speed_km_h", "nan", "refuse"),
                      ("vehicle.speed_km_h", "1e-6", "refuse"), ("vehicle.axle_load", "-1e5", "refuse"),
                      ("vehicle.axle_load", "1e12", "refuse"), ("vehicle.unsprung_mass", "0", "refuse"),
                      ("vehicle.unsprung_mass", "-800", "refuse"), ("vehicle.wheel_radius", "0", "refuse"),
                      ("vehicle.wheel_radius", "50.0", "refuse"), ("vehicle.wheel_rim_nodes", "3", "refuse"),
                      ("vehicle.wheel_thickness", "0", "refuse"), ("vehicle.wheel_thickness", "nan", "refuse"),
                      ("vehicle.model", "\"bogie\"", "refuse"), ("vehicle.travel_bays", "-2", "refuse"),
                      ("vehicle.travel_bays", "2.5", "refuse"), ("track.set", "\"uic99\"", "refuse"),
                      ("track.bays", "0", "refuse"), ("track.elements_per_bay", "0", "refuse"),
                      ("track.elements_per_bay", "1", "either"), ("track.end_bays", "-1", "refuse"),
                      ("track.end_bays", "0", "either"), ("time.alpha", "0", "refuse"),
                      ("time.alpha", "nan", "refuse"), ("time.gamma", "-1", "refuse"),
                      ("time.gamma", "2", "refuse"), ("contact.method", "\"bogus\"", "refuse"),
                      ("contact.friction", "0.3", "either"), ("vehicle.suspension_stiffness", "-1e7", "refuse"),
                      ("track.spacing", "nan", "refuse"), ("track.pad_stiffness", "0", "refuse"),
                      ("track.pad_stiffness", "-2e8", "refuse"), ("track.sleeper_mass", "0", "refuse"),
                      ("track.ballast_stiffness", "nan", "refuse"), ("track.bogus", "1", "refuse"),
                      ("vehicle", "1", "refuse"), ("time.h", "-1e-5", "refuse"), ("time.h", "1.0", "refuse")]:
        cs.append(Case(f"track {k}={v}", base + sets(f"{k}={v}"), exp, k, check=track_check))
    ttbase = ["run", TT, "--quiet", "--threads", "1"] + TRACKSET
    for k, v, exp in [("vehicle.creepage", "nan", "refuse"), ("vehicle.creepage", "-0.01", "either"),
                      ("vehicle.creepage", "3", "refuse"), ("contact.friction", "-0.3", "refuse"),
                      ("contact.friction", "inf", "refuse"), ("vehicle.suspension_damping", "-1", "refuse"),
                      ("vehicle.suspension_stiffness", "0", "either")]:
        cs.append(Case(f"track-traction {k}={v}", ttbase + sets(f"{k}={v}"), exp, k, check=track_check))
    cs.append(Case("track-moving-load as shipped (short)", ["run", ML, "--quiet"] + sets("track.bays=30", "track.end_bays=8"),
                   "either", None))
    for k, v in [("vehicle.speed_km_h", "-50"), ("vehicle.axle_load", "nan"), ("track.bays", "1e6")]:
        cs.append(Case(f"moving-load {k}={v}", ["run", ML, "--quiet"] + sets(f"{k}={v}"), "refuse", k))
    # receptance
    R = ["receptance", T]
    for k, v, exp in [("receptance.f_min", "0", "refuse"), ("receptance.f_min", "-20", "refuse"),
                      ("receptance.f_min", "nan", "refuse"), ("receptance.f_min", "5000", "refuse"),
                      ("receptance.f_max", "inf", "refuse"), ("receptance.f_max", "20", "refuse"),
                      ("receptance.points", "0", "refuse"), ("receptance.points", "1", "refuse"),
                      ("receptance.points", "2.5", "refuse"), ("receptance.points", "-5", "refuse"),
                      ("receptance.points", "1e9", "refuse"), ("receptance.bogus", "1", "refuse"),
                      ("receptance.f_min", "\"low\"", "refuse"), ("track.bays", "3", "refuse"),
                      ("track.pad_damping", "-1", "refuse"), ("track.rail", "\"x\"", "refuse"),
                      ("receptance.points", "2", "either"), ("receptance.f_min", "1e-3", "either")]:
        cs.append(Case(f"receptance {k}={v}", ["receptance", "{d}/s.toml"], exp, k, check=receptance_check,
                       setup=edited(T, {k: v})))
    cs.append(Case("receptance without [receptance]", R, "either", None, check=receptance_check,
                   setup=edited(T, {}, drop_tables=("receptance",))))
    cs[-1].args = ["receptance", "{d}/s.toml"]
    cs.append(Case("receptance of the wheel", ["receptance", str(SC / "wheel.toml")], "refuse", None))
    cs.append(Case("receptance of corrugation", ["receptance", str(SC / "corrugation.toml")], "either", None,
                   check=receptance_check))
    cs.append(Case("receptance --out is a file", ["receptance", T, "--out", "{d}/f"], "refuse", "f",
                   setup=lambda d: (d / "f").write_text("mine\n"), out=False))
    return cs


def block_cases():
    B = str(SC / "wheel-on-block.toml")
    base = ["run", B] + BLOCK
    cs = []
    for k, v, exp in [("block.depth", "0", "refuse"), ("block.depth", "-0.05", "refuse"),
                      ("block.depth", "nan", "refuse"), ("block.depth", "1e-6", "refuse"),
                      ("block.young", "0", "refuse"), ("block.young", "-2e11", "refuse"),
                      ("block.young", "1e30", "either"), ("block.poisson", "0.5", "refuse"),
                      ("block.poisson", "-1", "refuse"), ("block.poisson", "0.4999", "either"),
                      ("block.density", "0", "refuse"), ("block.density", "inf", "refuse"),
                      ("block.grading", "0", "refuse"), ("block.grading", "0.5", "refuse"),
                      ("block.grading", "100", "refuse"), ("block.grading", "1.0", "either"),
                      ("block.margin", "-1", "refuse"), ("block.margin", "0", "either"),
                      ("block.margin", "1e3", "refuse"), ("block.bogus", "1", "refuse"),
                      ("block", "1", "refuse"), ("contact.friction", "0.3", "either"),
                      ("contact.method", "\"exact\"", "either"), ("rolling.flattening", "0.02", "either"),
                      ("material.model", "\"j2\"", "either")]:
        extra = sets(f"{k}={v}")
        if k == "material.model":
            extra += sets("material.yield_stress=1.2e9", "wheel.plane=\"strain\"")
        cs.append(Case(f"block {k}={v}", base + extra, exp, k, check=block_check))
    cs.append(Case("[block] on the track", ["run", str(SC / "track.toml"), "--quiet"] + TRACKSET
                   + sets("block.depth=0.05"), "refuse", "block"))
    cs.append(Case("grow on the block", ["grow", "{d}/s.toml", "--passes", "1", "--threads", "1"]
                   + sets("wheel.rim_nodes=96", "rolling.turns=1"), "either", None, check=rate_check,
                   setup=lambda d: (d / "s.toml").write_text(_block_growth_text())))
    return cs


def _block_growth_text():
    b = (SC / "wheel-on-block.toml").read_text()
    p = (SC / "polygon.toml").read_text()
    tail = p[p.index("[growth]"):]
    return b + "\n" + tail


def shakedown_cases():
    cs = []
    base = ["shakedown", "--passes", "2"]
    for a, v, exp in [("--p0-over-k", "0", "either"), ("--p0-over-k", "-1", "refuse"),
                      ("--p0-over-k", "nan", "refuse"), ("--p0-over-k", "inf", "refuse"),
                      ("--p0-over-k", "1e9", "refuse"), ("--passes", "0", "refuse"),
                      ("--passes", "-1", "refuse"), ("--passes", "1000000000", "refuse"),
                      ("--h-over-a", "0", "refuse"), ("--h-over-a", "nan", "refuse"),
                      ("--h-over-a", "1e-6", "refuse"), ("--h-over-a", "100", "refuse"),
                      ("--path-over-a", "0", "refuse"), ("--path-over-a", "1", "refuse"),
                      ("--step-over-a", "0", "refuse"), ("--step-over-a", "-0.1", "refuse"),
                      ("--step-over-a", "100", "refuse"), ("--far-over-a", "0", "refuse"),
                      ("--far-over-a", "1", "refuse"), ("--far-over-a", "1e9", "refuse")]:
        args = list(base)
        if a == "--passes":
            args = ["shakedown", "--passes", v, "--p0-over-k", "4"]
        elif a == "--p0-over-k":
            args += [a, v]
        else:
            args += ["--p0-over-k", "4", a, v]
        key = v if v.startswith("-") else a.lstrip("-")  # clap names a negative value itself
        cs.append(Case(f"shakedown {a} {v}", args, exp, key[:2] if v.startswith("-") else key,
                       check=shakedown_check))
    cs.append(Case("shakedown --out is a file", ["shakedown", "--passes", "1", "--p0-over-k", "4",
                                                 "--out", "{d}/f"], "refuse", "f",
                   setup=lambda d: (d / "f").write_text("mine\n"), out=False))
    cs.append(Case("shakedown two p0 (ok)", ["shakedown", "--passes", "2", "--p0-over-k", "3",
                                             "--p0-over-k", "4.5"], "ok", None))
    return cs


def sweep_cases():
    W = str(SC / "wheel.toml")
    sh = ["sweep", W, "--jobs", "1"] + sets("rolling.omega=200,300", "wheel.rim_nodes=96", "rolling.turns=0.1")
    cs = []
    for v, exp in [("0/2", "refuse"), ("3/2", "refuse"), ("1/0", "refuse"), ("a/b", "refuse"),
                   ("1/2/3", "refuse"), ("-1/2", "refuse"), ("1/99999999999999999999", "refuse"),
                   ("2/5", "either")]:
        cs.append(Case(f"sweep --shard {v}", sh + ["--shard", v], exp, "-1" if v == "-1/2" else "shard"))
    cs.append(Case("sweep --jobs 0", sh + ["--jobs", "0"], "either", "jobs"))
    cs.append(Case("sweep value list empty", ["sweep", W] + sets("rolling.omega="), "refuse", "rolling.omega"))
    cs.append(Case("sweep value nan", ["sweep", W] + sets("rolling.omega=200,nan", "wheel.rim_nodes=96",
                                                         "rolling.turns=0.1"), "refuse", "rolling.omega"))
    cs.append(Case("sweep zip unequal", ["sweep", W, "--grid", "zip"] + sets("rolling.omega=200,300",
                                                                              "wheel.rim_nodes=96,144,192"),
                   "refuse", "zip"))
    cs.append(Case("sweep unknown key", ["sweep", W] + sets("rolling.omegaa=1,2"), "refuse", "rolling.omegaa"))
    cs.append(Case("sweep 1e5 points", ["sweep", W] + sets("rolling.omega=" + ",".join(str(200 + i) for i in range(400)),
                                                           "wheel.rim_nodes=" + ",".join(str(96 + 2 * i) for i in range(300))),
                   "refuse", None))

    def shards(d, n=2, extra=()):
        for i in range(1, n + 1):
            code, _, err, _ = run(sh + list(extra) + ["--shard", f"{i}/{n}", "--out", str(d / f"s{i}")], d, LIMIT)
            if code != 0:
                raise RuntimeError(f"shard {i}: {err[-300:]}")

    def gather_case(name, edit, key, expect="refuse"):
        def custom(d):
            shards(d)
            if edit:
                edit(d)
            args = ["gather", str(d / "s1"), str(d / "s2"), "--out", str(d / "g")]
            code, _, err, took = run(args, d, LIMIT)
            c = Case(name, [], expect, key)
            return classify(c, code, err, d / "g", False, d, took)
        cs.append(Case(name, [], custom=custom))

    def mjson(f, which="s1"):
        def e(d):
            p = d / which / "shard.json"
            s = json.loads(p.read_text())
            f(s)
            p.write_text(json.dumps(s))
        return e

    gather_case("gather ok", None, None, "ok")
    gather_case("gather of=0", mjson(lambda s: s.__setitem__("of", 0)), "of")
    gather_case("gather of=-1", mjson(lambda s: s.__setitem__("of", -1)), "shard.json")
    gather_case("gather shard=5", mjson(lambda s: s.__setitem__("shard", 5)), "shard")
    gather_case("gather shard.json truncated", lambda d: (d / "s1" / "shard.json").write_text("{\"na"), "shard.json")
    gather_case("gather shard.json missing", lambda d: (d / "s1" / "shard.json").unlink(), "shard.json")
    gather_case("gather status dropped", mjson(lambda s: s.pop("status")), "status", "either")
    gather_case("gather status bogus", mjson(lambda s: s.__setitem__("status", ["bogus"])), "status")
    gather_case("gather points emptied", mjson(lambda s: s.__setitem__("points", [])), "shard")
    gather_case("gather point folder deleted", lambda d: shutil.rmtree(
        next(p for p in (d / "s1").iterdir() if p.is_dir())), "s1")
    gather_case("gather point summary nulls", lambda d: _poison_point(d), "summary", "either")
    gather_case("gather sha edited", mjson(lambda s: s.__setitem__("scenario_sha256", "0" * 64)), "scenario")
    gather_case("gather grid edited", mjson(lambda s: s.__setitem__("grid", "zip")), "grid")
    gather_case("gather keys edited", mjson(lambda s: s["keys"][0][1].append("400")), "keys")

    def same_twice(d):
        shards(d)
        code, _, err, took = run(["gather", str(d / "s1"), str(d / "s1"), "--out", str(d / "g")], d, LIMIT)
        return classify(Case("", [], "refuse", "s1"), code, err, d / "g", False, d, took)
    cs.append(Case("gather the same shard twice", [], custom=same_twice))

    def one_missing(d):
        shards(d)
        code, _, err, took = run(["gather", str(d / "s1"), "--out", str(d / "g")], d, LIMIT)
        return classify(Case("", [], "refuse", "2"), code, err, d / "g", False, d, took)
    cs.append(Case("gather one of two shards", [], custom=one_missing))

    def two_sweeps(d):
        shards(d)
        code, _, err, _ = run(["sweep", W, "--jobs", "1"] + sets("rolling.omega=250,350", "wheel.rim_nodes=96",
                                                                  "rolling.turns=0.1")
                              + ["--shard", "2/2", "--out", str(d / "o2")], d, LIMIT)
        if code != 0:
            return "defect", f"setup: {err[-200:]}"
        code, _, err, took = run(["gather", str(d / "s1"), str(d / "o2"), "--out", str(d / "g")], d, LIMIT)
        return classify(Case("", [], "refuse", None), code, err, d / "g", False, d, took)
    cs.append(Case("gather shards of two sweeps", [], custom=two_sweeps))

    def gather_into_shard(d):
        shards(d)
        code, _, err, took = run(["gather", str(d / "s1"), str(d / "s2"), "--out", str(d / "s1")], d, LIMIT)
        kind, msg = classify(Case("", [], "refuse", None), code, err, None, True, d, took)
        if not (d / "s1" / "shard.json").exists():
            return "defect", "gather --out onto a shard destroyed the shard"
        return kind, msg
    cs.append(Case("gather --out onto a shard", [], custom=gather_into_shard))

    def gather_no_args(d):
        code, _, err, took = run(["gather", "--out", str(d / "g")], d, LIMIT)
        return classify(Case("", [], "refuse", None), code, err, d / "g", False, d, took)
    cs.append(Case("gather nothing", [], custom=gather_no_args))
    cs.append(Case("gather a plain folder", ["gather", "{d}/x", "{d}/y"], "refuse", "x",
                   setup=lambda d: ((d / "x").mkdir(), (d / "y").mkdir())))

    # converge
    def conv(name, ladder, key, expect="refuse", src=None):
        def setup(d):
            txt = (SC / "wheel.toml").read_text()
            txt = re.sub(r"(?m)^turns = .*$", "turns = 0.1", txt)
            (d / "w.toml").write_text(txt)
        cs.append(Case(name, ["converge", src or "{d}/w.toml", "--jobs", "1", "--set", ladder], expect, key,
                       setup=setup, timeout=300))
    conv("converge two rungs", "wheel.rim_nodes=48,96", "rungs")
    conv("converge not geometric", "wheel.rim_nodes=48,96,100", "constant ratio")
    conv("converge descending", "wheel.rim_nodes=192,96,48", None, "either")
    conv("converge repeated", "wheel.rim_nodes=96,96,96", "wheel.rim_nodes")
    conv("converge a string key", "contact.method=a,b,c", "contact.method")
    conv("converge negative step", "time.h=-1e-5,-5e-6,-2.5e-6", "time.h")
    conv("converge nan rung", "time.h=1e-5,nan,2.5e-6", "time.h")
    conv("converge unknown key", "wheel.rimnodes=48,96,192", "wheel.rimnodes")
    conv("converge no values", "wheel.rim_nodes=", "wheel.rim_nodes")
    conv("converge no =", "wheel.rim_nodes", "wheel.rim_nodes")
    conv("converge a growth study", "wheel.rim_nodes=48,96,192", None, "either", src=str(SC / "polygon.toml"))
    conv("converge the track", "vehicle.wheel_rim_nodes=180,360,720", None, "either", src=str(SC / "track.toml"))
    return cs


def _poison_point(d):
    p = next(p for p in (d / "s1").iterdir() if p.is_dir())
    s = p / "summary.json"
    t = json.loads(s.read_text())
    for k in list(t):
        if isinstance(t[k], float):
            t[k] = None
    s.write_text(json.dumps(t))


def set_and_files_cases():
    W = str(SC / "wheel.toml")
    P = str(SC / "polygon.toml")
    short = ["--quiet", "--threads", "1"] + sets("wheel.rim_nodes=96", "rolling.turns=0.1")
    cs = []
    for s, key in [("=1", None), ("wheel.rim_nodes", "wheel.rim_nodes"), (".rim_nodes=96", "rim_nodes"),
                   ("wheel..rim_nodes=96", "rim_nodes"), ("wheel.rim_nodes=[96]", "wheel.rim_nodes"),
                   ("wheel.rim_nodes={a=1}", "wheel.rim_nodes"), ("kind=\"track\"", None),
                   ("wheel=3", "wheel"), ("wheel.rim_nodes=0x60", None),
                   ("rolling.omega=\"300\"", "rolling.omega"), ("rolling.omega=1_000_000", "rolling.omega"),
                   ("name=\"" + "x" * 100000 + "\"", None), ("name=\"../../etc\"", None),
                   ("wheel.rim_nodes=9999999999999999999", "wheel.rim_nodes"),
                   ("time.h=1e-320", "time.h"), ("rolling.omega=-0.0", "rolling.omega"),
                   ("material.young=1e-300", "material.young"), ("material.density=1e300", "material.density")]:
        exp = "either" if s in ("wheel.rim_nodes=0x60", "name=\"../../etc\"") else "refuse"
        cs.append(Case(f"--set {s[:40]}", ["run", W] + short + ["--set", s], exp, key))
    for s, key in [("growth.passes=1e400", "growth.passes"), ("growth.level=-nan", "growth.level"),
                   ("growth.seed=18446744073709551616", "growth.seed"),
                   ("wear=\"none\"", "wear"), ("growth={}", "growth")]:
        cs.append(Case(f"grow --set {s}", ["grow", P] + POLY + ["--set", s], "either" if s == "growth={}" else "refuse",
                       key, check=rate_check))
    # scenario files
    for name, data, key in [("empty", b"", None), ("bom", b"\xef\xbb\xbf" + (SC / "wheel.toml").read_bytes(), None),
                            ("binary", bytes(range(256)) * 4, None),
                            ("utf16", (SC / "wheel.toml").read_text().encode("utf-16"), None),
                            ("two kinds", (SC / "wheel.toml").read_bytes() + b"\nkind = \"track\"\n", "kind"),
                            ("nan radius", (SC / "wheel.toml").read_bytes().replace(b"radius = 0.1 ", b"radius = nan "),
                             "wheel.radius")]:
        def setup(d, data=data):
            (d / "s.toml").write_bytes(data)
        exp = "either" if name == "bom" else "refuse"
        cs.append(Case(f"scenario file {name}", ["run", "{d}/s.toml"] + short, exp, key, setup=setup))
    cs.append(Case("scenario is a folder", ["run", "{d}"] + short, "refuse", None))
    cs.append(Case("scenario missing", ["grow", "{d}/nope.toml", "--passes", "1"], "refuse", "nope.toml"))
    cs.append(Case("scenario /dev/zero", ["run", "/dev/zero"] + short, "refuse", None, timeout=30))

    # output folders
    def ro(d):
        (d / "ro").mkdir()
        os.chmod(d / "ro", 0o555)
    cs.append(Case("grow --out in a read-only folder", ["grow", P] + POLY + ["--out", "{d}/ro/out"],
                   "either", None, setup=ro, out=False))
    cs.append(Case("grow --out is a file", ["grow", P] + POLY + ["--out", "{d}/f"], "refuse", "f",
                   setup=lambda d: (d / "f").write_text("mine\n"), out=False))

    def user_files(d):
        (d / "out").mkdir()
        (d / "out" / "notes.txt").write_text("my notes\n")
        code, _, err, took = run(["grow", P] + POLY + ["--out", str(d / "out")], d, LIMIT)
        if not (d / "out" / "notes.txt").exists():
            return "defect", f"user's notes.txt lost (exit {code})"
        return classify(Case("", [], "refuse", "out"), code, err, None, True, d, took)
    cs.append(Case("grow into a folder with the user's files", [], custom=user_files))

    def user_files_resume(d):
        code, _, err, _ = run(["grow", P] + POLY + ["--out", str(d / "out")], d, LIMIT)
        (d / "out" / "notes.txt").write_text("my notes\n")
        b = list(POLY)
        b[b.index("--passes") + 1] = "2"
        code, _, err, took = run(["grow", P] + b + ["--resume", "--out", str(d / "out")], d, LIMIT)
        if not (d / "out" / "notes.txt").exists():
            return "defect", f"resume lost the user's notes.txt (exit {code})"
        return classify(Case("", [], "either", None, check=rate_check), code, err, d / "out", True, d, took)
    cs.append(Case("resume with the user's file in the folder", [], custom=user_files_resume))

    def out_is_scenario_dir(d):
        shutil.copy(P, d / "polygon.toml")
        code, _, err, took = run(["grow", str(d / "polygon.toml")] + POLY + ["--out", str(d)], d, LIMIT)
        if not (d / "polygon.toml").exists():
            return "defect", f"the scenario itself deleted (exit {code})"
        return classify(Case("", [], "refuse", None), code, err, None, True, d, took)
    cs.append(Case("grow --out = the scenario's own folder", [], custom=out_is_scenario_dir))

    def receptance_over_run(d):
        T = str(SC / "track.toml")
        code, _, err, _ = run(["run", T, "--quiet"] + TRACKSET + ["--out", str(d / "out")], d, LIMIT)
        if code != 0:
            return "defect", f"setup: {err[-200:]}"
        code, _, err, took = run(["receptance", T, "--out", str(d / "out")], d, LIMIT)
        return classify(Case("", [], "either", None, check=receptance_check), code, err, d / "out", True, d, took)
    cs.append(Case("receptance into a run's folder", [], custom=receptance_over_run))
    return cs


def all_cases():
    return (grow_cases() + checkpoint_cases() + track_cases() + block_cases() + shakedown_cases()
            + sweep_cases() + set_and_files_cases())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--keep", action="store_true", help="keep the cases' folders")
    a = ap.parse_args()
    if not BIN.exists():
        sys.exit(f"no binary at {BIN}: cargo build --release")
    cases = [c for c in all_cases() if a.only in c.name]
    names = [c.name for c in cases]
    assert len(names) == len(set(names)), [n for n in names if names.count(n) > 1]
    base = Path(tempfile.mkdtemp(prefix="softway-probe-"))
    counts = {"refusal": 0, "result": 0, "defect": 0}
    defects = []
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        futs = {ex.submit(run_case, c, base): c for c in cases}
        for f in cf.as_completed(futs):
            c = futs[f]
            try:
                kind, msg = f.result()
            except Exception as e:  # noqa: BLE001
                kind, msg = "defect", f"probe error: {e!r}"
            counts[kind] += 1
            if kind == "defect":
                defects.append((c.name, msg))
                print(f"DEFECT  {c.name}: {msg}", flush=True)
            elif a.verbose:
                print(f"{kind:8s}{c.name}: {msg[:200]}", flush=True)
    if not a.keep:
        for p in base.rglob("*"):
            if p.is_dir():
                try:
                    os.chmod(p, 0o755)
                except OSError:
                    pass
        shutil.rmtree(base, ignore_errors=True)
    print(f"\n{len(cases)} cases: {counts['refusal']} clean refusals, {counts['result']} correct results, "
          f"{counts['defect']} defects")
    sys.exit(1 if defects else 0)


if __name__ == "__main__":
    main()
