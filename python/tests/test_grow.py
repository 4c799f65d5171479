"""softway.grow against `softway grow`: the same files and, in memory, the same numbers;
Ctrl-C keeps the finished passes and a resumed study gives the bits of one run without a
stop (from Python and from the command line).

The study: scenarios/polygon.toml (the paper's wheel, random rim roughness,
frictional-power wear, a reference pass) shrunk to run in seconds: 96 rim nodes, a step of
1e-5 s, a shorter settling; a pass is about 0.4 s of CPU."""

from __future__ import annotations

import _thread
import csv
import json
import math
import re
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import softway
from test_softway import SCENARIOS, cli

POLYGON = SCENARIOS / "polygon.toml"
SHRINK = {"wheel.rim_nodes": 96, "time.h": 1e-5, "rolling.settle_time": 1.5e-3}
SETS = [a for k, v in SHRINK.items() for a in ("--set", f"{k}={v}")]
PASSES = 3


def rows(p: Path) -> tuple[list[str], list[list[str]]]:
    with open(p, newline="") as f:
        r = list(csv.reader(f))
    return r[0], r[1:]


def is_timing(name: str) -> bool:
    """A column that measures the machine: the wall-clock times (`wall_s`, `build_s`,
    `loop_s`, `wear_bookkeeping_s`) carry the unit s; no other column of passes.csv
    does."""
    return name.endswith("_s")


def checkpoint_profiles(folder: Path) -> np.ndarray:
    """The profiles of a checkpoint, read independently of the package: JSON holds each
    float as its u64 bits."""
    ck = json.loads((folder / "checkpoint.json").read_text())
    zs = [ck["initial"]] + [p["z"] for p in ck["passes"]]
    return np.array(zs, dtype=np.uint64).view(np.float64)


def without_timing(summary: dict) -> dict:
    s = dict(summary)
    s.pop("mean_pass_wall_s")
    s["last_pass"] = [kv for kv in s["last_pass"] if not is_timing(kv[0])]
    return s


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The command line's study and softway.grow's, each 3 passes."""
    d = tmp_path_factory.mktemp("grow")
    o = cli("grow", POLYGON, "--passes", PASSES, *SETS, "--out", d / "cli")
    assert o.returncode == 0, o.stderr
    r = softway.grow(POLYGON, passes=PASSES, out=d / "py", progress=False, **SHRINK)
    return d, r


def test_grow_writes_the_cli_files(study):
    d, r = study
    cli_dir, py_dir = d / "cli", d / "py"
    assert not r.interrupted and r.passes_run == PASSES
    names = {f.name for f in r.files}
    assert {"passes.csv", "bands.csv", "orders.csv", "profile.csv", "summary.json",
            "checkpoint.json", "spectrum.png"} <= names, names
    # The tables and plots without a clock in them: byte for byte.
    for f in ("bands.csv", "orders.csv", "profile.csv", "spectrum.png", "growth_rate.png",
              "profile.png", "orders.png"):
        assert (py_dir / f).read_bytes() == (cli_dir / f).read_bytes(), f
    # passes.csv and summary.json less the wall-clock times.
    (h1, r1), (h2, r2) = rows(cli_dir / "passes.csv"), rows(py_dir / "passes.csv")
    assert h1 == h2
    keep = [i for i, n in enumerate(h1) if not is_timing(n)]
    assert [[row[i] for i in keep] for row in r1] == [[row[i] for i in keep] for row in r2]
    a = json.loads((cli_dir / "summary.json").read_text())
    b = json.loads((py_dir / "summary.json").read_text())
    assert without_timing(a) == without_timing(b)
    # The checkpoints' profiles, bit for bit.
    assert checkpoint_profiles(cli_dir).tobytes() == checkpoint_profiles(py_dir).tobytes()
    # save() writes the same files from the result.
    saved = r.save(d / "saved")
    assert {f.name for f in saved} == {f.name for f in r.files}
    for f in ("bands.csv", "orders.csv", "profile.csv", "passes.csv", "summary.json",
              "checkpoint.json", "scenario.toml", "spectrum.png"):
        assert (d / "saved" / f).read_bytes() == (py_dir / f).read_bytes(), f


def test_the_result_holds_the_cli_numbers(study):
    d, r = study
    cli_dir = d / "cli"
    # passes: the per-pass table over `pass`, each number the CSV's (shortest round-trip
    # text, so parsing it gives the bits).
    p = r.passes
    assert isinstance(p, xr.Dataset)
    head, body = rows(cli_dir / "passes.csv")
    assert list(p["pass"].values) == [int(row[0]) for row in body] == list(range(PASSES))
    assert [n for n in head[1:]] == list(p.data_vars)
    for j, name in enumerate(head[1:], start=1):
        if is_timing(name):
            continue
        want = np.array([float(row[j]) for row in body])
        assert p[name].values.tobytes() == want.tobytes(), name
    assert p["rms_m"].attrs["units"] == "m" and p["mean_force_n"].attrs["units"] == "N"
    assert p["wall_s"].attrs["units"] == "s" and p["steps"].attrs["units"] == "1"
    assert p.to_pandas().shape == (PASSES, len(head) - 1)
    # bands: level per pass (after 0 .. 3 passes) and wavelength, the CSV's to its 4
    # decimals; the rates likewise; the wavelengths exactly.
    b = r.bands
    head, body = rows(cli_dir / "bands.csv")
    assert b["level_db"].dims == ("after_passes", "wavelength")
    assert b["level_db"].shape == (PASSES + 1, len(body))
    assert b["level_db"].attrs["units"] == "dB re 1 um"
    assert b["wavelength"].values.tobytes() == np.array([float(x[0]) for x in body]).tobytes()
    for j, row in enumerate(body):
        for k in range(PASSES + 1):
            assert row[4 + k] == f"{b['level_db'].values[k, j]:.4f}", (j, k)
        rate = b["rate_db_per_1e5"].values[j]
        assert row[-1] == ("NaN" if math.isnan(rate) else f"{rate:.4f}"), j
    # The initial roughness is 0 dB re 1 um in every band from 5 mm to the circumference.
    full = (b["wavelength"] >= 5e-3) & (b["wavelength"] <= 0.7)
    assert np.allclose(b["level_db"].isel(after_passes=0).where(full, drop=True), 0.0,
                       atol=1e-6)
    # orders: the wheel's polygon orders' amplitudes, the CSV's bits.
    head, body = rows(cli_dir / "orders.csv")
    amp = r.orders["amplitude_m"].values
    assert amp.shape == (PASSES + 1, len(body)) and len(body) == 96 // 2 - 1  # below Nyquist
    for j, row in enumerate(body):
        assert np.array([float(x) for x in row[3:3 + PASSES + 1]]).tobytes() == amp[:, j].tobytes()
    # profile: numpy arrays, the CSV's bits; profiles[k] the profile after k passes.
    head, body = rows(cli_dir / "profile.csv")
    cols = np.array([[float(x) for x in row] for row in body]).T
    for name, want in zip(head, cols):
        assert getattr(r.profile, name).tobytes() == want.tobytes(), name
    assert r.profiles.shape == (PASSES + 1, 96)
    assert r.profiles.tobytes() == checkpoint_profiles(cli_dir).tobytes()
    # The summary: the CLI's, and the RMS of the last profile.
    want = json.loads((cli_dir / "summary.json").read_text())
    assert without_timing(r.summary) == without_timing(want)
    assert r.summary["rms_final_m"] == pytest.approx(np.sqrt(np.mean(r.profile.z_m ** 2)),
                                                     rel=1e-12)


def test_ctrl_c_keeps_the_finished_passes_and_resume_gives_the_same_bits(
    tmp_path, study, monkeypatch
):
    """Ctrl-C (SIGINT's flag, as _thread.interrupt_main sets it) once the first pass has
    finished: GrowthInterrupted, a KeyboardInterrupt, with that pass kept in the result
    and the checkpoint; resume=True then runs the two passes left and gives the bits of
    the study run without a stop. The command line resumes a study Python began too."""
    d, whole = study
    fired = {}
    bar_call = softway._growth._PassBar.__call__

    def progress(self, p, target, *rest):
        bar_call(self, p, target, *rest)
        if p == 0 and "t" not in fired:
            fired["t"] = time.perf_counter()
            _thread.interrupt_main()

    monkeypatch.setattr(softway._growth._PassBar, "__call__", progress)
    with pytest.raises(KeyboardInterrupt) as e:
        softway.grow(POLYGON, passes=PASSES, out=tmp_path / "a", progress=True, **SHRINK)
    stopped = time.perf_counter()
    monkeypatch.undo()
    assert isinstance(e.value, softway.GrowthInterrupted)
    assert stopped - fired["t"] < 1.0, stopped - fired["t"]
    r = e.value.result
    assert r.interrupted and r.summary["passes"] == 1 and r.passes.sizes["pass"] == 1
    assert checkpoint_profiles(tmp_path / "a").shape == (2, 96)
    assert r.profiles.tobytes() == whole.profiles[:2].tobytes()

    resumed = softway.grow(POLYGON, passes=PASSES, out=tmp_path / "a", resume=True,
                           progress=False, **SHRINK)
    assert resumed.passes_run == PASSES - 1 and not resumed.interrupted
    assert resumed.profiles.tobytes() == whole.profiles.tobytes()
    for name in ("rms_m", "uniform_loss_m", "mean_force_n", "max_force_n"):
        assert resumed.passes[name].values.tobytes() == whole.passes[name].values.tobytes()
    assert resumed.bands["level_db"].values.tobytes() == whole.bands["level_db"].values.tobytes()

    # The command line goes on from a study Python stopped (the same scenario text, so the
    # same SHA-256), to the same bits.
    r.save(tmp_path / "b")
    assert checkpoint_profiles(tmp_path / "b").shape == (2, 96)
    o = cli("grow", POLYGON, "--passes", PASSES, *SETS, "--out", tmp_path / "b", "--resume")
    assert o.returncode == 0, o.stderr
    assert checkpoint_profiles(tmp_path / "b").tobytes() == whole.profiles.tobytes()


def test_grow_refuses_what_it_cannot_run(tmp_path):
    with pytest.raises(softway.ScenarioError, match=r"no \[growth\] table") as e:
        softway.grow(SCENARIOS / "wheel-paper-mesh.toml", passes=1, out=tmp_path / "x",
                     progress=False)
    assert e.value.key == "growth"
    with pytest.raises(softway.RunError, match="checkpoint"):
        softway.grow(POLYGON, passes=2, out=tmp_path / "none", resume=True, progress=False,
                     **SHRINK)
    with pytest.raises(ValueError, match="passes"):
        softway.grow(POLYGON, passes=0, out=tmp_path / "y", progress=False)
    with pytest.raises(softway.ScenarioError) as e:
        softway.grow(POLYGON, passes=1, out=tmp_path / "z", progress=False,
                     **{"growth.passes_per_pass": 0.0})
    assert e.value.key == "growth.passes_per_pass"


def test_grow_progress_bar_counts_passes(tmp_path, capsys):
    softway.grow(POLYGON, passes=1, out=tmp_path / "p", progress=True, **SHRINK)
    err = capsys.readouterr().err
    assert "pass" in err and "100%" in err, err
    help_text = softway.grow.__doc__
    assert "resume" in help_text and "GrowthInterrupted" in help_text


def test_issue_48_a_growth_result_pickles(study, tmp_path):
    """A GrowthResult sent between processes (a pool, Dask) keeps its numbers; save()
    needs the engine's state, left in the process that ran: said, naming the study's
    folder, whose checkpoint a resumed study reads."""
    import pickle

    _, r = study
    copy = pickle.loads(pickle.dumps(r))
    assert copy.summary == r.summary and copy.lines == r.lines
    assert copy.out == r.out and copy.files == r.files and copy.passes_run == r.passes_run
    np.testing.assert_array_equal(copy.profiles, r.profiles)
    for a, b in zip(copy.profile, r.profile):
        np.testing.assert_array_equal(a, b)
    xr.testing.assert_identical(copy.passes, r.passes)
    xr.testing.assert_identical(copy.bands, r.bands)
    xr.testing.assert_identical(copy.orders, r.orders)
    assert copy.profiles.flags.writeable
    e = pickle.loads(pickle.dumps(softway.GrowthInterrupted(r)))
    assert isinstance(e, softway.GrowthInterrupted) and e.result.summary == r.summary
    with pytest.raises(softway.RunError, match="unpickled.*" + re.escape(str(r.out))):
        copy.save(tmp_path / "again")
