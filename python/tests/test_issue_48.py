"""Issue 48, "Python, as a notebook user": a Result that pickles (Dask's client.map, process
pools, joblib), writable arrays, the engine's warnings as Python warnings, the dotted key of
a ScenarioError, 3-vectors for VTK, and dask/netCDF4 as extras."""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import pickle
import subprocess
import sys
import types
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import softway
from softway._result import _vtk_array, without_timings
from test_softway import BAR, ROOT, SCENARIOS

#: The paper's bar (Fig. 8) as a dict: a run of a few milliseconds.
BAR_SCENARIO = {"kind": "bar_impact", "time": {"h": 0.1, "t_end": 1.0}, "bar": BAR}


@pytest.fixture(scope="module")
def short_wheel() -> softway.Result:
    """The paper's wheel (its 12-ring mesh) rolling one turn: history, contact nodes,
    fields (velocity snapshots, turn averages) and warnings (its 72-node rim is coarse for
    Hertz's patch: warned about at every speed), in about a second."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", softway.SoftwayWarning)
        return softway.run(
            SCENARIOS / "wheel-paper-mesh.toml",
            progress=False,
            **{"rolling.turns": 1, "output.plots": False},
        )


def assert_same_result(a: softway.Result, b: softway.Result) -> None:
    assert a.kind == b.kind
    assert a.summary == b.summary
    assert a.lines == b.lines and a.warnings == b.warnings
    assert a.interrupted == b.interrupted
    xr.testing.assert_identical(a.history, b.history)
    for name in ("contact_nodes", "rim_profile"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            pd.testing.assert_frame_equal(x, y)
            assert x.attrs == y.attrs
    if a.traction_history is None:
        assert b.traction_history is None
    else:
        xr.testing.assert_identical(a.traction_history, b.traction_history)
    fa, fb = a.fields, b.fields
    assert (fa.points is None) == (fb.points is None)
    if fa.points is not None:
        np.testing.assert_array_equal(fa.points, fb.points)
        np.testing.assert_array_equal(fa.cells, fb.cells)
        assert fa.cell_type == fb.cell_type
    assert [f.name for f in fa.frames] == [f.name for f in fb.frames]
    for x, y in zip(fa.frames, fb.frames):
        assert x.time == y.time
        assert x.point_data.keys() == y.point_data.keys()
        for k in x.point_data:
            np.testing.assert_array_equal(x.point_data[k], y.point_data[k])
        for k in x.cell_data:
            np.testing.assert_array_equal(x.cell_data[k], y.cell_data[k])


def test_issue_48_a_result_pickles_with_its_tables_and_fields(short_wheel, tmp_path):
    r = short_wheel
    assert r.contact_nodes is not None and len(r.fields.frames) > 0
    copy = pickle.loads(pickle.dumps(r))
    assert isinstance(copy, softway.Result)
    assert_same_result(copy, r)
    assert "history rows" in repr(copy)
    # save() where it is unpickled writes the files of a save() where it ran, byte for
    # byte, under the command line's folder rules (test_an_unpickled_result_saves_...).
    # RunInterrupted (Ctrl-C in a worker) travels with its result.
    e = pickle.loads(pickle.dumps(softway.RunInterrupted(r)))
    assert isinstance(e, softway.RunInterrupted) and e.result.summary == r.summary
    # The original still saves.
    assert any(p.name == "history.csv" for p in r.save(tmp_path / "orig"))


def test_issue_48_an_unpickled_result_saves_the_command_lines_files(short_wheel, tmp_path):
    """`save()` on a Result unpickled (sent from the process that ran it) writes the files
    `save()` writes where it ran, the same names and bytes (the VTU fields, the tables,
    `summary.json`), marked as softway's; a folder of the user's files is refused unless
    `force=True`, and then replaced whole. Before, it raised RunError ("unpickled")."""
    r = short_wheel
    here = r.save(tmp_path / "here")
    copy = pickle.loads(pickle.dumps(r))
    there = copy.save(tmp_path / "there")
    assert [p.name for p in there] == [p.name for p in here]
    assert any(p.suffix == ".vtu" for p in there) and any(p.name == "summary.json" for p in there)
    for a, b in zip(here, there):
        assert a.read_bytes() == b.read_bytes(), a.name
    assert (tmp_path / "there" / ".softway").is_file()
    assert sorted(p.name for p in (tmp_path / "there").iterdir()) == sorted(
        p.name for p in (tmp_path / "here").iterdir()
    )
    # The folder rules: a folder of the user's files is refused, nothing written in it.
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    with pytest.raises(softway.RunError, match="force"):
        copy.save(mine)
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]
    # force=True replaces it whole; a folder softway wrote is replaced without it.
    copy.save(mine, force=True)
    assert not (mine / "notes.txt").exists() and (mine / "history.csv").is_file()
    again = copy.save(tmp_path / "there")
    assert [p.name for p in again] == [p.name for p in here]
    # An interrupted run's copy marks its folder interrupted, as the command line does.
    e = pickle.loads(pickle.dumps(softway.RunInterrupted(r)))
    e.result.interrupted = True
    e.result.save(tmp_path / "stopped")
    assert "interrupted" in (tmp_path / "stopped" / ".softway").read_text()


def test_issue_48_a_process_pool_returns_a_result():
    """softway.run mapped on a process pool (spawn: a fresh interpreter, as Dask's workers
    and joblib's loky are) returns the Result, its numbers those of a run here."""
    here = softway.run(BAR_SCENARIO, progress=False)
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(1, mp_context=ctx) as pool:
        there = pool.submit(softway.run, BAR_SCENARIO, progress=False).result(timeout=120)
    assert isinstance(there, softway.Result)
    assert without_timings(there.summary) == without_timings(here.summary)
    xr.testing.assert_identical(there.history, here.history)


def test_issue_48_arrays_are_writable(short_wheel):
    r = pickle.loads(pickle.dumps(short_wheel))  # a copy: the fixture stays as it ran
    f = r.history["contact_force_N"].values.copy()
    r.history["contact_force_N"] *= 1e-3
    np.testing.assert_array_equal(r.history["contact_force_N"].values, f * 1e-3)
    fresh = softway.run(BAR_SCENARIO, progress=False)
    for name in fresh.history.data_vars:
        if fresh.history[name].dtype == np.float64:
            assert fresh.history[name].values.flags.writeable, name
    fields = short_wheel.fields
    for a in (fields.points, *(a for fr in fields.frames for a in fr.point_data.values())):
        assert a.flags.writeable
    v = next(fr for fr in fields.frames if "velocity" in fr.point_data).point_data["velocity"]
    v0 = v.copy()
    v[:, 0] += 1.0
    np.testing.assert_array_equal(v[:, 0], v0[:, 0] + 1.0)
    v[:, 0] -= 1.0


def test_issue_48_the_engines_warnings_are_python_warnings():
    with pytest.warns(softway.SoftwayWarning, match="the rim is coarse") as rec:
        r = softway.run(
            SCENARIOS / "wheel-paper-mesh.toml",
            progress=False,
            **{"rolling.turns": 0.005, "rolling.settle_time": 2e-4, "output.plots": False},
        )
    emitted = [str(w.message) for w in rec if issubclass(w.category, softway.SoftwayWarning)]
    assert r.warnings and set(r.warnings) <= set(emitted)
    assert issubclass(softway.SoftwayWarning, UserWarning)
    # Pointed at the caller's line, not at the package's.
    assert all(w.filename == __file__ for w in rec if issubclass(w.category, softway.SoftwayWarning))
    # The validation's warnings too (the command line prints them before the run): a step
    # beyond the central difference's stable one.
    # (8 elements of length 1/8, c = 1: a stable step of 1/8; the run diverges.)
    explicit = {
        **BAR_SCENARIO,
        "time": {"h": 0.2, "t_end": 1.0, "integrator": "central_difference"},
        "contact": {"method": "exact"},
    }
    with pytest.warns(softway.SoftwayWarning, match="exceeds the central difference's stable"):
        with pytest.raises(softway.RunError, match="diverged"):
            softway.run(explicit, progress=False)
    # Filtered as any warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error", softway.SoftwayWarning)
        with pytest.raises(softway.SoftwayWarning):
            softway.run(
                SCENARIOS / "wheel-paper-mesh.toml",
                progress=False,
                **{"rolling.turns": 0.005, "rolling.settle_time": 2e-4, "output.plots": False},
            )


HEAD = 'kind = "bar_impact"\n[time]\nh = 0.1\nt_end = 1.0\n'
BAR_TABLE = "[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n"
RUNS = '[[runs]]\nlabel = "a"\nh = 0.1\n[[runs]]\nlabel = "b"\n'


@pytest.mark.parametrize(
    "text, key",
    [
        ('kind = "bar_impact"\n[bar]\nlenght = 1.0\n', "bar.lenght"),
        (HEAD + BAR_TABLE.replace("length = 1.0", 'length = "x"'), "bar.length"),
        (HEAD + BAR_TABLE.replace("gap = 0.5\n", ""), "bar.gap"),
        (HEAD + BAR_TABLE + "foo = 1\n", "bar.foo"),
        (HEAD.replace("h = 0.1\n", "") + BAR_TABLE + RUNS + "hh = 0.1\n", "runs[1].hh"),
        (HEAD.replace("h = 0.1\n", "") + BAR_TABLE + RUNS + 'h = "x"\n', "runs[1].h"),
        (HEAD.replace("h = 0.1\n", "") + BAR_TABLE + RUNS + "h = -1.0\n", "runs[1].h"),
        (HEAD.replace("h = 0.1\n", "") + BAR_TABLE + RUNS + "h = 0.1\n[runs.time]\nx = 1\n",
         "runs[1].time"),
        ('kind = "bar_impact"\ntime = {h = 0.1, t_end = 1.0}\n'
         "bar = {length = 1.0, ea = 1.0, rho_a = 1.0, speed = 1.0, gap = 0.5, elements = 8, "
         "foo = 1}\n", "bar.foo"),
        (HEAD + "bar.length = 2.0\n" + BAR_TABLE, "time.bar"),
        ('kind = "bar_impact"\n[time.x]\nh = 0.1\n', "time.x"),
    ],
)
def test_issue_48_a_scenario_errors_key_is_the_dotted_key(text, key, tmp_path):
    with pytest.raises(softway.ScenarioError) as e:
        softway.Scenario(text)
    assert e.value.key == key, str(e.value)
    # The message names the same key (the validation's `key`) or the key's own line.
    assert key.rsplit(".", 1)[-1].split("[")[0] in str(e.value)
    # The same from a file.
    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(softway.ScenarioError) as e:
        softway.Scenario(p)
    assert e.value.key == key, str(e.value)


def test_issue_48_vectors_for_vtk_have_three_components(short_wheel, monkeypatch):
    # The helper: 2-vectors (and a bar's 1-component displacement) padded with zeros to 3;
    # scalars and 3-or-more components as they are.
    v = np.arange(8.0).reshape(4, 2)
    p = _vtk_array(v)
    assert p.shape == (4, 3)
    np.testing.assert_array_equal(p[:, :2], v)
    np.testing.assert_array_equal(p[:, 2], 0.0)
    assert _vtk_array(np.ones((4, 1))).shape == (4, 3)
    assert _vtk_array(np.ones(4)).shape == (4,)
    assert _vtk_array(np.ones((4, 3))).shape == (4, 3)
    assert _vtk_array(np.ones((4, 6))).shape == (4, 6)

    # to_pyvista itself, on a stand-in for PyVista (not installed here) that keeps what it
    # is given.
    class Grid:
        def __init__(self, cells, types, points):
            self.cells, self.types, self.points = cells, types, points
            self.point_data, self.cell_data = {}, {}

    fake = types.SimpleNamespace(UnstructuredGrid=Grid, MultiBlock=dict)
    monkeypatch.setitem(sys.modules, "pyvista", fake)
    f = short_wheel.fields
    i = next(i for i, fr in enumerate(f.frames) if "velocity" in fr.point_data)
    grid = f.to_pyvista(i)
    assert grid.points.shape == (f.points.shape[0], 3)
    vel = grid.point_data["velocity"]
    assert vel.shape == (f.points.shape[0], 3)
    np.testing.assert_array_equal(vel[:, :2], f.frames[i].point_data["velocity"])
    np.testing.assert_array_equal(vel[:, 2], 0.0)
    for k, a in grid.point_data.items():
        assert a.ndim == 1 or a.shape[1] >= 3, k
    for k, a in grid.cell_data.items():
        assert a.ndim == 1 or a.shape[1] >= 3, k


def test_issue_48_dask_and_netcdf_are_extras(monkeypatch, tmp_path):
    import tomllib

    project = tomllib.loads((ROOT / "python/pyproject.toml").read_text())["project"]
    deps = " ".join(project["dependencies"]).lower()
    assert "dask" not in deps and "netcdf" not in deps
    extras = project["optional-dependencies"]
    assert any("dask[distributed]" in d for d in extras["dask"])
    assert any(d.lower().startswith("netcdf4") for d in extras["netcdf"])
    assert {"dask", "netcdf"} <= set(extras) and "all" in extras

    # softway.run without them: neither imported (they are not there).
    code = (
        "import sys\n"
        "for m in ('dask', 'distributed', 'netCDF4'):\n"
        "    sys.modules[m] = None\n"
        "import softway\n"
        f"r = softway.run({BAR_SCENARIO!r}, progress=False)\n"
        "print(r.summary['steps'])\n"
    )
    o = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert o.returncode == 0, o.stderr

    # Asking for what needs them: an ImportError naming the extra, before anything runs.
    for m in ("dask", "dask.distributed", "distributed"):
        monkeypatch.setitem(sys.modules, m, None)
    with pytest.raises(ImportError, match=r"pip install 'softway\[dask\]'"):
        softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0]}, progress=False)
    with pytest.raises(ImportError, match=r"pip install 'softway\[dask\]'"):
        softway.grow_sweep(SCENARIOS / "polygon.toml", {"rolling.omega": [300.0]},
                           progress=False)
    # An executor of one's own needs no Dask.
    ds = softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0, 2.0]}, executor="serial",
                       progress=False)
    assert list(ds["status"].values) == ["complete", "complete"]
    monkeypatch.setitem(sys.modules, "netCDF4", None)
    with pytest.raises(ImportError, match=r"pip install 'softway\[netcdf\]'"):
        softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0]}, executor="serial",
                      out=tmp_path / "sw", progress=False)
    assert not (tmp_path / "sw").exists()
    with pytest.raises(ImportError, match=r"pip install 'softway\[netcdf\]'"):
        softway.grow_sweep(SCENARIOS / "polygon.toml", {"rolling.omega": [300.0]},
                           executor="serial", out=tmp_path / "gs", progress=False)
