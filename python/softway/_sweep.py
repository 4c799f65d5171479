"""Parameter studies: a scenario over a grid of values, mapped on any
``concurrent.futures.Executor`` (a Dask cluster's ``client.get_executor()``, a process
pool, or in this process), gathered into one xarray Dataset."""

from __future__ import annotations

import contextlib
import json
import os
import time
import uuid
import warnings
from concurrent.futures import Executor
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence

import numpy as np

from . import _native
from ._result import without_timings
from ._scenario import Scenario, ScenarioLike, as_scenario, dotted, toml_literal


class SweepInterrupted(KeyboardInterrupt):
    """A sweep stopped by Ctrl-C (KeyboardInterrupt) in the process that called it. The
    points not started are cancelled; on Dask (the default executor, or a Dask client's
    ``get_executor()``) the points running are told to stop at their next step and come
    back with what they computed; on another executor they run on unseen (a process
    pool's workers get the terminal's Ctrl-C themselves). ``dataset`` holds every point
    finished by then as :func:`sweep` returns it, the others with ``status`` ``"interrupted"``
    (NaN figures, as ``softway sweep`` marks the points it stopped or did not start); with
    ``out=`` it is also written as ``out/sweep.nc``. It is a KeyboardInterrupt, so code
    that does not catch it stops as on any Ctrl-C."""

    def __init__(self, dataset: Any):
        done = int((dataset["status"] == "complete").sum()) if "status" in dataset else 0
        super().__init__(
            f"sweep interrupted with {done} of {dataset['status'].size} points complete; "
            ".dataset holds them"
        )
        self.dataset = dataset

    def __reduce__(self):  # pickled with its dataset (an exception pickles its args)
        return (type(self), (self.dataset,))


class _Interrupted(Exception):
    """The points' results when Ctrl-C stopped the wait for them (finished, stopped and not
    run ones), for :func:`sweep` to raise :class:`SweepInterrupted` with."""

    def __init__(self, results: list[dict]):
        super().__init__("interrupted")
        self.results = results


#: How long an interrupted sweep waits for the points it told to stop (Dask): a run stops
#: at its next step after the worker's next look at the flag (every second).
STOP_WAIT_S = 30.0


def _dask_stop(executor: Any) -> tuple[Optional[str], Optional[Callable[[], None]]]:
    """For a Dask client's executor: the name of a ``distributed.Event`` the points watch
    and the function that sets it (an interrupted sweep tells its running points to stop);
    ``(None, None)`` for other executors."""
    client = getattr(executor, "_client", None)
    if client is None or not type(executor).__module__.startswith("distributed"):
        return None, None
    from distributed import Event

    name = f"softway-sweep-stop-{uuid.uuid4().hex}"
    event = Event(name, client=client)
    return name, event.set


def _stop_flag(name: Optional[str]) -> Optional[Callable[[], bool]]:
    """Where a point runs on a Dask worker: True once the sweep's ``distributed.Event``
    ``name`` is set, looked at once a second at most (a call to the scheduler)."""
    if name is None:
        return None
    from distributed import Event

    event = Event(name)
    last = [0.0]

    def should_stop() -> bool:
        now = time.monotonic()
        if now - last[0] < 1.0:
            return False
        last[0] = now
        try:
            return bool(event.is_set())
        except Exception:  # noqa: BLE001 - the scheduler gone: the sweep is over
            return True

    return should_stop


def run_point(
    text: str,
    path: str,
    point: dict[str, Any],
    histories: Sequence[str],
    folder: Optional[str],
    stop: Optional[str] = None,
) -> dict[str, Any]:
    """One point of a sweep, where the executor runs it: the scenario text with the point's
    values set, run on one thread. Returns the summary (timings left out), the requested
    history columns and the error message if the point failed (its values refused, the run
    failed), never raises. With ``folder`` the point's files are written there: the command
    line's files (``summary.json``, ``history.csv``, plots, VTU) and ``point.nc``, the
    whole history and every field as NetCDF. ``stop``: the name of the sweep's
    ``distributed.Event`` (Dask); once it is set the run stops at its next step and the
    point is ``interrupted`` with what it computed, as on Ctrl-C where it runs."""
    from . import RunInterrupted, _run

    out: dict[str, Any] = {"point": point, "error": None, "summary": None, "histories": {}}
    should_stop = _stop_flag(stop)
    if should_stop is not None and should_stop():  # the sweep was stopped before this point
        return _not_run(point)
    try:
        sc = Scenario(text, path=path).with_values(**point)
        try:
            r = _run(sc, progress=False, threads=1, should_stop=should_stop)
        except RunInterrupted as e:  # Ctrl-C where it runs, or the sweep's stop
            r = e.result
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
            os.makedirs(os.path.dirname(folder) or ".", exist_ok=True)
            # The point's folder is the sweep's own (named by its values inside ``out``):
            # replaced whole, whoever wrote it (a sweep of an older softway left no marker);
            # the current and the home folder are still never replaced.
            r.save(folder, force=True)
            _point_netcdf(r, Path(folder) / "point.nc")
    except BaseException as e:  # a failed point is reported, the others go on
        if isinstance(e, KeyboardInterrupt):
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


def _points(
    grid: Mapping[str, Iterable[Any]], mode: str, sc: Scenario
) -> tuple[list[dict], dict, list[str]]:
    """The points of ``grid`` (dotted key -> values) in ``mode``, every one checked by the
    engine before any runs, as ``softway sweep`` checks them: the grid (each key once,
    with values; a zip's lists of one length, a single value broadcast), each point's
    values set into the scenario and validated (a refused value raises
    :class:`ScenarioError` naming its dotted key), no point twice. Returns the points
    (key -> value, in the keys' order), the values of each key and each point's folder
    name (``key=value,...``, the command line's)."""
    if mode not in ("product", "zip"):
        raise ValueError(f"mode={mode!r}: 'product' or 'zip'")
    if isinstance(grid, (str, bytes)) or not isinstance(grid, Mapping):
        raise TypeError(f"grid: a mapping of dotted keys to values, not {type(grid).__name__}")
    keys = list(grid)
    values = {k: list(grid[k]) for k in keys}
    # Every value written as TOML first (a value that cannot be is a mistake in the call).
    literals = [(dotted(k), [toml_literal(v) for v in values[k]]) for k in keys]
    index, dirs = _native.sweep_points(sc.text, sc.path, literals, mode)
    pts = [{k: values[k][i] for k, i in zip(keys, idx)} for idx in index]
    return pts, values, dirs


def check_histories(sc: Scenario, pts: list[dict], histories: Sequence[str]) -> None:
    """Every name of ``histories`` a column of the history of some point's run, as the
    engine names them (the run built and stopped before its first step); a ValueError
    listing the names otherwise, before any point runs. The first point's names are looked
    at first, the others' only for a name it lacks (a grid may switch a column on)."""
    if not histories:
        return
    missing = list(dict.fromkeys(histories))
    known: list[str] = []
    for p in pts:
        names = _native.history_names(sc.with_values(**p).text, sc.path)
        known += [n for n in names if n not in known]
        missing = [m for m in missing if m not in names]
        if not missing:
            return
    raise ValueError(
        f"histories: {', '.join(repr(m) for m in missing)} not a column of this scenario's "
        f"history; its columns: {', '.join(known)}"
    )


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
    force: bool = False,
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
            ``softway[netcdf]``). The folder is claimed before any point runs, under the
            command line's folder rules: a folder of your own files, or of another
            command's results, is refused unless ``force``; the current, the home and the
            scenario's folder never; an older sweep there is replaced whole.
        force: replace ``out`` even when it holds files softway did not write (or another
            command's results), as ``--force``.
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

    Raises:
        ScenarioError: before any point is sent, the grid or a point's values refused by
            the engine as ``softway sweep`` refuses them (a misspelt key, a value out of
            range at any point, a key or a point given twice); ``key`` is the dotted key.
        ValueError: before any point is sent, a ``histories`` name that is not a column of
            the run's history (the message lists them).
        SweepInterrupted: Ctrl-C (KeyboardInterrupt); ``.dataset`` holds the points
            finished, the others ``interrupted``. On Dask the points running are stopped at
            their next step and those not started are not run; on another executor those
            not started are cancelled.

    Each point runs on one thread (as ``softway sweep`` does); the same values give the
    numbers of ``softway sweep``, bit for bit. Any executor works, a process pool that
    forks included: the engine keeps no thread or lock between calls.
    """

    sc = as_scenario(scenario)
    # Everything checked before any point runs: the grid and every point's values (by the
    # engine, as `softway sweep` checks them), the history names, the extras.
    pts, values, dirs = _points(grid, mode, sc)
    hist = tuple(histories)
    check_histories(sc, pts, hist)
    out_dir = None if out is None else Path(out)
    if out_dir is not None:
        need_netcdf("sweep(out=...) (sweep.nc, point.nc)")
        _native.claim_folder(
            str(out_dir), "sweep", force=force, scenario=None if sc.path is None else str(sc.path)
        )
    folders = [None if out_dir is None else str(out_dir / d) for d in dirs]

    cluster = client = None
    if executor is None:
        cluster, client = _default_cluster(len(pts))
        executor = client.get_executor()
    try:
        try:
            if executor == "serial":
                results = _serial(sc, pts, hist, folders, progress)
            elif isinstance(executor, Executor):
                stop_name, stop = _dask_stop(executor)
                futures = []
                try:
                    for p, f in zip(pts, folders):
                        futures.append(
                            executor.submit(
                                run_point, sc.text, sc.path, p, hist, f, stop_name
                            )
                        )
                except KeyboardInterrupt:
                    raise _Interrupted(_stopped(futures, pts, stop)) from None
                results = _gather(futures, pts, progress, stop=stop)
            else:
                raise TypeError(
                    f"executor={executor!r}: a concurrent.futures.Executor, None or 'serial'"
                )
        except _Interrupted as e:
            ds = _dataset(e.results, pts, values, mode, hist)
            if out_dir is not None:
                ds.to_netcdf(out_dir / "sweep.nc")
            raise SweepInterrupted(ds) from None
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


def _not_run(point: dict) -> dict:
    """A point that did not run (cancelled, or not reached when the sweep was stopped)."""
    return {"point": point, "error": None, "summary": None, "histories": {}, "interrupted": True}


def _serial(sc: Scenario, pts: list[dict], hist: tuple, folders: list, progress: bool) -> list:
    """The points one after another in this process; Ctrl-C stops the point under way at
    its next step (kept, ``interrupted``) and the sweep with it (:class:`_Interrupted`)."""
    results: list[dict] = []
    try:
        for p, f in _progress(zip(pts, folders), len(pts), progress):
            results.append(run_point(sc.text, sc.path, p, hist, f))
            if results[-1].get("interrupted"):
                raise KeyboardInterrupt
    except KeyboardInterrupt:
        results += [_not_run(p) for p in pts[len(results) :]]
        raise _Interrupted(results) from None
    return results


def _progress(it, total: int, show: bool, desc: str = "sweep"):
    if not show:
        return it
    from tqdm.auto import tqdm

    return tqdm(it, total=total, desc=desc, unit="point", leave=False)


def _result(f: Any, p: dict) -> dict:
    """A finished future's result; a future that failed outside the point's function (a
    worker lost, a task that could not be sent) is a failed point like any other."""
    try:
        return f.result()
    except Exception as e:  # noqa: BLE001 - reported as the point's error
        return {"point": p, "error": f"{type(e).__name__}: {e}", "summary": None, "histories": {}}


def _stopped(futures: list, pts: list[dict], stop: Optional[Callable[[], None]]) -> list[dict]:
    """After Ctrl-C: on Dask (``stop``) every point told to stop and waited for (at most
    :data:`STOP_WAIT_S`): those running stop at their next step and come back with what
    they computed, those not started come back at once without running; on another
    executor the points not started are cancelled. Any point not back by then is
    cancelled. Returns the results of the finished points; the others are not run
    (``interrupted``)."""
    from concurrent.futures import wait

    if stop is not None:
        try:
            stop()
        except Exception:  # noqa: BLE001 - the scheduler gone: nothing runs any more
            stop = None
    if stop is not None:
        with contextlib.suppress(KeyboardInterrupt):  # a second Ctrl-C: wait no longer
            wait(futures, timeout=STOP_WAIT_S)
    for f in futures:
        f.cancel()
    out = []
    for i, p in enumerate(pts):
        f = futures[i] if i < len(futures) else None
        if f is not None and f.done() and not f.cancelled():
            out.append(_result(f, p))
        else:
            out.append(_not_run(p))
    return out


def _gather(
    futures: list,
    pts: list[dict],
    show: bool,
    desc: str = "sweep",
    stop: Optional[Callable[[], None]] = None,
) -> list[dict]:
    """The futures' results in submission order, waiting with a bar over completions. On
    Ctrl-C (KeyboardInterrupt) the points not started are cancelled and those running
    told to stop (``stop``), and :class:`_Interrupted` carries what finished
    (:func:`_stopped`)."""
    from concurrent.futures import as_completed

    try:
        for _ in _progress(as_completed(futures), len(futures), show, desc):
            pass
    except KeyboardInterrupt:
        raise _Interrupted(_stopped(futures, pts, stop)) from None
    return [_result(f, p) for f, p in zip(futures, pts)]


def _dataset(results, pts, values, mode, hist):
    import xarray as xr

    keys = list(values)
    if mode == "product":
        dims = keys
        shape = tuple(len(values[k]) for k in keys)
        coords = {k: (k, np.asarray(values[k]), key_attrs(k)) for k in keys}
    else:
        dims = ["point"]
        shape = (len(pts),)
        # Each point's own value (a key with one value broadcast to every point).
        coords = {k: ("point", np.asarray([p[k] for p in pts]), key_attrs(k)) for k in keys}
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
    for name in names:
        unit = _native.summary_unit(name)
        if unit is not None:
            ds[name].attrs["units"] = unit
    ds.attrs["softway_grid_mode"] = mode
    ds.attrs["softway_failed_points"] = int(sum(1 for r in results if r["error"]))
    return ds


def key_attrs(key: str) -> dict[str, str]:
    """A grid coordinate's attributes: its unit as ``softway sweep``'s table gives it
    (``rolling.omega``: rad/s; the engine's list, or the unit the key's name carries),
    ``"1"`` for a key without one; ``long_name`` the dotted key."""
    unit = _native.key_unit(dotted(key))
    return {"units": "1" if unit is None else unit, "long_name": dotted(key)}


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
