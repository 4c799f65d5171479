"""The Python package against the command line: the same summary bit for bit, the same
one-line errors, Ctrl-C, and sweeps on Dask equal to serial and to `softway sweep`.

The command line under test is $SOFTWAY_BIN (default: target/release/softway, then
target/debug/softway, of the repository this file is in)."""

from __future__ import annotations

import _thread
import json
import os
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import softway

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"
SPEEDS = [250.0, 300.0, 350.0, 400.0]
#: The paper's bar (Fig. 8).
BAR = {"length": 1.0, "ea": 1.0, "rho_a": 1.0, "speed": 1.0, "gap": 0.5, "elements": 8}


def softway_bin() -> str:
    env = os.environ.get("SOFTWAY_BIN")
    if env:
        return env
    for p in (ROOT / "target/release/softway", ROOT / "target/debug/softway"):
        if p.is_file():
            return str(p)
    pytest.skip("no softway binary: cargo build --release (or set SOFTWAY_BIN)")


def cli(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [softway_bin(), *map(str, args)], capture_output=True, text=True, cwd=cwd
    )


#: Provenance that depends on the build, not on the run: the git commit each of the two
#: builds (the command line's, the wheel's) was made at.
BUILD_KEYS = ("softway_git_commit",)


def without_timings(summary: dict) -> dict:
    return {
        k: v
        for k, v in summary.items()
        if k not in softway.TIMING_KEYS and k not in BUILD_KEYS
    }


@pytest.fixture(scope="module")
def one_turn(tmp_path_factory) -> Path:
    """The paper's wheel (its 12-ring mesh) rolling one turn: about a second a run."""
    d = tmp_path_factory.mktemp("one-turn")
    sc = softway.Scenario(SCENARIOS / "wheel-paper-mesh.toml").with_values(
        **{"rolling.turns": 1}
    )
    p = d / "wheel-one-turn.toml"
    p.write_text(sc.text)
    return p


@pytest.fixture(scope="module")
def dask_executor():
    """A LocalCluster of two worker processes, one thread each."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster, Client(cluster) as client:
        yield client.get_executor()


def test_run_gives_the_cli_summary_bit_for_bit(tmp_path):
    """The paper's wheel (scenarios/wheel-paper-mesh.toml, five turns): softway.run's
    summary is the command line's, every number the same bits; save() writes the same
    history.csv and contact_nodes.csv bytes."""
    sc = SCENARIOS / "wheel-paper-mesh.toml"
    o = cli("run", sc, "--out", tmp_path / "cli", "--quiet")
    assert o.returncode == 0, o.stderr
    want = json.loads((tmp_path / "cli/summary.json").read_text())
    r = softway.run(str(sc), progress=False)
    assert not r.interrupted
    assert r.summary["steps"] > 10_000
    assert without_timings(r.summary) == without_timings(want)
    # Floats compared as bits, not as ==, and nothing left out by the dict comparison.
    for k, v in without_timings(want).items():
        if isinstance(v, float):
            assert np.float64(r.summary[k]).tobytes() == np.float64(v).tobytes(), k
    files = r.save(tmp_path / "py")
    names = {f.name for f in files}
    for f in ("history.csv", "contact_nodes.csv", "j2_rim_profile.csv", "velocity.pvd"):
        assert f in names, names
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    saved = json.loads((tmp_path / "py/summary.json").read_text())
    assert without_timings(saved) == without_timings(want)


def test_history_and_fields_are_xarray_and_numpy(one_turn):
    r = softway.run(one_turn, progress=False)
    h = r.history
    assert isinstance(h, xr.Dataset)
    assert h["time"].attrs["units"] == "s"
    assert h["contact_force_N"].attrs["units"] == "N"
    # The history is the CSV's: one row per stride of steps, times increasing.
    stride = 5
    assert h.sizes["time"] == r.summary["steps"] // stride + 1
    assert np.all(np.diff(h["time"].values) > 0)
    df = h.to_pandas()
    assert list(df.columns[:2]) == ["base_angle_deg", "contact_force_N"]
    # The mean over the rolling phase is the summary's (same samples: every step is in the
    # summary, every fifth in the history, so only close).
    rolling = h["contact_force_N"].where(h["time"] >= 5e-3, drop=True)
    assert abs(float(rolling.mean()) / r.summary["mean_contact_force"] - 1) < 1e-2
    # The contact nodes' forces add up to the total contact force at each written step.
    cn = r.contact_nodes
    assert {"node", "t_s", "force_N", "gap_m", "held"} <= set(cn.columns)
    total = cn.groupby("t_s")["force_N"].sum()
    t = total.index.values[len(total) // 2]
    i = int(np.argmin(np.abs(h["time"].values - t)))
    assert abs(total.loc[t] - float(h["contact_force_N"][i])) <= 1e-6 * abs(total.loc[t])
    # Fields: the mesh as numpy (469 nodes of the 12-ring disk within the radius), each
    # velocity frame a 2-vector per node.
    f = r.fields
    assert f.points.shape == (469, 2)
    assert f.cells.shape == (864, 3) and f.cells.max() == 468
    assert np.max(np.hypot(*f.points.T)) == pytest.approx(0.1)
    v = [fr for fr in f.frames if fr.name.startswith("velocity_")]
    assert len(v) == 8 and all(fr.time is not None for fr in v)
    assert v[0].point_data["velocity"].shape == (469, 2)
    try:
        import pyvista  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pip install pyvista"):
            f.to_pyvista(0)
    else:  # pragma: no cover - pyvista is optional
        assert f.to_pyvista(0).n_points == 469


def test_a_bad_scenario_raises_the_cli_message(tmp_path):
    bad = tmp_path / "bad.toml"
    text = (SCENARIOS / "wheel-paper-mesh.toml").read_text().replace(
        "flattening = 1e-3", "flattening = 0.5"
    )
    assert text != (SCENARIOS / "wheel-paper-mesh.toml").read_text()
    bad.write_text(text)
    o = cli("run", bad, "--out", tmp_path / "out")
    assert o.returncode == 2
    line = o.stderr.strip()
    assert line.startswith("softway: error: ") and "\n" not in line
    with pytest.raises(softway.ScenarioError) as e:
        softway.Scenario(bad)
    assert str(e.value) == line.removeprefix("softway: error: ")
    assert e.value.key == "rolling.flattening"
    # The same from a dict and from text, named as such; an override is checked too.
    with pytest.raises(softway.ScenarioError) as e:
        softway.run(SCENARIOS / "wheel-paper-mesh.toml", **{"rolling.flattening": 0.5})
    assert e.value.key == "rolling.flattening"
    with pytest.raises(softway.ScenarioError, match=r"^<dict>: .*`bar\.elements`") as e:
        softway.Scenario({"kind": "bar_impact", "time": {"h": 0.1, "t_end": 1.0},
                          "bar": {**BAR, "elements": 0}})
    assert e.value.key == "bar.elements"
    with pytest.raises(softway.ScenarioError, match="missing field `gap`") as e:
        softway.Scenario({"kind": "bar_impact", "time": {"h": 0.1, "t_end": 1.0},
                          "bar": {k: v for k, v in BAR.items() if k != "gap"}})
    assert e.value.key == "bar.gap"
    with pytest.raises(softway.ScenarioError, match=r"^<string>: line 3.*unknown field `lenght`"):
        softway.Scenario('kind = "bar_impact"\n[bar]\nlenght = 1.0\n')
    missing = tmp_path / "nowhere.toml"
    o = cli("run", missing)
    with pytest.raises(softway.ScenarioError) as e:
        softway.Scenario(missing)
    assert str(e.value) == o.stderr.strip().removeprefix("softway: error: ")


def test_keyboard_interrupt_stops_the_run_within_a_second(monkeypatch):
    """Ctrl-C (as _thread.interrupt_main delivers it: SIGINT's flag) once the
    mesh-converged wheel (6-10 s) has run 2,000 steps: RunInterrupted, a KeyboardInterrupt,
    within a second, with the steps computed so far marked as interrupted. The signal is
    sent from the progress callback, so that it falls in the time loop whatever the load."""
    fired = {}

    def progress(self, label, done, total):
        if done >= 2000 and "t" not in fired:
            fired["t"] = time.perf_counter()
            _thread.interrupt_main()

    monkeypatch.setattr(softway._Bar, "__call__", progress)
    with pytest.raises(KeyboardInterrupt) as e:
        softway.run(SCENARIOS / "wheel.toml", progress=True)
    stopped = time.perf_counter()
    assert isinstance(e.value, softway.RunInterrupted)
    assert stopped - fired["t"] < 1.0, stopped - fired["t"]
    r = e.value.result
    assert r.interrupted and r.summary["interrupted"] is True
    full_steps = round((5e-3 + 5 * 2 * np.pi / 300.0) / 2e-6)
    assert 2000 <= r.summary["steps"] < full_steps
    assert 0 < r.history.sizes["time"] < full_steps // 5


def test_progress_bar_follows_the_run(capsys, one_turn):
    softway.run(one_turn, progress=True)
    err = capsys.readouterr().err
    assert "step" in err and "%" in err
    softway.run(one_turn, progress=False)
    assert capsys.readouterr().err == ""


def test_sweep_on_two_dask_workers_equals_serial_and_the_cli(tmp_path, one_turn, dask_executor):
    grid = {"rolling.omega": SPEEDS}
    hist = ["contact_force_N"]
    on_dask = softway.sweep(one_turn, grid, executor=dask_executor, histories=hist,
                            out=tmp_path / "dask", progress=False)
    serial = softway.sweep(one_turn, grid, executor="serial", histories=hist, progress=False)
    xr.testing.assert_identical(on_dask, serial)
    for name in on_dask.data_vars:
        a, b = on_dask[name].values, serial[name].values
        if a.dtype.kind == "f":
            assert a.tobytes() == b.tobytes(), name
    assert list(on_dask["rolling.omega"].values) == SPEEDS
    assert (on_dask["error"] == "").all()
    # The NetCDF written reads back the same.
    back = xr.open_dataset(tmp_path / "dask/sweep.nc").load()
    for name in ("mean_contact_force", "max_contact_force", "contact_force_N"):
        assert back[name].values.tobytes() == on_dask[name].values.tobytes()
    # Each point's folder, written by its worker: the command line's files and point.nc.
    p = tmp_path / "dask/rolling.omega=300.0"
    assert (p / "summary.json").is_file() and (p / "point.nc").is_file()
    # The same numbers as `softway sweep` over the same values.
    o = cli("sweep", one_turn, "--set", "rolling.omega=" + ",".join(map(str, SPEEDS)),
            "--out", tmp_path / "cli", "--jobs", "2")
    assert o.returncode == 0, o.stderr
    for w in SPEEDS:
        want = json.loads((tmp_path / f"cli/rolling.omega={w}/summary.json").read_text())
        got = json.loads(str(on_dask["summary_json"].sel({"rolling.omega": w}).item()))
        assert without_timings(got) == without_timings(want), w
        for k, v in want.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool) and k not in softway.TIMING_KEYS:
                x = float(on_dask[k].sel({"rolling.omega": w}))
                assert np.float64(x).tobytes() == np.float64(v).tobytes(), (w, k)
    # The history gathered is the point's own.
    r = softway.run(one_turn, progress=False, **{"rolling.omega": 350.0})
    f = on_dask["contact_force_N"].sel({"rolling.omega": 350.0}).values
    n = r.history.sizes["time"]
    assert f[:n].tobytes() == r.history["contact_force_N"].values.tobytes()
    assert np.isnan(f[n:]).all()


def test_a_failing_point_is_reported_and_the_others_kept(one_turn, dask_executor, tmp_path):
    """A point whose run fails where it runs (its folder cannot be written: a file stands
    where `out/<key>=<value>` goes) is reported, the others kept. (A value the validation
    refuses is refused before any point runs: test_issue_48_sweeps.py.) The sweep claims
    `out` empty before any point is sent, so the file is put in the way as the point is
    submitted, by an executor around the Dask one."""
    from concurrent.futures import Executor

    class InTheWay(Executor):
        def submit(self, fn, *args, **kwargs):
            point, folder = args[2], args[4]
            if point.get("rolling.omega") == 300.0:
                Path(folder).write_text("a file where the point's folder goes")
            return dask_executor.submit(fn, *args, **kwargs)

    speeds = [250.0, 300.0, 350.0, 400.0]
    out = tmp_path / "sweep"
    with pytest.warns(RuntimeWarning, match=r"rolling\.omega.*300\.0.*failed"):
        ds = softway.sweep(one_turn, {"rolling.omega": speeds}, executor=InTheWay(),
                           out=out, progress=False)
    err = ds["error"].values
    assert "RunError" in err[1] and "rolling.omega=300.0" in err[1], err[1]
    assert list(err[[0, 2, 3]]) == ["", "", ""]
    assert np.isnan(ds["mean_contact_force"].values[1])
    assert np.all(ds["mean_contact_force"].values[[0, 2, 3]] > 5e5)
    assert ds.attrs["softway_failed_points"] == 1
    # The status column of `softway sweep`'s sweep.csv, the same words.
    st = ds["status"].values
    assert list(st[[0, 2, 3]]) == ["complete"] * 3
    assert st[1].startswith("failed: RunError") and "\n" not in st[1]


def test_grid_product_and_zip():
    bar = {"kind": "bar_impact", "time": {"h": 0.1, "t_end": 2.0}, "bar": BAR}
    ds = softway.sweep(bar, {"bar.speed": [0.5, 1.0, 2.0], "bar.elements": [8, 16]},
                       executor="serial", progress=False)
    assert ds["energy_initial"].dims == ("bar.speed", "bar.elements")
    # The initial kinetic energy is m v^2 / 2 with m = rho_a L = 1 kg, whatever the mesh.
    e = ds["energy_initial"].values
    assert np.allclose(e, 0.5 * np.array([0.5, 1.0, 2.0])[:, None] ** 2 * np.ones((1, 2)))
    z = softway.sweep(bar, {"bar.speed": [0.5, 2.0], "bar.elements": [8, 16]}, mode="zip",
                      executor="serial", progress=False)
    assert z["energy_initial"].dims == ("point",)
    assert z["energy_initial"].values.tolist() == [e[0, 0], e[2, 1]]
    # A key with one value is set at every point of a zip, as `softway sweep --grid zip`
    # does (the grid is the core's): two points at 1 m/s, 0.5 J each.
    b = softway.sweep(bar, {"bar.speed": [1.0], "bar.elements": [8, 16]}, mode="zip",
                      executor="serial", progress=False)
    assert b["bar.speed"].values.tolist() == [1.0, 1.0]
    assert b["bar.elements"].values.tolist() == [8, 16]
    assert np.allclose(b["energy_initial"].values, [0.5, 0.5])
    with pytest.raises(ValueError, match="same length"):
        softway.sweep(bar, {"bar.speed": [1.0, 2.0], "bar.elements": [8, 16, 32]},
                      mode="zip", executor="serial")


def test_the_default_executor_is_a_local_dask_cluster():
    """executor=None: a LocalCluster of processes, started and closed by the sweep. The
    bar's impact comes at the first step past gap / speed (h = 0.01 s)."""
    bar = {"kind": "bar_impact", "time": {"h": 0.01, "t_end": 2.0}, "bar": BAR}
    speeds = [0.5, 1.0, 1.5]
    ds = softway.sweep(bar, {"bar.speed": speeds}, progress=False)
    serial = softway.sweep(bar, {"bar.speed": speeds}, executor="serial", progress=False)
    xr.testing.assert_identical(ds, serial)
    for v, t in zip(speeds, ds["impact_time"].values):
        assert 0.5 / v <= t < 0.5 / v + 0.01 + 1e-12


def test_a_path_with_an_equals_sign_is_a_path(tmp_path, one_turn):
    d = tmp_path / "rolling.omega=300"
    d.mkdir()
    (d / "s.toml").write_text(one_turn.read_text())
    assert softway.Scenario(str(d / "s.toml")).path == str(d / "s.toml")


def test_scenario_from_dict_text_and_file_run_the_same(one_turn):
    text = one_turn.read_text()
    import tomllib

    as_dict = tomllib.loads(text)
    a = softway.Scenario(one_turn).with_values(**{"rolling.turns": 1, "wheel.rings": 4})
    b = softway.Scenario(as_dict).with_values(rolling__turns=1, wheel__rings=4)
    c = softway.Scenario(text).with_values(**{"wheel.rings": 4})
    ra, rb, rc = (softway.run(s, progress=False) for s in (a, b, c))
    assert without_timings(ra.summary) | {"scenario_sha256": ""} == without_timings(rb.summary) | {"scenario_sha256": ""}
    assert ra.history["contact_force_N"].values.tobytes() == rc.history["contact_force_N"].values.tobytes()


def test_help_reads_well():
    for f in (softway.run, softway.sweep, softway.Scenario, softway.Result):
        doc = f.__doc__ or ""
        assert len(doc) > 200, f
    assert "KeyboardInterrupt" in softway.run.__doc__
    assert "client.get_executor()" in softway.sweep.__doc__


def test_a_rail_irregularity_as_an_array_is_the_measured_profiles_run(tmp_path):
    """The wheel on the track over a rail roughness given as a numpy array: the same bits as
    the command line over the same points written as a CSV (`[irregularity] type =
    "measured"`), and the roughness felt (the force differs from the smooth rail's)."""
    sc = softway.Scenario(SCENARIOS / "track.toml").with_values(
        **{
            "vehicle.travel_bays": 2,
            "vehicle.settle_bays": 2,
            "vehicle.wheel_rim_nodes": 180,
        }
    )
    x = np.linspace(0.0, 3.0, 3001)
    profile = np.c_[x, 20e-6 * np.sin(2.0 * np.pi * x / 0.3)]
    rough = softway.run(sc, progress=False, irregularity=profile)
    smooth = softway.run(sc, progress=False)
    f_rough = rough.history["contact_force_N"].values
    f_smooth = smooth.history["contact_force_N"].values
    assert np.max(np.abs(f_rough - f_smooth)) > 1e3
    assert float(rough.history["irregularity_m"].max()) == pytest.approx(20e-6, rel=1e-3)
    # The command line over the same profile as a file.
    np.savetxt(
        tmp_path / "rough.csv", profile, delimiter=",", header="x_m,r_m", comments="", fmt="%.17g"
    )
    text = sc.with_values(
        **{"irregularity.type": "measured", "irregularity.file": str(tmp_path / "rough.csv")}
    ).text
    (tmp_path / "rough.toml").write_text(text)
    out = tmp_path / "out"
    r = cli("run", tmp_path / "rough.toml", "--quiet", "--out", out)
    assert r.returncode == 0, r.stderr
    from_cli = json.loads((out / "summary.json").read_text())
    assert without_timings(from_cli["runs"][0]) == without_timings(rough.summary["runs"][0])
    with pytest.raises(ValueError, match="shape"):
        softway.run(sc, progress=False, irregularity=np.zeros(5))


def test_the_sweep_table_and_its_ladder_as_the_command_line_reads_them():
    """``[sweep]`` with ``ladder``: the key and values of each, as ``softway sweep`` runs
    their product; a ladder of one rung is refused on the key at fault."""
    sc = softway.Scenario(SCENARIOS / "creep-curve-coupled.toml")
    key, values = sc.sweep
    assert key == "rolling.creepage" and len(values) >= 3
    assert sc.sweep_ladder == ("wheel.zone_rim_nodes", ["4608", "9216", "18432"])
    assert softway.Scenario(SCENARIOS / "creep-curve.toml").sweep_ladder is None
    assert sc.sweep_ladder_with == []
    kalker = softway.Scenario(SCENARIOS / "rolling3d-kalker.toml")
    assert kalker.sweep_ladder == ("wheel.zone_sectors", ["768", "1088", "1536"])
    assert kalker.sweep_ladder_with == [
        ("wheel.mesh", ["[4, 48, 2]", "[4, 68, 2]", "[4, 48, 2]"])
    ]
    text = (SCENARIOS / "creep-curve-coupled.toml").read_text().replace(
        "values = [4608, 9216, 18432]", "values = [4608]"
    )
    with pytest.raises(softway.ScenarioError) as e:
        softway.Scenario(text)
    assert e.value.key == "sweep.ladder.values"


def test_save_keeps_the_command_lines_folder_rules(one_turn, tmp_path):
    """``Result.save`` writes as ``softway run`` does: a folder of the user's files (one
    holding a ``summary.json`` among them) is refused and left as it was, ``force=True``
    replaces it, and the folder saved is marked as softway's, so saving again replaces it
    without ``force``; the command line then replaces it as its own."""
    r = softway.run(str(one_turn), progress=False)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "summary.json").write_text('{"mine": true}')
    (mine / "notes.txt").write_text("my notes")
    with pytest.raises(softway.RunError, match="--force"):
        r.save(mine)
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt", "summary.json"]
    assert (mine / "notes.txt").read_text() == "my notes"
    files = r.save(mine, force=True)
    assert (mine / ".softway").is_file() and not (mine / "notes.txt").exists()
    assert {f.name for f in files} >= {"history.csv", "summary.json"}
    r.save(mine)
    o = cli("run", one_turn, "--out", mine, "--quiet")
    assert o.returncode == 0, o.stderr
