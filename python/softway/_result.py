"""A run's results in Python: the summary, the history as an xarray Dataset, the contact
nodes as a pandas DataFrame, the fields as numpy arrays (and PyVista meshes)."""

from __future__ import annotations

import functools
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import numpy as np

from . import _native

#: Entries of ``summary.json`` that measure the machine, not the model (they differ from
#: run to run): left out of comparisons and of a sweep's Dataset.
TIMING_KEYS = (
    "wall_time_s",
    "time_per_step_us",
    "time_per_metre_s",
    "peak_rss_mib",
    "peak_rss_scope",
)


def without_timings(summary: Any) -> Any:
    """``summary`` less the :data:`TIMING_KEYS`, at every depth (a bar scenario's runs
    carry their own)."""
    if isinstance(summary, dict):
        return {k: without_timings(v) for k, v in summary.items() if k not in TIMING_KEYS}
    if isinstance(summary, list):
        return [without_timings(v) for v in summary]
    return summary


def _f64(b: Any) -> np.ndarray:
    """The engine's little-endian ``f64`` values as a writable numpy array: a view of the
    ``bytearray`` the engine filled (owned by Python, no further copy), a copy of read-only
    ``bytes``."""
    a = np.frombuffer(b, dtype="<f8")
    return a if a.flags.writeable else a.copy()


def _vtk_array(a: np.ndarray) -> np.ndarray:
    """An array for VTK (PyVista): a vector of fewer than 3 components per point or cell
    (a 2D model's velocity, ``(n, 2)``; a bar's displacement, ``(n, 1)``) padded with
    zeros to 3, VTK's vectors being 3-vectors (glyphs, ``warp_by_vector``, ParaView's
    vector tools); scalars ``(n,)`` and arrays of 3 or more components as they are."""
    a = np.asarray(a)
    if a.ndim == 2 and a.shape[1] < 3:
        out = np.zeros((a.shape[0], 3), dtype=a.dtype)
        out[:, : a.shape[1]] = a
        return out
    return a


def _table_to_dataset(tab: Any):
    """A native table as an ``xarray.Dataset`` over ``time`` (from the ``t_s`` column, unit
    s) or, without one, over ``row``; every column keeps its unit in ``attrs["units"]``;
    the key column (the bar's ``run``) is a string variable along the same dimension."""
    import xarray as xr

    key, cols = tab
    arrays = {name: (unit, _f64(b)) for name, unit, b in cols}
    if "t_s" in arrays:
        dim = "time"
        unit, t = arrays.pop("t_s")
        coords = {"time": ("time", t, {"units": unit, "long_name": "time", "csv_name": "t_s"})}
    else:
        dim, coords = "row", {}
    data = {
        name: (dim, values, {"units": unit, "csv_name": name})
        for name, (unit, values) in arrays.items()
    }
    ds = xr.Dataset(data, coords=coords)
    if key is not None:
        kname, labels, codes = key
        ds[kname] = (dim, np.asarray(labels, dtype=object)[_f64(codes).astype(np.int64)])
        ds = ds[[kname, *arrays]]
    return ds


def _table_to_frame(tab: Any):
    """A native table as a ``pandas.DataFrame`` (the CSV's columns, in order; a key column
    of node indices as integers), units in ``attrs["units"]``."""
    import pandas as pd

    key, cols = tab
    data: dict[str, Any] = {}
    units: dict[str, str] = {}
    if key is not None:
        kname, labels, codes = key
        lab = np.asarray(labels, dtype=object)
        if all(str(x).isdigit() for x in labels):
            lab = np.asarray([int(x) for x in labels], dtype=np.int64)
        data[kname] = lab[_f64(codes).astype(np.int64)]
        units[kname] = "1"
    for name, unit, b in cols:
        data[name] = _f64(b)
        units[name] = unit
    df = pd.DataFrame(data)
    df.attrs["units"] = units
    return df


@dataclass
class FieldFrame:
    """One set of fields on the mesh (one VTU file of the command line)."""

    #: The VTU file's name (e.g. ``velocity_003.vtu``).
    name: str
    #: The instant, s (None for an average over a window, such as the last turn).
    time: Optional[float]
    #: The displacement of every node, m, shape ``(nodes, dim)`` (None if not drawn).
    displacement: Optional[np.ndarray]
    #: Arrays on the nodes by name (unit in the name; ``velocity`` in m/s): shape
    #: ``(nodes,)`` or ``(nodes, components)``.
    point_data: dict[str, np.ndarray] = field(default_factory=dict)
    #: Arrays on the cells by name.
    cell_data: dict[str, np.ndarray] = field(default_factory=dict)


class Fields:
    """The fields of a run on its mesh, as numpy arrays: ``points`` (reference coordinates,
    m, ``(nodes, dim)``), ``cells`` (node indices, ``(cells, nodes per cell)``
    in VTK's node order: ``cell_type`` "line", "triangle", "tetra", "tetra10" or "hexahedron"), ``frames`` (:class:`FieldFrame`). Empty (``points`` None) for a run with no
    fields."""

    def __init__(self, native: Any):
        mesh, frames = native
        self.points: Optional[np.ndarray] = None
        self.cells: Optional[np.ndarray] = None
        self.cell_type: Optional[str] = None
        if mesh is not None:
            dim, coords, kind, per, cells = mesh
            self.points = _f64(coords).reshape(-1, dim)
            self.cells = _f64(cells).astype(np.int64).reshape(-1, per)
            self.cell_type = kind
        self.frames: list[FieldFrame] = []
        n = 0 if self.points is None else self.points.shape[0]
        for name, t, disp, pdata, cdata in frames:

            def arrays(items):
                out = {}
                for aname, comps, b in items:
                    a = _f64(b)
                    out[aname] = a.reshape(-1, comps) if comps > 1 else a
                return out

            d = None if disp is None else _f64(disp).reshape(n, -1)
            self.frames.append(FieldFrame(name, t, d, arrays(pdata), arrays(cdata)))

    def __len__(self) -> int:
        return len(self.frames)

    def __getitem__(self, i: int) -> FieldFrame:
        return self.frames[i]

    def __repr__(self) -> str:
        if self.points is None:
            return "Fields(none)"
        return (
            f"Fields({self.points.shape[0]} nodes, {self.cells.shape[0]} {self.cell_type}s, "
            f"{len(self.frames)} frames: {', '.join(f.name for f in self.frames)})"
        )

    def to_pyvista(self, frame: int | str | None = None):
        """The mesh as a ``pyvista.UnstructuredGrid`` with one frame's arrays (by index or
        file name; the point array ``displacement`` and every 2-component vector, such as
        ``velocity``, as 3-vectors with a zero third component, VTK's convention, for
        glyphs and ``warp_by_vector``), or with ``frame=None`` a ``pyvista.MultiBlock`` of
        every frame. Needs PyVista (``pip install pyvista``, or ``softway[pyvista]``)."""
        try:
            import pyvista as pv
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError(
                "Fields.to_pyvista needs PyVista: pip install pyvista"
            ) from e
        if self.points is None:
            raise ValueError("this run has no fields (no mesh)")
        if frame is None:
            mb = pv.MultiBlock()
            for i, f in enumerate(self.frames):
                mb[f.name] = self.to_pyvista(i)
            return mb
        if isinstance(frame, str):
            matches = [f for f in self.frames if f.name == frame]
            if not matches:
                raise KeyError(f"no frame {frame!r}: {[f.name for f in self.frames]}")
            fr = matches[0]
        else:
            fr = self.frames[frame]
        vtk_type = {"line": 3, "triangle": 5, "tetra": 10, "tetra10": 24, "hexahedron": 12}[
            self.cell_type
        ]
        per = self.cells.shape[1]
        cells = np.hstack([np.full((self.cells.shape[0], 1), per), self.cells]).ravel()
        pts = np.zeros((self.points.shape[0], 3))
        pts[:, : self.points.shape[1]] = self.points
        grid = pv.UnstructuredGrid(
            cells, np.full(self.cells.shape[0], vtk_type, dtype=np.uint8), pts
        )
        if fr.displacement is not None:
            grid.point_data["displacement"] = _vtk_array(fr.displacement)
        for k, v in fr.point_data.items():
            grid.point_data[k] = _vtk_array(v)
        for k, v in fr.cell_data.items():
            grid.cell_data[k] = _vtk_array(v)
        return grid


class Result:
    """The results of :func:`softway.run`, in memory.

    Attributes:
        summary: the key figures, ``summary.json``'s object (units in ``summary["units"]``
            where the model gives them).
        history: an ``xarray.Dataset`` over ``time`` (s), a variable per column of
            ``history.csv`` with its unit in ``attrs["units"]``; ``history.to_pandas()``
            gives a DataFrame. A bar scenario's runs follow each other, told apart by the
            ``run`` variable.
        contact_nodes: the wheel's per-node contact rows (``contact_nodes.csv``) as a
            ``pandas.DataFrame``, or None.
        traction_history: the wheel's traction over time with friction (an
            ``xarray.Dataset``), or None.
        rim_profile: the turn-averaged J2 at the rim nodes (``j2_rim_profile.csv``) as a
            ``pandas.DataFrame``, or None.
        fields: the fields on the mesh (:class:`Fields`: numpy arrays, ``to_pyvista()``).
        interrupted: True when the run was stopped (Ctrl-C) before its end: the results
            hold the steps computed.
        warnings: the run's warnings (also emitted by :func:`softway.run` as
            :class:`softway.SoftwayWarning`).
        lines: the command line's screen summary.

    A Result pickles (``client.map(softway.run, ...)`` on Dask, a process pool, joblib):
    the summary, the tables, the fields, the lines and the warnings go with it, as they are
    (an array changed in place stays changed), and the command line's files as the engine
    writes them (rendered when the Result is pickled), so that :meth:`save` works where it
    is unpickled, the same bytes under the same folder rules.
    """

    #: The tables a pickle carries (the cached properties below).
    _TABLES = ("history", "contact_nodes", "traction_history", "rim_profile")

    def __init__(self, native: Any):
        self._native: Any = native
        self.kind: str = native.kind
        self.summary: dict = json.loads(native.summary_json)
        self.interrupted: bool = native.interrupted
        self.warnings: list[str] = list(native.warnings)
        self.lines: list[str] = list(native.lines)
        self._fields: Optional[Fields] = None

    # The tables are built on first use: the first xarray Dataset or pandas DataFrame of a
    # Python session costs about a second (their lazy imports), which a RunInterrupted
    # raised on Ctrl-C should not wait for.
    @functools.cached_property
    def history(self):
        """The history (``history.csv``): an ``xarray.Dataset`` over ``time``, units in
        ``attrs["units"]``."""
        return _table_to_dataset(self._native.table("history"))

    @functools.cached_property
    def contact_nodes(self):
        """``contact_nodes.csv`` as a ``pandas.DataFrame`` (None when the run has none)."""
        cn = self._native.table("contact_nodes")
        return None if cn is None else _table_to_frame(cn)

    @functools.cached_property
    def traction_history(self):
        """The traction history as an ``xarray.Dataset`` (None when the run has none)."""
        th = self._native.table("traction_history")
        return None if th is None else _table_to_dataset(th)

    @functools.cached_property
    def rim_profile(self):
        """The rim profile as a ``pandas.DataFrame`` (None when the run has none)."""
        rp = self._native.table("rim_profile")
        return None if rp is None else _table_to_frame(rp)

    @property
    def fields(self) -> Fields:
        """The fields on the mesh (built on first use)."""
        if self._fields is None:
            self._fields = Fields(self._native.fields())
        return self._fields

    def save(self, folder: str | os.PathLike[str], force: bool = False) -> list[Path]:
        """Writes the command line's files into ``folder``: the same ``history.csv``,
        ``summary.json``, ``contact_nodes.csv``, VTU and PNG files as ``softway run``
        writes, byte for byte but for the run's timings, under the command line's folder
        rules: the folder is written whole (or not at all) and marked as softway's; a
        folder of other files is refused (``RunError``) unless ``force=True``; the current
        and the home folder are never replaced. Returns the paths."""
        if self._native is None:  # unpickled: the files the engine wrote when pickled
            return [
                Path(p)
                for p in _native.save_files(
                    os.fspath(folder), self._files, self.interrupted, force
                )
            ]
        return [Path(p) for p in self._native.save(os.fspath(folder), force)]

    def __getstate__(self) -> dict[str, Any]:
        """What a pickle carries: every attribute and table (built now if not yet), the
        fields, and the command line's files as the engine writes them (``_files``: name
        and bytes, for :meth:`save` where it is unpickled)."""
        state = {k: v for k, v in self.__dict__.items() if k != "_native"}
        for name in self._TABLES:
            state[name] = getattr(self, name)
        state["_fields"] = self.fields
        if self._native is not None:
            import tempfile

            with tempfile.TemporaryDirectory(prefix="softway-pickle-") as scratch:
                state["_files"] = list(self._native.files(scratch))
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._native = None

    def __repr__(self) -> str:
        state = ", interrupted" if self.interrupted else ""
        return (
            f"Result(kind={self.kind!r}, {self.history.sizes.get('time', 0)} history rows"
            f"{state})"
        )
