"""Type stubs of the compiled engine `softway._native` (python/src/lib.rs). The public API
is `softway`'s: Scenario, run, sweep, Result."""

from typing import Callable, Optional

__version__: str

class ScenarioError(ValueError):
    """A scenario refused by the validation: the command line's one-line message."""

    #: The dotted key at fault (None where the parser names none).
    key: Optional[str]

class RunError(RuntimeError):
    """A run that failed (a model that cannot be built, the divergence guard)."""

_Table = tuple[
    Optional[tuple[str, list[str], bytes]],  # key column: name, labels, codes (f64 bytes)
    list[tuple[str, str, bytes]],  # columns: name, unit, values (f64 bytes)
]
_Arrays = list[tuple[str, int, bytes]]  # name, components, values (f64 bytes)
_Fields = tuple[
    Optional[tuple[int, bytes, str, int, bytes]],  # dim, coords, cell kind, per cell, cells
    list[tuple[str, Optional[float], Optional[bytes], _Arrays, _Arrays]],
]

class NativeResults:
    @property
    def kind(self) -> str: ...
    @property
    def summary_json(self) -> str: ...
    @property
    def lines(self) -> list[str]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def interrupted(self) -> bool: ...
    def table(self, name: str) -> Optional[_Table]: ...
    def fields(self) -> _Fields: ...
    def save(self, folder: str, force: bool = False) -> list[str]: ...

def check(text: str, path: str) -> dict: ...
def check_file(path: str) -> None: ...
def set_key(text: str, key: str, value: str) -> str: ...
def json_to_toml(json: str) -> str: ...
def run(
    text: str,
    path: str,
    threads: Optional[int] = None,
    progress: Optional[Callable[[str, int, int], object]] = None,
    poll_s: float = 0.1,
) -> tuple[NativeResults, Optional[BaseException]]: ...

class NativeGrowth:
    @property
    def summary_json(self) -> str: ...
    @property
    def lines(self) -> list[str]: ...
    @property
    def files(self) -> list[str]: ...
    @property
    def interrupted(self) -> bool: ...
    @property
    def passes_run(self) -> int: ...
    def passes(self) -> list[tuple[str, bytes]]: ...
    # x0, dx, n, periodic, profiles ((passes + 1) x n), last pass's wear (or None)
    def profiles(self) -> tuple[float, float, int, bool, bytes, Optional[bytes]]: ...
    # centre wavelengths, first orders, last orders, levels ((passes + 1) x bands)
    def bands(self) -> tuple[bytes, bytes, bytes, bytes]: ...
    def orders(self) -> bytes: ...
    def save(self, folder: str, force: bool = False) -> list[str]: ...

def grow(
    text: str,
    path: str,
    out: str,
    passes: Optional[int] = None,
    resume: bool = False,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int, float, float, float, dict[str, float]], object]] = None,
    poll_s: float = 0.1,
) -> tuple[NativeGrowth, Optional[BaseException]]: ...
