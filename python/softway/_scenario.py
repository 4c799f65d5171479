"""Scenarios: TOML text validated by the engine, from a file, a string or a dict."""

from __future__ import annotations

import json
import math
import os
from typing import Any, Mapping, Union

from . import _native

ScenarioError = _native.ScenarioError

ScenarioLike = Union["Scenario", str, "os.PathLike[str]", Mapping[str, Any]]


def toml_literal(value: Any) -> str:
    """The TOML literal of a Python value (bool, int, float, str, list, dict; numpy scalars
    too), as ``softway sweep --set KEY=VALUE`` takes it: ``300.0``, ``"exact"``, ``true``."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return "true" if value else "false"
    if isinstance(value, int) or (hasattr(value, "dtype") and value.dtype.kind in "iu"):
        return str(int(value))
    if isinstance(value, float) or (hasattr(value, "dtype") and value.dtype.kind == "f"):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_literal(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k} = {toml_literal(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {value!r} ({type(value).__name__}) as a TOML value")


def dotted(key: str) -> str:
    """A keyword argument's name as a dotted scenario key: ``rolling__omega`` ->
    ``rolling.omega`` (a dotted name passed through ``**{"rolling.omega": ...}`` stays)."""
    return key.replace("__", ".")


class Scenario:
    """A scenario, validated as the command line validates it.

    ``Scenario(source)`` takes a path to a TOML file (a ``pathlib.Path``, or a ``str``
    without a newline that names a file, ends in ``.toml`` or holds no ``=``), TOML text (any
    other ``str``), a ``dict`` of the same tables and keys, or another ``Scenario``. Bad input raises :class:`ScenarioError` with the command line's one-line
    message (file, key, what is allowed); its ``key`` attribute is the dotted key at fault.

    A scenario given as text or a dict is named ``<string>`` or ``<dict>`` in messages (or
    ``path=``, which also sets the folder that relative mesh paths are read from).

    >>> sc = Scenario("scenarios/wheel.toml")
    >>> sc.name, sc.kind
    ('wheel', 'wheel')
    >>> faster = sc.with_values(**{"rolling.turns": 1})
    """

    text: str
    path: str
    info: dict

    def __init__(self, source: ScenarioLike, *, path: str | os.PathLike[str] | None = None):
        if isinstance(source, Scenario):
            text, name = source.text, source.path
        elif isinstance(source, Mapping):
            text = _native.json_to_toml(json.dumps(source, default=_json_default))
            name = "<dict>"
        elif isinstance(source, os.PathLike) or (
            isinstance(source, str)
            and "\n" not in source
            and ("=" not in source or source.endswith(".toml") or os.path.exists(source))
        ):
            name = os.fspath(source)
            text = _read_text(name)
        elif isinstance(source, str):
            text, name = source, "<string>"
        else:
            raise TypeError(
                "a scenario is a path, TOML text, a dict or a Scenario, not "
                f"{type(source).__name__}"
            )
        self.text = text
        self.path = os.fspath(path) if path is not None else name
        self.info = _native.check(self.text, self.path)

    @property
    def name(self) -> str:
        """The scenario's name (its default output folder ``out/<name>``)."""
        return self.info["name"]

    @property
    def kind(self) -> str:
        """The model: ``sdof``, ``bar_impact``, ``two_bars``, ``wheel``, ``track``, ``press`` or
        ``rolling3d``."""
        return self.info["kind"]

    @property
    def warnings(self) -> list[str]:
        """The validation's warnings (the command line prints them before a run)."""
        return list(self.info["warnings"])

    @property
    def sweep(self) -> tuple[str, list[str]] | None:
        """The scenario's ``[sweep]`` table: the key and its values (TOML literals)."""
        return self.info["sweep"]

    @property
    def sweep_ladder(self) -> tuple[str, list[str]] | None:
        """The ladder of the scenario's ``[sweep]`` table (``ladder = { key, values }``): the
        rung key and its values, each run with every value of :attr:`sweep`."""
        return self.info["sweep_ladder"]

    @property
    def sweep_ladder_with(self) -> list[tuple[str, list[str]]]:
        """The keys set with each rung of the ladder (``ladder.with``), each with one value a
        rung (TOML literals): what else a rung changes beside its key (``[]`` without)."""
        return list(self.info["sweep_ladder_with"])

    @property
    def sha256(self) -> str:
        """SHA-256 of the text (``summary.json``'s ``scenario_sha256``)."""
        return self.info["sha256"]

    def with_values(self, **overrides: Any) -> "Scenario":
        """A copy with dotted keys set (``**{"rolling.omega": 350.0}`` or
        ``rolling__omega=350.0``), validated anew, as ``softway sweep --set`` sets them."""
        text = self.text
        for k, v in overrides.items():
            text = _native.set_key(text, dotted(k), toml_literal(v))
        return Scenario(text, path=self.path)

    def to_toml(self) -> str:
        """The scenario's TOML text."""
        return self.text

    def __reduce__(self):
        return (_rebuild, (self.text, self.path))

    def __repr__(self) -> str:
        return f"Scenario(name={self.name!r}, kind={self.kind!r}, path={self.path!r})"


def _rebuild(text: str, path: str) -> Scenario:
    return Scenario(text, path=path)


def _json_default(v: Any) -> Any:
    """numpy scalars and arrays in a scenario dict."""
    if hasattr(v, "tolist"):
        return v.tolist()
    raise TypeError(f"cannot write {v!r} ({type(v).__name__}) in a scenario")


def _read_text(path: str) -> str:
    """The text of the scenario file ``path`` as the command line reads it (the engine's
    reader: a regular file of at most 16 MiB, UTF-8); raises its ScenarioError otherwise
    (missing, a folder, a pipe or a device, too large, not UTF-8)."""
    return _native.read_scenario(path)


def as_scenario(scenario: ScenarioLike) -> Scenario:
    """``scenario`` as a :class:`Scenario` (validated)."""
    return scenario if isinstance(scenario, Scenario) else Scenario(scenario)
