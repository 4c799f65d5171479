"""softway: dynamic contact by the space-time finite element method in the velocity
formulation, with Bajer's soft way, from Python.

- :class:`Scenario`: a scenario from a TOML file, TOML text or a dict, validated as the
  command line validates it (:class:`ScenarioError` carries the message and the dotted
  key); the engine's warnings come as :class:`SoftwayWarning`.
- :func:`run`: one run, results in memory (:class:`Result`: summary, history as an xarray
  Dataset, contact nodes, fields as numpy arrays); Ctrl-C stops it at the next step.
- :func:`grow`: a growth study (``softway grow``: wear pass by pass, checkpointed,
  resumable), its results as xarray (:class:`GrowthResult`: per-pass table, band spectrum
  per pass, profile); Ctrl-C stops it within a step, the finished passes kept.
- :func:`sweep`: a parameter grid on any ``concurrent.futures.Executor`` (Dask's
  ``client.get_executor()`` included; by default a local Dask cluster, ``softway[dask]``),
  gathered into one xarray Dataset written as NetCDF (``softway[netcdf]``).
- :func:`grow_sweep`: growth studies over a grid (the polygon's growth at several speeds)
  on any executor likewise, each study checkpointed in its own folder, the per-pass scalars
  and band tables gathered into one xarray Dataset.

The engine is the Rust crate ``softway`` (the same as the ``softway`` command line): the
same scenario gives the same numbers here, bit for bit.
"""

from __future__ import annotations

import contextlib
import os
import warnings as _warnings
from typing import Any, Callable, Optional

from . import _native
from ._native import RunError, ScenarioError
from ._result import TIMING_KEYS, FieldFrame, Fields, Result
from ._scenario import Scenario, ScenarioLike, as_scenario, toml_literal
from ._growth import GrowthResult, Profile, grow
from ._sweep import SweepInterrupted, sweep
from ._grow_sweep import grow_sweep

__version__ = _native.__version__

__all__ = [
    "Scenario",
    "ScenarioError",
    "RunError",
    "RunInterrupted",
    "SoftwayWarning",
    "Result",
    "Fields",
    "FieldFrame",
    "run",
    "grow",
    "GrowthResult",
    "GrowthInterrupted",
    "Profile",
    "sweep",
    "SweepInterrupted",
    "grow_sweep",
    "toml_literal",
    "TIMING_KEYS",
]


class SoftwayWarning(UserWarning):
    """A warning of the engine about a scenario or a run (a time step beyond the stable
    one, a rim too coarse for the contact patch, a resonance): what the command line prints
    as ``softway: warning: ...``. :func:`run` emits each with :func:`warnings.warn` (the
    scenario's before the run, the run's after it); ``Result.warnings`` keeps the run's.
    Filter them as any warning: ``warnings.simplefilter("ignore", softway.SoftwayWarning)``
    or ``"error"`` to stop on one."""


def _warn(messages: list[str], stacklevel: int) -> None:
    for m in messages:
        _warnings.warn(m, SoftwayWarning, stacklevel=stacklevel + 1)


class RunInterrupted(KeyboardInterrupt):
    """A run stopped by Ctrl-C (KeyboardInterrupt) at its next step. ``result`` holds what
    was computed (``result.interrupted`` is True); it is a KeyboardInterrupt, so code that
    does not catch it stops as on any Ctrl-C."""

    def __init__(self, result: Result):
        super().__init__("run interrupted; .result holds the steps computed")
        self.result = result

    def __reduce__(self):  # pickled with its result (an exception pickles its args)
        return (type(self), (self.result,))


class GrowthInterrupted(KeyboardInterrupt):
    """A growth study stopped by Ctrl-C (KeyboardInterrupt) within a step of the pass under
    way: that pass is dropped, the finished ones are kept. ``result`` holds them
    (``result.interrupted`` is True), and so does the checkpoint in the study's folder:
    ``grow(..., resume=True)`` goes on from it, giving the bits of a study run without a
    stop. It is a KeyboardInterrupt, so code that does not catch it stops as on any
    Ctrl-C."""

    def __init__(self, result: GrowthResult):
        super().__init__(
            f"growth study interrupted after {result.summary['passes']} finished passes; "
            ".result holds them, resume=True goes on"
        )
        self.result = result

    def __reduce__(self):  # pickled with its result (an exception pickles its args)
        return (type(self), (self.result,))


class _Bar:
    """A tqdm.auto bar per run of the scenario (a notebook widget in Jupyter, text in a
    terminal), fed by the engine's progress."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.bar = None
        self.label: Optional[str] = None

    def __call__(self, label: str, done: int, total: int) -> None:
        if not self.enabled or total == 0:
            return
        if self.bar is None or label != self.label:
            self.close()
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, desc=label, unit="step", unit_scale=True, leave=False)
            self.label = label
        self.bar.update(max(0, done - self.bar.n))

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def run(
    scenario: ScenarioLike,
    /,
    *,
    progress: bool = True,
    threads: Optional[int] = None,
    irregularity: Any = None,
    **overrides: Any,
) -> Result:
    """Runs a scenario and returns its results in memory.

    Args:
        scenario: a :class:`Scenario`, a path to a TOML file, TOML text or a dict.
        progress: show a progress bar (tqdm.auto: a widget in a notebook); False for none.
        threads: threads of the run (None: the cores; a model of 1,500 dofs or more is
            solved on two). The results do not depend on it.
        irregularity: for the wheel on a track (``kind = "track"``), the rail's roughness as
            an array of shape (N, 2): the distance from the axle's start (m, increasing) and
            the height of the rail's top there (m). It is passed to the engine as data (the
            scenario's ``[irregularity] type = "measured"``), not as a Python callback.
        **overrides: dotted scenario keys to set first, as ``softway sweep --set`` does:
            ``run("wheel.toml", **{"rolling.omega": 350.0})`` or ``rolling__omega=350.0``.

    Returns:
        :class:`Result`: ``summary``, ``history`` (xarray), ``contact_nodes``, ``fields``,
        ``save(folder)``.

    Warns:
        SoftwayWarning: each of the scenario's warnings (before the run) and of the run's
            (after it, also in ``Result.warnings``), as the command line prints them.

    Raises:
        ScenarioError: the scenario (or an override) is refused; the message is the command
            line's, ``key`` the dotted key at fault (``bar.length``, ``runs[1].h``).
        RunError: the model cannot be built or the run failed (e.g. stopped by the
            divergence guard).
        RunInterrupted: Ctrl-C (KeyboardInterrupt, in a terminal or a notebook) stopped the
            run at its next step; ``.result`` holds the steps computed.

    The engine runs without the GIL on a thread of its own; other Python threads go on.
    """
    sc = as_scenario(scenario)
    if overrides:
        sc = sc.with_values(**overrides)
    return _run(sc, progress=progress, threads=threads, irregularity=irregularity, stacklevel=3)


class _Stopped(Exception):
    """Raised by a run's progress callback when its ``should_stop`` says so (a sweep's
    point told to stop by the sweep that was interrupted): the engine stops the run at its
    next step, as on Ctrl-C."""


def _run(
    sc: Scenario,
    *,
    progress: bool,
    threads: Optional[int],
    irregularity: Any = None,
    should_stop: Optional[Callable[[], bool]] = None,
    stacklevel: int = 2,
) -> Result:
    """:func:`run` of a validated scenario; ``should_stop`` (None, or called at every
    progress report, about every 0.1 s) stops the run at its next step when it returns
    True, raising RunInterrupted with what was computed (a sweep's point on a worker,
    stopped by the sweep that was interrupted)."""
    _warn(sc.warnings, stacklevel=stacklevel)
    with contextlib.ExitStack() as stack:
        if irregularity is not None:
            sc = _with_irregularity(sc, irregularity, stack)
        bar = _Bar(progress)
        report: Optional[Callable[[str, int, int], None]] = bar if progress else None
        if should_stop is not None:

            def report(label: str, done: int, total: int, _bar=report) -> None:
                if _bar is not None:
                    _bar(label, done, total)
                if should_stop():
                    raise _Stopped()

        try:
            native, raised = _native.run(sc.text, sc.path, threads, report)
        finally:
            bar.close()
    result = Result(native)
    _warn(result.warnings, stacklevel=stacklevel)
    if raised is not None:
        if isinstance(raised, (KeyboardInterrupt, _Stopped)):
            raise RunInterrupted(result) from None
        raise raised
    return result


def _with_irregularity(sc: Scenario, profile: Any, stack: contextlib.ExitStack) -> Scenario:
    """The scenario with ``profile`` ((N, 2): x from the axle's start, m; r, m) as its
    measured irregularity: written to a CSV file in a temporary folder that lives while the
    run does, named by an absolute path in ``[irregularity]``."""
    import numpy as np
    import tempfile

    arr = np.asarray(profile, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 2:
        raise ValueError(
            f"irregularity: an array of shape (N, 2) with N >= 2 (x_m, r_m), not {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError("irregularity: the values must be finite")
    folder = stack.enter_context(tempfile.TemporaryDirectory(prefix="softway-irregularity-"))
    path = os.path.join(folder, "irregularity.csv")
    np.savetxt(path, arr, delimiter=",", header="x_m,r_m", comments="", fmt="%.17g")
    return sc.with_values(
        **{"irregularity.type": "measured", "irregularity.file": path}
    )


with contextlib.suppress(AttributeError):  # help() shows the engine's exceptions as ours
    ScenarioError.__module__ = "softway"
    RunError.__module__ = "softway"
