"""Growth studies over a parameter grid (the growth study's passes at several speeds, ...),
mapped on any ``concurrent.futures.Executor`` as :func:`softway.sweep` maps runs, gathered
into one xarray Dataset."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import warnings
from concurrent.futures import Executor
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional

import numpy as np

from ._scenario import Scenario, ScenarioLike, as_scenario
from ._sweep import (
    _default_cluster,
    _gather,
    _Interrupted,
    _is_number,
    _points,
    _not_run,
    _progress,
    _stopped,
    SweepInterrupted,
    key_attrs,
    need_netcdf,
)
from . import _native


def _is_timing(name: str) -> bool:
    """A column of ``passes.csv`` that measures the machine (``wall_s``, ``build_s``,
    ``loop_s``, ``wear_bookkeeping_s``): the only ones whose unit is s."""
    return name.endswith("_s")


def _without_timings(summary: dict) -> dict:
    s = dict(summary)
    s.pop("mean_pass_wall_s", None)
    if isinstance(s.get("last_pass"), list):
        s["last_pass"] = [kv for kv in s["last_pass"] if not _is_timing(kv[0])]
    return s


def _nan(x: Any) -> float:
    return float("nan") if x is None else float(x)


def grow_point(
    text: str,
    path: str,
    point: dict[str, Any],
    passes: Optional[int],
    folder: Optional[str],
    resume: bool,
) -> dict[str, Any]:
    """One point of a growth sweep, where the executor runs it: the scenario text with the
    point's values set, its growth study run on one thread into ``folder`` (its files and
    checkpoint; with ``resume`` and a checkpoint there, the study goes on from it; None: a
    temporary folder, removed). Returns the summary (timings left out), the per-pass
    scalars, the band table and the error message if the point failed (a value refused, a
    pass failed, Ctrl-C on the worker: the finished passes stay in the checkpoint); never
    raises."""
    from . import GrowthInterrupted, grow

    out: dict[str, Any] = {"point": point, "error": None, "summary": None}
    tmp = None
    try:
        if folder is None:
            tmp = folder = tempfile.mkdtemp(prefix="softway-grow-")
        go_on = resume and (Path(folder) / "checkpoint.json").is_file()
        sc = Scenario(text, path=path).with_values(**point)
        try:
            g = grow(sc, passes=passes, out=folder, resume=go_on, progress=False, threads=1)
        except GrowthInterrupted as e:  # the finished passes are in the checkpoint
            out["interrupted"] = True
            raise RuntimeError(
                f"interrupted after {e.result.summary['passes']} finished passes "
                f"(resume=True goes on from {folder})"
            ) from None
        out["interrupted"] = g.interrupted
        out["summary"] = _without_timings(g.summary)
        p = g.passes
        out["passes"] = {
            name: (np.asarray(p[name].values), p[name].attrs.get("units", ""))
            for name in p.data_vars
            if not _is_timing(name)
        }
        b = g.bands
        out["bands"] = {
            "wavelength": np.asarray(b["wavelength"].values),
            "level_db": np.asarray(b["level_db"].values),
            "rate_db_per_1e5": np.asarray(b["rate_db_per_1e5"].values),
            "frequency_hz": np.asarray(b["frequency_hz"].values),
        }
    except BaseException as e:  # a failed point is reported, the others go on
        if isinstance(e, KeyboardInterrupt):
            raise
        out["error"] = f"{type(e).__name__}: {e}"
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    return out


def grow_sweep(
    scenario: ScenarioLike,
    grid: Mapping[str, Iterable[Any]],
    *,
    passes: Optional[int] = None,
    grid_mode: str = "product",
    executor: Executor | str | None = None,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
    progress: bool = True,
):
    """Runs a growth study (:func:`grow`) at every point of a grid (e.g. the growth of a
    wheel's polygon at several speeds) and gathers the results into one Dataset.

    Args:
        scenario: a :class:`Scenario` with ``[growth]`` and ``[wear]`` tables (e.g.
            ``scenarios/polygon.toml``): a path, TOML text or a dict.
        grid: dotted key -> values, e.g. ``{"rolling.omega": [250.0, 300.0]}``.
        passes: simulated passes of each study (None: the scenario's ``growth.passes``).
        grid_mode: ``"product"`` (every combination; one dimension per key) or ``"zip"``
            (the lists side by side; one dimension ``point``).
        executor: where the studies run, as for :func:`sweep`: any
            ``concurrent.futures.Executor`` (a Dask cluster's ``client.get_executor()``, a
            ``ProcessPoolExecutor``, ...); None (the default): a
            ``dask.distributed.LocalCluster`` of processes with one thread each, as many as
            the points or the cores, closed at the end (needs ``softway[dask]``);
            ``"serial"``: one study after another in this process.
        out: a folder: each point's study (the files of ``softway grow`` and its
            checkpoint) in ``out/<key>=<value>/``, written by the worker that ran it, and
            the gathered Dataset as ``out/grow_sweep.nc`` (NetCDF: needs
            ``softway[netcdf]``). None: each study in a temporary
            folder on its worker, removed once its numbers are gathered.
        resume: a point whose folder under ``out`` holds a checkpoint goes on from it (to
            ``passes`` in all; a study already there is only read back): a failed or
            interrupted point, or more passes for all, without rerunning what is done;
            the same bits as studies run without a stop.
        progress: a tqdm.auto bar over the points.

    Returns:
        ``xarray.Dataset`` indexed by the grid's keys: the per-pass scalars of
        ``passes.csv`` over ``pass`` (``rms_m``, ``uniform_loss_m``, ``mean_force_n``, ...;
        the wall-clock columns left out), the band levels ``level_db`` over
        (``after_passes``, ``wavelength``), the growth rates ``rate_db_per_1e5`` and the
        bands' frequencies ``band_frequency_hz`` over ``wavelength``, the fastest band's
        ``fastest_band_centre_wavelength_m`` and ``fastest_band_frequency_hz`` (and its
        rate; likewise ``fastest_order_*``), every other number of the summaries
        (``rms_final_m``, ``speed_m_s``, ...), ``error`` (a failed point's message, ""
        for the others, whose values are kept; NaN in a failed point's numbers),
        ``interrupted`` and ``summary_json``. Only these numbers travel back from the
        workers. A failed point is also reported by a warning. The Dataset is the same
        bits whatever the executor, and each point's numbers those of :func:`grow` with
        the point's values as overrides.
    """
    if grid_mode not in ("product", "zip"):
        raise ValueError(f"grid_mode={grid_mode!r}: 'product' or 'zip'")
    sc = as_scenario(scenario)
    # The grid and every point's values checked by the engine before any study runs.
    pts, values, dirs = _points(grid, grid_mode, sc)
    if passes is not None and (isinstance(passes, bool) or int(passes) != passes or passes < 1):
        raise ValueError(f"passes: a whole number >= 1, not {passes!r}")
    if resume and out is None:
        raise ValueError("resume=True needs out=, the folder of the studies to go on from")
    out_dir = None if out is None else Path(out)
    if out_dir is not None:
        need_netcdf("grow_sweep(out=...) (grow_sweep.nc)")
        out_dir.mkdir(parents=True, exist_ok=True)
    folders = [None if out_dir is None else str(out_dir / d) for d in dirs]
    n_passes = None if passes is None else int(passes)

    cluster = client = None
    if executor is None:
        cluster, client = _default_cluster(len(pts))
        executor = client.get_executor()
    try:
        try:
            if executor == "serial":
                results = []
                try:
                    for p, f in _progress(zip(pts, folders), len(pts), progress, "grow_sweep"):
                        results.append(grow_point(sc.text, sc.path, p, n_passes, f, resume))
                        if results[-1].get("interrupted"):  # Ctrl-C stopped its study
                            raise KeyboardInterrupt
                except KeyboardInterrupt:
                    results += [_not_run(p) for p in pts[len(results) :]]
                    raise _Interrupted(results) from None
            elif isinstance(executor, Executor):
                futures = []
                try:
                    for p, f in zip(pts, folders):
                        futures.append(
                            executor.submit(grow_point, sc.text, sc.path, p, n_passes, f, resume)
                        )
                except KeyboardInterrupt:
                    raise _Interrupted(_stopped(futures, pts, None)) from None
                results = _gather(futures, pts, progress, "grow_sweep")
            else:
                raise TypeError(
                    f"executor={executor!r}: a concurrent.futures.Executor, None or 'serial'"
                )
        except _Interrupted as e:
            ds = _dataset([_as_failed(r) for r in e.results], pts, values, grid_mode)
            if out_dir is not None:
                ds.to_netcdf(out_dir / "grow_sweep.nc")
            raise SweepInterrupted(ds) from None
    finally:
        if client is not None:
            client.close()
            cluster.close()

    ds = _dataset(results, pts, values, grid_mode)
    for r in results:
        if r["error"]:
            warnings.warn(
                f"grow_sweep point {r['point']} failed: {r['error']}", RuntimeWarning, stacklevel=2
            )
    if out_dir is not None:
        ds.to_netcdf(out_dir / "grow_sweep.nc")
    return ds


def _as_failed(r: dict) -> dict:
    """A point not run when a growth sweep was stopped, as the Dataset takes it (no
    passes: an error saying so)."""
    if r.get("summary") is None and not r.get("error"):
        return {**r, "error": "not run: the sweep was interrupted"}
    return r


def _flat_numbers(summary: Optional[dict]) -> dict[str, float]:
    """The summary's scalar numbers, and those of its ``fastest_band`` and
    ``fastest_order`` objects prefixed with their name (``null``: NaN)."""
    out: dict[str, float] = {}
    for k, v in (summary or {}).items():
        if _is_number(v):
            out[k] = float(v)
        elif k in ("fastest_band", "fastest_order") and isinstance(v, dict):
            for kk, vv in v.items():
                if _is_number(vv) or vv is None:
                    out[f"{k}_{kk}"] = _nan(vv)
    return out


def _dataset(results, pts, values, mode):
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
    ok = [r for r in results if not r["error"]]
    data: dict[str, Any] = {}

    # The per-pass scalars over `pass`, NaN past a study's last pass.
    m = max((len(v) for r in ok for v, _ in r["passes"].values()), default=0)
    names: list[str] = []
    for r in ok:
        names += [k for k in r["passes"] if k not in names]
    for name in names:
        a = np.full((n, m), np.nan)
        unit = ""
        for i, r in enumerate(results):
            if not r["error"] and name in r["passes"]:
                v, unit = r["passes"][name]
                a[i, : len(v)] = v
        data[name] = ((*dims, "pass"), a.reshape(*shape, m), {"units": unit})
    coords["pass"] = ("pass", np.arange(m), {"long_name": "pass, from 0", "units": "1"})

    # The bands: every band of any point (the points' bands are the same unless the grid
    # changes the profile's length or sampling), in the order first met.
    wl: list[float] = []
    for r in ok:
        wl += [w for w in r["bands"]["wavelength"].tolist() if w not in wl]
    col = {w: j for j, w in enumerate(wl)}
    level = np.full((n, m + 1, len(wl)), np.nan)
    rate = np.full((n, len(wl)), np.nan)
    freq = np.full((n, len(wl)), np.nan)
    for i, r in enumerate(results):
        if r["error"]:
            continue
        b = r["bands"]
        js = [col[w] for w in b["wavelength"].tolist()]
        level[i][: b["level_db"].shape[0]][:, js] = b["level_db"]
        rate[i, js] = b["rate_db_per_1e5"]
        freq[i, js] = b["frequency_hz"]
    data["level_db"] = (
        (*dims, "after_passes", "wavelength"),
        level.reshape(*shape, m + 1, len(wl)),
        {"units": "dB re 1 um", "long_name": "band level"},
    )
    data["rate_db_per_1e5"] = (
        (*dims, "wavelength"),
        rate.reshape(*shape, len(wl)),
        {"units": "dB per 1e5 real passes", "long_name": "growth rate"},
    )
    data["band_frequency_hz"] = (
        (*dims, "wavelength"),
        freq.reshape(*shape, len(wl)),
        {"units": "Hz", "long_name": "band centre frequency (speed / wavelength)"},
    )
    coords["after_passes"] = (
        "after_passes",
        np.arange(m + 1),
        {"long_name": "passes finished (0: the initial profile)", "units": "1"},
    )
    coords["wavelength"] = (
        "wavelength",
        np.asarray(wl, dtype=float),
        {"units": "m", "long_name": "band centre wavelength"},
    )

    # The summaries' numbers.
    flat = [_flat_numbers(r["summary"]) for r in results]
    scalars: list[str] = []
    for f in flat:
        scalars += [k for k in f if k not in scalars and k not in data]
    for name in scalars:
        a = np.array([f.get(name, np.nan) for f in flat], dtype=float)
        data[name] = (dims, a.reshape(shape), {"units": _unit(name)})
    data["error"] = (
        dims,
        np.asarray([r["error"] or "" for r in results], dtype=object).reshape(shape),
    )
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
    ds = xr.Dataset(data, coords=coords)
    ds.attrs["softway_grid_mode"] = mode
    ds.attrs["softway_failed_points"] = int(sum(1 for r in results if r["error"]))
    return ds


def _unit(name: str) -> str:
    """The unit of a summary's number, as the engine names it (``speed_m_s``: m/s,
    ``rate_db_per_1e5``: dB per 1e5 real passes); ``"1"`` for a count or a ratio."""
    return _native.summary_unit(name) or "1"
