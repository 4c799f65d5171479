"""Parameter studies: a scenario over a grid of values, mapped on any
``concurrent.futures.Executor`` (a Dask cluster's ``client.get_executor()``, a process
pool, or in this process), gathered into one xarray Dataset."""

from __future__ import annotations

import json
import os
import warnings
from concurrent.futures import Executor
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional, Sequence

import numpy as np

from . import _native
from ._result import without_timings
from ._scenario import Scenario, ScenarioLike, as_scenario, toml_literal


def _point_dir(point: Mapping[str, Any]) -> str:
    """A point's folder, ``key=value,key=value`` (as ``softway sweep`` names its points)."""
    name = ",".join(f"{k}={toml_literal(v).strip(chr(34))}" for k, v in point.items())
    return name.replace("/", "_").replace("\\", "_")


def run_point(
    text: str,
    path: str,
    point: dict[str, Any],
    histories: Sequence[str],
    folder: Optional[str],
) -> dict[str, Any]:
    """One point of a sweep, where the executor runs it: the scenario text with the point's
    values set, run on one thread. Returns the summary (timings left out), the requested
    history columns and the error message if the point failed (its values refused, the run
    failed), never raises. With ``folder`` the point's files are written there: the command
    line's files (``summary.json``, ``history.csv``, plots, VTU) and ``point.nc``, the
    whole history and every field as NetCDF."""
    from . import run

    out: dict[str, Any] = {"point": point, "error": None, "summary": None, "histories": {}}
    try:
        sc = Scenario(text, path=path).with_values(**point)
        r = run(sc, progress=False, threads=1)
        out["summary"] = without_timings(r.summary)
        out["interrupted"] = r.interrupted
        h = r.history
        out["time"] = np.asarray(h["time"].values)
        for name in histories:
            if name not in h:
                raise KeyError(
                    f"history column {name!r} not in this run's history: {sorted(h.data_vars)}"
                )
            out["histories"][name] = (np.asarray(h[name].values), h[name].attrs.get("units", ""))
        if folder is not None:
            os.makedirs(folder, exist_ok=True)
            # The point's folder is the sweep's own (named by its values inside ``out``):
            # replaced whole, whoever wrote it (a sweep of an older softway left no marker);
            # the current and the home folder are still never replaced.
            r.save(folder, force=True)
            _point_netcdf(r, Path(folder) / "point.nc")
    except BaseException as e:  # a failed point is reported, the others go on
        if isinstance(e, KeyboardInterrupt) and not hasattr(e, "result"):
            raise
        out["error"] = f"{type(e).__name__}: {e}"
    return out


def _point_netcdf(r, path: Path) -> None:
    """The whole history and the fields of a run as one NetCDF file: the history over
    ``time``, the mesh (``node_x``, ``node_y``, ``cells``) and every frame's arrays, named
    ``<frame>_<array>`` (the frame's instant in ``attrs["time_s"]``)."""
    ds = r.history.copy()
    f = r.fields
    if f.points is not None:
        ds = ds.assign_coords(
            node_x=(("node",), f.points[:, 0], {"units": "m"}),
        )
        if f.points.shape[1] > 1:
            ds = ds.assign_coords(node_y=(("node",), f.points[:, 1], {"units": "m"}))
        ds["cells"] = (("cell", "cell_node"), f.cells)
        for fr in f.frames:
            stem = fr.name.rsplit(".", 1)[0]
            attrs = {} if fr.time is None else {"time_s": fr.time}
            if fr.displacement is not None:
                ds[f"{stem}_displacement"] = (
                    ("node", "dim"),
                    fr.displacement,
                    {**attrs, "units": "m"},
                )
            for where, arrays in (("node", fr.point_data), ("cell", fr.cell_data)):
                for k, v in arrays.items():
                    dims = (where,) if v.ndim == 1 else (where, f"{stem}_{k}_component")
                    ds[f"{stem}_{k}"] = (dims, v, attrs)
    ds.attrs["summary_json"] = json.dumps(r.summary)
    ds.to_netcdf(path)


def _points(grid: Mapping[str, Iterable[Any]], mode: str) -> tuple[list[dict], dict]:
    keys = list(grid)
    values = {k: list(grid[k]) for k in keys}
    if not keys:
        raise ValueError("an empty grid: give at least one key and its values")
    for k, v in values.items():
        if not v:
            raise ValueError(f"{k}: no values")
    # The grid is the command line's (softway sweep --grid product|zip): the same points in
    # the same order, a single value broadcast in a zip.
    index = _native.grid_indices([(k, len(v)) for k, v in values.items()], mode)
    pts = [{k: values[k][i] for k, i in zip(keys, idx)} for idx in index]
    return pts, values


def _need(module: str, extra: str, what: str):
    """``module`` imported, or an ImportError naming the extra that installs it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(
            f"{what} needs {module.split('.')[0]}, an optional dependency: "
            f"pip install 'softway[{extra}]'"
        ) from e


def need_netcdf(what: str) -> None:
    """An ImportError naming ``softway[netcdf]`` unless netCDF4 (xarray's NetCDF-4 engine)
    is installed; checked before any point runs."""
    _need("netCDF4", "netcdf", what)


def _default_cluster(n_points: int):
    distributed = _need(
        "dask.distributed",
        "dask",
        "the default executor (a local Dask cluster; or pass executor='serial' or a "
        "concurrent.futures executor)",
    )
    Client, LocalCluster = distributed.Client, distributed.LocalCluster

    cores = os.cpu_count() or 1
    cluster = LocalCluster(
        n_workers=max(1, min(n_points, cores)),
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
    )
    return cluster, Client(cluster)


def sweep(
    scenario: ScenarioLike,
    grid: Mapping[str, Iterable[Any]],
    *,
    executor: Executor | str | None = None,
    mode: str = "product",
    histories: Sequence[str] = (),
    out: str | os.PathLike[str] | None = None,
    progress: bool = True,
):
    """Runs a scenario over a grid of values and gathers the results into one Dataset.

    Args:
        scenario: a :class:`Scenario`, a path, TOML text or a dict.
        grid: dotted key -> values, e.g. ``{"rolling.omega": [250.0, 300.0, 350.0]}``.
        executor: where the points run: any ``concurrent.futures.Executor`` (a Dask
            cluster's ``client.get_executor()``, a ``ProcessPoolExecutor``, ...); None (the
            default): a ``dask.distributed.LocalCluster`` of processes with one thread
            each, as many as the points or the cores, closed at the end (needs
            ``softway[dask]``); ``"serial"``: one point after another in this process.
        mode: ``"product"`` (every combination; one dimension per key) or ``"zip"`` (the
            lists side by side; one dimension ``point``).
        histories: history columns to gather per point (e.g. ``["contact_force_N"]``), over
            a dimension ``sample`` padded with NaN to the longest, with their times in
            ``history_time``.
        out: a folder: each point's files (the command line's, and ``point.nc`` with the
            whole history and the fields) in ``out/<key>=<value>/``, written by the worker
            that ran it, and the gathered Dataset as ``out/sweep.nc`` (NetCDF: needs
            ``softway[netcdf]``).
        progress: a tqdm.auto bar over the points.

    Returns:
        ``xarray.Dataset`` indexed by the grid: every number of the points' summaries
        (timings left out: the Dataset is the same bits whatever the executor; NaN at a
        point that did not complete, whose numbers are not results), ``status``
        (``"complete"``, ``"interrupted"`` or ``"failed: <message>"``, as the ``status``
        column of ``softway sweep``'s ``sweep.csv``), ``error`` (the message of a failed
        point, "" for the others), ``interrupted``, ``summary_json`` (the whole summary,
        as written, interrupted or not) and the histories asked for. A failed point is
        also reported by a warning.

    Each point runs on one thread (as ``softway sweep`` does); the same values give the
    numbers of ``softway sweep``, bit for bit.
    """

    sc = as_scenario(scenario)
    pts, values = _points(grid, mode)
    # Every value written as TOML before anything runs (a value that cannot be is a
    # mistake in the call, not a failed point).
    for p in pts:
        for v in p.values():
            toml_literal(v)
    out_dir = None if out is None else Path(out)
    if out_dir is not None:
        need_netcdf("sweep(out=...) (sweep.nc, point.nc)")
        out_dir.mkdir(parents=True, exist_ok=True)
    folders = [None if out_dir is None else str(out_dir / _point_dir(p)) for p in pts]
    hist = tuple(histories)

    cluster = client = None
    if executor is None:
        cluster, client = _default_cluster(len(pts))
        executor = client.get_executor()
    try:
        if executor == "serial":
            results = [
                run_point(sc.text, sc.path, p, hist, f)
                for p, f in _progress(zip(pts, folders), len(pts), progress)
            ]
        elif isinstance(executor, Executor):
            futures = [
                executor.submit(run_point, sc.text, sc.path, p, hist, f)
                for p, f in zip(pts, folders)
            ]
            results = _gather(futures, pts, progress)
        else:
            raise TypeError(
                f"executor={executor!r}: a concurrent.futures.Executor, None or 'serial'"
            )
    finally:
        if client is not None:
            client.close()
            cluster.close()

    ds = _dataset(results, pts, values, mode, hist)
    failed = [(r["point"], r["error"]) for r in results if r["error"]]
    for p, e in failed:
        warnings.warn(f"sweep point {p} failed: {e}", RuntimeWarning, stacklevel=2)
    if out_dir is not None:
        ds.to_netcdf(out_dir / "sweep.nc")
    return ds


def _progress(it, total: int, show: bool, desc: str = "sweep"):
    if not show:
        return it
    from tqdm.auto import tqdm

    return tqdm(it, total=total, desc=desc, unit="point", leave=False)


def _gather(futures: list, pts: list[dict], show: bool, desc: str = "sweep") -> list[dict]:
    """The futures' results in submission order, waiting with a bar over completions; a
    future that failed outside :func:`run_point` (a worker lost, a task that could not be
    sent) is a failed point like any other."""
    from concurrent.futures import as_completed

    for _ in _progress(as_completed(futures), len(futures), show, desc):
        pass
    results = []
    for f, p in zip(futures, pts):
        try:
            results.append(f.result())
        except Exception as e:  # noqa: BLE001 - reported as the point's error
            results.append(
                {"point": p, "error": f"{type(e).__name__}: {e}", "summary": None, "histories": {}}
            )
    return results


def _dataset(results, pts, values, mode, hist):
    import xarray as xr

    keys = list(values)
    if mode == "product":
        dims = keys
        shape = tuple(len(values[k]) for k in keys)
        coords = {k: (k, np.asarray(values[k])) for k in keys}
    else:
        dims = ["point"]
        shape = (len(pts),)
        # Each point's own value (a key with one value broadcast to every point).
        coords = {k: ("point", np.asarray([p[k] for p in pts])) for k in keys}
    n = len(pts)
    status = [_status(r) for r in results]
    # Every scalar number of any summary, in the order first met.
    names: list[str] = []
    for r in results:
        for k, v in (r["summary"] or {}).items():
            if _is_number(v) and k not in names:
                names.append(k)
    data: dict[str, Any] = {}
    for name in names:
        a = np.full(n, np.nan)
        for i, r in enumerate(results):
            v = (r["summary"] or {}).get(name)
            if _is_number(v) and status[i] == "complete":
                a[i] = float(v)
        data[name] = (dims, a.reshape(shape))
    data["status"] = (dims, np.asarray(status, dtype=object).reshape(shape))
    data["error"] = (dims, np.asarray([r["error"] or "" for r in results], dtype=object).reshape(shape))
    data["interrupted"] = (
        dims,
        np.asarray([bool(r.get("interrupted", False)) for r in results]).reshape(shape),
    )
    data["summary_json"] = (
        dims,
        np.asarray(
            [json.dumps(r["summary"], sort_keys=True) if r["summary"] else "" for r in results],
            dtype=object,
        ).reshape(shape),
    )
    if hist:
        m = max((len(r.get("time", ())) for r in results), default=0)
        t = np.full((n, m), np.nan)
        for i, r in enumerate(results):
            if "time" in r:
                t[i, : len(r["time"])] = r["time"]
        data["history_time"] = ((*dims, "sample"), t.reshape(*shape, m), {"units": "s"})
        for name in hist:
            a = np.full((n, m), np.nan)
            unit = ""
            for i, r in enumerate(results):
                if name in r["histories"]:
                    v, unit = r["histories"][name]
                    a[i, : len(v)] = v
            data[name] = ((*dims, "sample"), a.reshape(*shape, m), {"units": unit})
    ds = xr.Dataset(data, coords=coords)
    units = {}
    for r in results:
        if r["summary"] and isinstance(r["summary"].get("units"), dict):
            units = r["summary"]["units"]
            break
    for name in names:
        if name in units:
            ds[name].attrs["units"] = units[name]
    ds.attrs["softway_grid_mode"] = mode
    ds.attrs["softway_failed_points"] = int(sum(1 for r in results if r["error"]))
    return ds


def _status(r: Mapping[str, Any]) -> str:
    """A point's status as ``softway sweep`` writes it: ``complete``, ``interrupted`` or
    ``failed: <message>`` (on one line)."""
    if r.get("error"):
        return "failed: " + " ".join(str(r["error"]).splitlines())
    if r.get("interrupted", False):
        return "interrupted"
    return "complete"


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)
