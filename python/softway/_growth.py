"""A growth study from Python (``softway grow``): wear pass by pass, checkpointed, its
results as xarray Datasets and numpy arrays."""

from __future__ import annotations

import functools
import json
import os
import time
from pathlib import Path
from typing import Any, NamedTuple, Optional, Union

import numpy as np

from . import _native
from ._result import _f64
from ._scenario import ScenarioLike, as_scenario

_AFTER_ATTRS = {"long_name": "passes finished (0: the initial profile)", "units": "1"}


def _unit(name: str) -> str:
    """The unit a column's name carries (the engine's names do: ``mean_force_n`` in N,
    ``contact_stiffness_n_m`` in N/m, ``speed_m_s`` in m/s), as the engine reads it;
    ``"1"`` for a count or a ratio."""
    return _native.summary_unit(name) or "1"


class Profile(NamedTuple):
    """The surface profile of a study (``profile.csv``'s columns), numpy arrays over the
    samples of the rolling coordinate."""

    #: Abscissa of each sample, m.
    x_m: np.ndarray
    #: The initial profile, m (+ = material standing proud).
    z_initial_m: np.ndarray
    #: The profile after the last finished pass, m.
    z_m: np.ndarray
    #: The last pass's smoothed wear (one simulated pass, after the reference's
    #: subtraction), m; zeros before any pass.
    wear_last_pass_m: np.ndarray


class GrowthResult:
    """A growth study's results (:func:`grow`): the numbers of ``softway grow``'s files.

    Attributes:
        summary: ``summary.json`` as a dict (bands, orders, fastest band and order, RMS
            roughness, uniform loss, ...).
        passes: ``passes.csv`` as an ``xarray.Dataset`` over ``pass`` (0 = the first
            pass): ``real_passes``, ``rms_m``, ``uniform_loss_m`` (accumulated),
            ``wall_s`` and the runner's scalars (``mean_force_n``, ...); units in
            ``attrs["units"]``.
        bands: ``bands.csv`` as an ``xarray.Dataset``: ``level_db`` (dB re 1 um) over
            ``after_passes`` (0 = the initial profile, then after each pass) x
            ``wavelength`` (the one-third-octave band's centre wavelength, m), and
            ``rate_db_per_1e5`` over ``wavelength`` (the growth rate, dB per 1e5 real
            passes); coordinates ``frequency_hz`` (V / wavelength), ``first_order`` and
            ``last_order``.
        orders: ``orders.csv`` as an ``xarray.Dataset`` (periodic profiles: the wheel's
            polygon orders; None for a rail): ``amplitude_m`` over ``after_passes`` x
            ``order``, ``rate_db_per_1e5``, ``rate_last_db_per_1e5``.
        profile: :class:`Profile`: ``profile.csv``'s columns as numpy arrays.
        profiles: every profile, initial then after each pass: a numpy array
            ``(passes + 1, samples)``, m, bit for bit the checkpoint's.
        interrupted: True when Ctrl-C stopped the study; the finished passes are kept in
            ``out/checkpoint.json``: ``grow(..., resume=True)`` goes on from them.
        passes_run: passes run by this call (not those resumed from).
        out: the study's folder; files: the files written there.

    A GrowthResult pickles (a process pool, Dask): its numbers go with it (the tables
    built first); :meth:`save` needs the engine's state, which stays in the process that
    ran the study (its checkpoint is in ``out``: ``grow(..., out=out, resume=True)``
    reads it back).
    """

    #: The tables a pickle carries (the cached properties below).
    _TABLES = ("passes", "bands", "orders")

    def __init__(self, native: Any, out: Path):
        self._native = native
        self.out = Path(out)
        self.summary: dict = json.loads(native.summary_json)
        self.lines: list[str] = list(native.lines)
        self.files: list[Path] = [Path(f) for f in native.files]
        self.interrupted: bool = native.interrupted
        self.passes_run: int = native.passes_run
        x0, dx, n, self._periodic, profiles, wear = native.profiles()
        self.profiles: np.ndarray = _f64(profiles).reshape(-1, n)
        self.profile = Profile(
            x_m=x0 + np.arange(n) * dx,
            z_initial_m=self.profiles[0],
            z_m=self.profiles[-1],
            wear_last_pass_m=_f64(wear) if wear is not None else np.zeros(n),
        )

    # The Datasets are built on first use: the first xarray Dataset of a Python session
    # costs about a second (xarray's lazy imports), which GrowthInterrupted raised on
    # Ctrl-C should not wait for.
    @functools.cached_property
    def passes(self):
        import xarray as xr

        cols = [(name, _f64(b)) for name, b in self._native.passes()]
        ds = xr.Dataset(
            {
                name: ("pass", v, {"units": _unit(name), "csv_name": name})
                for name, v in cols[1:]
            },
            coords={
                "pass": (
                    "pass",
                    cols[0][1].astype(np.int64),
                    {"long_name": "pass, from 0", "units": "1"},
                )
            },
        )
        ds["real_passes"].attrs["units"] = "1"
        ds["real_passes"].attrs["long_name"] = "real passes after this pass"
        return ds

    @functools.cached_property
    def bands(self):
        import xarray as xr

        centre, first, last, levels = self._native.bands()
        centre = _f64(centre)
        after = np.arange(self.profiles.shape[0])
        # summary.json's bands are the same bands, in the same order.
        sb = self.summary["bands"]
        assert len(sb) == len(centre)
        rate = np.array([_nan(b["rate_db_per_1e5"]) for b in sb], dtype=float)
        freq = np.array([_nan(b["frequency_hz"]) for b in sb], dtype=float)
        return xr.Dataset(
            {
                "level_db": (
                    ("after_passes", "wavelength"),
                    _f64(levels).reshape(len(after), len(centre)),
                    {"units": "dB re 1 um", "long_name": "band level"},
                ),
                "rate_db_per_1e5": (
                    "wavelength",
                    rate,
                    {"units": "dB per 1e5 real passes", "long_name": "growth rate"},
                ),
            },
            coords={
                "after_passes": ("after_passes", after, _AFTER_ATTRS),
                "wavelength": (
                    "wavelength",
                    centre,
                    {"units": "m", "long_name": "band centre wavelength"},
                ),
                "frequency_hz": ("wavelength", freq, {"units": "Hz"}),
                "first_order": ("wavelength", _f64(first).astype(np.int64)),
                "last_order": ("wavelength", _f64(last).astype(np.int64)),
            },
        )

    @functools.cached_property
    def orders(self):
        if not (self._periodic and self.summary["orders"]):
            return None
        import xarray as xr

        o = self.summary["orders"]
        after = np.arange(self.profiles.shape[0])
        amp = _f64(self._native.orders()).reshape(len(after), -1)
        return xr.Dataset(
            {
                "amplitude_m": (("after_passes", "order"), amp, {"units": "m"}),
                "rate_db_per_1e5": (
                    "order",
                    np.array([_nan(x["rate_db_per_1e5"]) for x in o], dtype=float),
                    {"units": "dB per 1e5 real passes"},
                ),
                "rate_last_db_per_1e5": (
                    "order",
                    np.array([_nan(x["rate_last_db_per_1e5"]) for x in o], dtype=float),
                    {"units": "dB per 1e5 real passes"},
                ),
            },
            coords={
                "after_passes": ("after_passes", after, _AFTER_ATTRS),
                "order": ("order", np.array([x["order"] for x in o], dtype=np.int64)),
                "wavelength_m": (
                    "order",
                    np.array([x["wavelength_m"] for x in o], dtype=float),
                    {"units": "m"},
                ),
            },
        )

    def save(self, folder: Union[str, os.PathLike[str]], force: bool = False) -> list[Path]:
        """Writes this result's files into ``folder``, as ``softway grow`` writes them:
        ``scenario.toml``, ``checkpoint.json`` (a study resumed from ``folder`` goes on
        from this state), ``passes.csv``, ``bands.csv``, ``orders.csv``, ``profile.csv``,
        ``summary.json`` and the plots; the runner's own outputs written at the end of a
        study (the track's prediction) are copied from the study's folder. The study's own
        folder is written in place; another follows the command line's folder rules (a
        folder of other files is refused unless ``force=True``, an older study there is
        replaced whole, the current and the home folder are never replaced). Returns their
        paths."""
        if self._native is None:
            raise _native.RunError(
                "this GrowthResult was unpickled (sent from the process that ran the "
                "study): save() writes the engine's state, which stays in that process; "
                f"the study's files and checkpoint are in {self.out} (grow(..., out=..., "
                "resume=True) reads them back)"
            )
        return [Path(p) for p in self._native.save(str(folder), force)]

    def __getstate__(self) -> dict[str, Any]:
        """What a pickle carries: every attribute and table (built now if not yet); not the
        engine's state (see :meth:`save`)."""
        state = {k: v for k, v in self.__dict__.items() if k != "_native"}
        for name in self._TABLES:
            state[name] = getattr(self, name)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._native = None

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"<GrowthResult {s['passes']} passes ({s['real_passes']:.4g} real), RMS "
            f"{s['rms_initial_m'] * 1e6:.4f} -> {s['rms_final_m'] * 1e6:.4f} um"
            f"{', interrupted' if self.interrupted else ''}, {self.out}>"
        )


def _nan(x: Any) -> float:
    """A number of ``summary.json`` (``null`` for a NaN) as a float."""
    return float("nan") if x is None else float(x)


class _PassBar:
    """A tqdm.auto bar over the study's passes (a widget in Jupyter, text in a terminal),
    its postfix the RMS roughness after the last pass."""

    def __init__(self, enabled: bool, desc: str):
        self.enabled = enabled
        self.desc = desc
        self.bar = None
        self.t0 = time.time()

    def __call__(self, p: int, target: int, rms: float, loss: float, wall: float, scalars: dict) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=target, initial=p, desc=self.desc, unit="pass", leave=False)
            # The bar appears with the first finished pass; its clock starts with the study.
            self.bar.start_t = self.t0
        self.bar.set_postfix(rms_um=f"{rms * 1e6:.4f}", pass_s=f"{wall:.2f}", refresh=False)
        self.bar.update(p + 1 - self.bar.n)
        self.bar.refresh()  # every pass shown (tqdm skips updates closer than 0.1 s)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def grow(
    scenario: ScenarioLike,
    /,
    *,
    passes: Optional[int] = None,
    out: Union[str, os.PathLike[str], None] = None,
    resume: bool = False,
    progress: bool = True,
    threads: Optional[int] = None,
    **overrides: Any,
) -> GrowthResult:
    """Runs a growth study (``softway grow``): passes of the scenario's run, each over the
    surface profile the wear of the passes before left.

    Args:
        scenario: a :class:`Scenario` with ``[growth]`` and ``[wear]`` tables (``kind =
            "wheel"`` or ``"track"``; e.g. ``scenarios/polygon.toml``): a path, TOML text
            or a dict.
        passes: simulated passes in all (None: the scenario's ``growth.passes``); with
            ``resume`` the total to reach, counting those already done.
        out: the study's folder (default ``out/<scenario name>-grow``, as the command
            line's); it receives the command line's files, rewritten after every pass,
            and the checkpoint ``checkpoint.json``.
        resume: go on from the checkpoint in ``out`` (the same scenario text and overrides
            required): the same bits as a study run without a stop.
        progress: show a progress bar over the passes (tqdm.auto: a widget in a notebook);
            False for none.
        threads: threads of each pass (None: the cores). The results do not depend on it.
        **overrides: dotted scenario keys to set first, as ``softway grow --set`` does:
            ``grow("polygon.toml", passes=3, **{"wheel.rim_nodes": 96})``.

    Returns:
        :class:`GrowthResult`: ``passes`` (xarray, per pass), ``bands`` (xarray, band
        level per pass and wavelength), ``orders``, ``profile`` (numpy), ``summary``,
        ``save(folder)``.

    Raises:
        ScenarioError: the scenario (or an override) is refused, or it has no ``[growth]``
            table; the message is the command line's, ``key`` the key at fault.
        RunError: a pass failed, or the checkpoint cannot be resumed (none in ``out``,
            another scenario text, another grid).
        GrowthInterrupted: Ctrl-C (KeyboardInterrupt, in a terminal or a notebook)
            stopped the study within a step of the pass under way; that pass is dropped,
            the finished ones are kept (``.result``, and the checkpoint for ``resume``).
            During a new study's reference pass, before there is a state to keep, it is a
            plain KeyboardInterrupt.

    The engine runs without the GIL on a thread of its own; other Python threads go on.
    """
    from . import GrowthInterrupted

    sc = as_scenario(scenario)
    if overrides:
        sc = sc.with_values(**overrides)
    if passes is not None and (isinstance(passes, bool) or int(passes) != passes or passes < 1):
        raise ValueError(f"passes: a whole number >= 1, not {passes!r}")
    folder = Path(out) if out is not None else Path("out") / f"{sc.name}-grow"
    bar = _PassBar(progress, sc.name)
    try:
        native, raised = _native.grow(
            sc.text,
            sc.path,
            str(folder),
            None if passes is None else int(passes),
            resume,
            threads,
            bar if progress else None,
        )
    finally:
        bar.close()
    result = GrowthResult(native, folder)
    if raised is not None:
        if isinstance(raised, KeyboardInterrupt):
            raise GrowthInterrupted(result) from None
        raise raised
    return result
