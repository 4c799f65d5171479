"""Type stubs of the package `softway` (the code is softway/*.py; the engine's stubs are
_native.pyi)."""

import os
from concurrent.futures import Executor
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import xarray

from ._native import RunError as RunError
from ._native import ScenarioError as ScenarioError
from ._growth import GrowthResult as GrowthResult
from ._growth import Profile as Profile
from ._result import TIMING_KEYS as TIMING_KEYS
from ._result import FieldFrame as FieldFrame
from ._result import Fields as Fields
from ._result import Result as Result
from ._scenario import Scenario as Scenario
from ._scenario import toml_literal as toml_literal

__version__: str

ScenarioLike = Union[Scenario, str, os.PathLike[str], Mapping[str, Any]]

class SoftwayWarning(UserWarning): ...

class RunInterrupted(KeyboardInterrupt):
    result: Result
    def __init__(self, result: Result) -> None: ...

def run(
    scenario: ScenarioLike,
    /,
    *,
    progress: bool = True,
    threads: Optional[int] = None,
    irregularity: Any = None,
    **overrides: Any,
) -> Result: ...
class GrowthInterrupted(KeyboardInterrupt):
    result: GrowthResult
    def __init__(self, result: GrowthResult) -> None: ...

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
) -> GrowthResult: ...
class SweepInterrupted(KeyboardInterrupt):
    dataset: Any
    def __init__(self, dataset: Any) -> None: ...

def sweep(
    scenario: ScenarioLike,
    grid: Mapping[str, Iterable[Any]],
    *,
    executor: Union[Executor, str, None] = None,
    mode: str = "product",
    histories: Sequence[str] = (),
    out: Union[str, os.PathLike[str], None] = None,
    progress: bool = True,
) -> xarray.Dataset: ...
def grow_sweep(
    scenario: ScenarioLike,
    grid: Mapping[str, Iterable[Any]],
    *,
    passes: Optional[int] = None,
    grid_mode: str = "product",
    executor: Union[Executor, str, None] = None,
    out: Union[str, os.PathLike[str], None] = None,
    resume: bool = False,
    progress: bool = True,
) -> xarray.Dataset: ...
