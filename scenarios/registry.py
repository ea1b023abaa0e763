"""The scenario registry: name -> module, and config overrides from TOML.

Scenario modules are imported lazily, so ``gyrobench list`` stays fast.
See :mod:`gyrobench.scenarios.base` for what a scenario module defines.
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import math
import sys
import types
import typing
from pathlib import Path
from types import ModuleType
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

#: the scenarios that are not papers, by name -> module: ``static_noise`` runs first, every other
#: entry after the papers (:func:`table`). Papers are not listed here: :func:`table` discovers
#: them (:func:`gyrobench.scenarios.papers.discover`), so adding a paper is adding its folder.
SCENARIOS: dict[str, str] = {
    "static_noise": "gyrobench.scenarios.static_noise",
    "part": "gyrobench.scenarios.part_bench",
    "physics_checks": "gyrobench.scenarios.physics_checks",
}

#: the entries of :data:`SCENARIOS` that run before the papers
_BEFORE_PAPERS = ("static_noise",)


def table() -> dict[str, str]:
    """Every scenario, name -> module, in the order of ``reproduce --all`` and the report.

    Every scenario, name -> module, in the order of ``reproduce --all`` and the report:
    ``static_noise``, the discovered papers (in folder order), then the rest of :data:`SCENARIOS`.

    Returns
    -------
    dict of str to str
        Scenario name -> its module's dotted name.

    Raises
    ------
    ValueError
        If a discovered paper's ``NAME`` is also a registered scenario's name.
    """
    from gyrobench.scenarios import papers

    out = {n: m for n, m in SCENARIOS.items() if n in _BEFORE_PAPERS}
    for p in papers.discover():
        if p.name in SCENARIOS:
            raise ValueError(f"paper {p.module} is named {p.name!r}, as a registered scenario is")
        out[p.name] = p.module
    out.update((n, m) for n, m in SCENARIOS.items() if n not in out)
    return out


def available() -> list[str]:
    """Scenario names whose module is present in this installation (:func:`table`'s order).

    Returns
    -------
    list of str
        The names.
    """
    return [n for n, mod in table().items() if importlib.util.find_spec(mod) is not None]


def get(name: str) -> ModuleType:
    """Import and return the scenario module named ``name``.

    Parameters
    ----------
    name : str
        A scenario name (:func:`available`).

    Returns
    -------
    module
        The scenario module.

    Raises
    ------
    ValueError
        If ``name`` is not a scenario.
    """
    names = available()
    if name not in names:
        raise ValueError(f"scenario must be one of {names}; got {name!r}")
    return importlib.import_module(table()[name])


@dataclasses.dataclass(frozen=True, slots=True)
class ScenarioInfo:
    """What ``gyrobench list`` shows of a scenario, read from its source without importing it.

    Parameters
    ----------
    name : str
        The scenario's name.
    title : str
        Its ``TITLE``.
    paper : str or None
        Its paper key (None: not a paper scenario).
    bench : bool
        It has a ``compensation_task`` (``gyrobench bench`` runs it).
    """

    name: str
    title: str
    paper: str | None
    bench: bool


def describe(name: str) -> ScenarioInfo:
    """Title, paper key and bench capability of scenario ``name``, from its module's source.

    Reading the constants ``TITLE`` and ``PAPER`` and looking for ``def compensation_task``
    (or, in a paper package's ``__init__``, ``from .x import compensation_task``)
    with :mod:`ast` keeps ``gyrobench list`` from importing every scenario (and with them
    numpy, scipy, scikit-learn and matplotlib).

    Parameters
    ----------
    name : str
        A scenario name.

    Returns
    -------
    ScenarioInfo
        What ``gyrobench list`` shows.

    Raises
    ------
    ValueError
        If ``name`` is not a scenario, or its module does not set ``TITLE`` to a
        string literal.
    """
    import ast

    modules = table()
    if name not in modules:
        raise ValueError(f"scenario must be one of {list(modules)}; got {name!r}")
    spec = importlib.util.find_spec(modules[name])
    if spec is None or not spec.origin:
        raise ValueError(f"scenario {name!r}: module {modules[name]!r} is not installed")
    tree = ast.parse(Path(spec.origin).read_bytes(), filename=spec.origin)
    constants: dict[str, Any] = {}
    bench = False
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            target = node.targets[0]
            if isinstance(target, ast.Name) and target.id in ("TITLE", "PAPER"):
                try:
                    constants[target.id] = ast.literal_eval(node.value)
                except ValueError:
                    pass
        elif isinstance(node, ast.FunctionDef) and node.name == "compensation_task":
            bench = True
        elif isinstance(node, ast.ImportFrom) and any(
            (a.asname or a.name) == "compensation_task" for a in node.names
        ):
            bench = True  # a paper package's __init__ re-exports it from its modules
    title = constants.get("TITLE")
    if not isinstance(title, str):
        raise ValueError(f"scenario {name!r}: TITLE must be a string literal in {spec.origin}")
    paper = constants.get("PAPER")
    return ScenarioInfo(name, title, paper if isinstance(paper, str) else None, bench)


#: the largest integer magnitude a configuration accepts (TOML's own limit, 64-bit signed): a
#: larger one (Python parses any size) would make the config's checks hang or overflow
MAX_CONFIG_INT = 2**63 - 1


def _coerce(owner: str, key: str, value: Any, hint: Any) -> Any:
    """Check a TOML value against a dataclass field's type hint and convert lists to tuples."""
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        errors = []
        for a in args:
            if a is type(None):
                if value is None:
                    return None
                continue
            try:
                return _coerce(owner, key, value, a)
            except (TypeError, ValueError) as exc:
                errors.append(str(exc))
        raise TypeError(f"{owner}.{key} must be one of {args}; got {value!r}")
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{owner}.{key} must be a number; got {value!r}")
        if isinstance(value, int) and abs(value) > MAX_CONFIG_INT:
            raise ValueError(f"{owner}.{key} must be a finite number of magnitude <= {MAX_CONFIG_INT}; got {value!r}")
        if not math.isfinite(value):
            raise ValueError(f"{owner}.{key} must be a finite number; got {value!r}")
        return float(value)
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"{owner}.{key} must be an integer; got {value!r}")
        if abs(value) > MAX_CONFIG_INT:
            raise ValueError(f"{owner}.{key} must be an integer of magnitude <= {MAX_CONFIG_INT}; got {value!r}")
        return value
    if hint is bool or hint is str:
        if not isinstance(value, hint):
            raise TypeError(f"{owner}.{key} must be a {hint.__name__}; got {value!r}")
        return value
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise TypeError(f"{owner}.{key} must be a list; got {value!r}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_coerce(owner, f"{key}[{i}]", v, args[0]) for i, v in enumerate(value))
        if len(args) != len(value):
            raise ValueError(f"{owner}.{key} must have {len(args)} elements; got {value!r}")
        return tuple(_coerce(owner, f"{key}[{i}]", v, a) for i, (v, a) in enumerate(zip(value, args, strict=True)))
    if dataclasses.is_dataclass(hint):
        if not isinstance(value, dict):
            raise TypeError(f"{owner}.{key} must be a table; got {value!r}")
        return override(typing.cast(Any, hint)(), value, owner=f"{owner}.{key}")
    if typing.get_origin(hint) is typing.Literal:
        if value not in args:
            raise ValueError(f"{owner}.{key} must be one of {list(args)}; got {value!r}")
        return value
    return value


def _check_field(owner: str, config_type: type, key: str, value: Any) -> None:
    """Refuse ``value`` of field ``key`` by its declared spec (:func:`gyrobench.base.ranges.check_field`,
    the one check a config's own ``validate`` runs too), before the configuration is built: a value
    out of range never reaches the config's constraints or a model."""
    from gyrobench.base.ranges import check_field

    check_field(owner, config_type, key, value)


def override(config: Any, values: dict[str, Any], *, owner: str | None = None) -> Any:
    """Return ``config`` with ``values`` replaced, validated field by field.

    Unknown keys raise ``ValueError`` naming the valid ones; wrong types raise
    ``TypeError``; a value outside its field's declared spec
    (:class:`~gyrobench.base.ranges.FieldRange`, :class:`~gyrobench.base.ranges.FieldChoice`)
    raises ``ValueError`` naming the range and unit; then the config's own ``__post_init__``
    (:func:`~gyrobench.base.ranges.validate`) checks its declared constraints across fields.

    Parameters
    ----------
    config : dataclass instance
        A scenario's Config.
    values : dict of str to object
        Field -> new value.
    owner : str or None
        How the messages name the config (None: its class name).

    Returns
    -------
    dataclass instance
        ``config`` with ``values`` replaced.
    """
    owner = owner or type(config).__name__
    hints = typing.get_type_hints(type(config))
    names = [f.name for f in dataclasses.fields(config)]
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise ValueError(f"{owner} has no parameter(s) {unknown}; valid: {names}")
    current = {k: getattr(config, k) for k in values}
    changes = {}
    for k, v in values.items():
        hint = hints[k]
        if dataclasses.is_dataclass(current[k]) and isinstance(v, dict):
            changes[k] = override(current[k], v, owner=f"{owner}.{k}")
        else:
            changes[k] = _coerce(owner, k, v, hint)
            _check_field(owner, type(config), k, changes[k])
    try:
        return dataclasses.replace(config, **changes)
    except (OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        # the config's own checks computed with an absurd value (1e308 h x fs = inf samples)
        given = ", ".join(
            f"{owner}.{k} = {v!r}" for k, v in values.items() if not isinstance(v, dict)
        )
        raise ValueError(
            f"{owner}: a value is out of range ({given or 'nested values'}): "
            f"{type(exc).__name__}: {exc}"
        ) from None


def load_config(module: ModuleType, path: str | Path | None) -> Any:
    """The scenario's default ``Config``, overridden by the TOML file at ``path`` if given.

    The file may hold the fields at top level or under a table named after the scenario.
    Every error is a ``ValueError`` or ``TypeError`` naming the file (not TOML, not UTF-8,
    nested deeper than :data:`MAX_CONFIG_DEPTH`, an unknown or mistyped parameter, a value
    so large the configuration's checks overflow), or
    :class:`gyrobench.base.memory.MemoryLimitError` when the scenario states a memory
    estimate (``memory_estimate(config)``) above the limit.

    Parameters
    ----------
    module : module
        The scenario.
    path : str, Path or None
        A TOML file (None: the defaults).

    Returns
    -------
    dataclass instance
        The scenario's Config.
    """
    config = module.Config()
    if path is None:
        return _check_memory(module, config, None)
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"config file not found: {str(p)!r}")
    try:
        text = p.read_bytes().decode("utf-8-sig")  # a BOM (Windows editors) is not an error
    except UnicodeDecodeError as exc:
        raise ValueError(f"config file {str(p)!r} is not UTF-8 text: {exc}") from None
    if len(text) > MAX_CONFIG_CHARS:
        raise ValueError(
            f"config file {str(p)!r} has {len(text)} characters; a configuration is at most "
            f"{MAX_CONFIG_CHARS}"
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"config file {str(p)!r} is not valid TOML: {exc}") from None
    except RecursionError:
        raise ValueError(
            f"config file {str(p)!r} nests arrays or tables too deeply to read"
        ) from None
    if _depth(data) > MAX_CONFIG_DEPTH:
        raise ValueError(
            f"config file {str(p)!r} nests values {_depth(data)} levels deep; a scenario "
            f"configuration needs at most {MAX_CONFIG_DEPTH}"
        )
    if set(data) == {module.NAME} and isinstance(data[module.NAME], dict):
        data = data[module.NAME]
    try:
        config = override(config, data)
    except RecursionError:  # pragma: no cover - bounded by MAX_CONFIG_DEPTH
        raise ValueError(f"config file {str(p)!r} nests values too deeply") from None
    except (ValueError, TypeError) as exc:
        raise type(exc)(f"config file {str(p)!r}: {exc}") from None
    return _check_memory(module, config, p)


def _check_memory(module: ModuleType, config: Any, path: Path | None) -> Any:
    """``config``, if the scenario's run fits in memory (gyrobench.base.memory.check_scenario):
    every verb reads its configuration here, before any work."""
    from gyrobench.base import memory

    name = getattr(module, "NAME", module.__name__)
    source = f"config file {str(path)!r}" if path else "its default configuration"
    what = f"scenario {name} with {source}"
    memory.check_scenario(module, config, what)
    return config


#: a scenario configuration is a few tables of scalars and short lists
MAX_CONFIG_DEPTH = 16
MAX_CONFIG_CHARS = 1_000_000


def _depth(value: Any, level: int = 0) -> int:
    """Nesting depth of lists and tables (stops counting past MAX_CONFIG_DEPTH + 1)."""
    if level > MAX_CONFIG_DEPTH or not isinstance(value, (dict, list)):
        return level
    items = value.values() if isinstance(value, dict) else value
    return max((_depth(v, level + 1) for v in items), default=level + 1)
