"""Identity of a campaign: what a campaign id hashes, so that changed code never mixes results.

A campaign is identified by a hash of the scenario (its configuration; the source of its
module and of every module it imports, transitively, from its own package and from
gyrobench; the gyrobench, numpy, scipy and scikit-learn versions), of the bench's own source
and of the compensator (its class or function and its full state: ``get_params`` where it
has them, else its attributes, else its pickled bytes; the source of the module defining it
with its import closure: every module it imports, transitively, that lies outside the
standard library and site-packages, so a helper module beside it is hashed too). :func:`scenario_identity` is the
scenario half, shared with the units runner (:mod:`gyrobench.scenarios.runner.units`).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import importlib
import importlib.util
import inspect
import json
import os
import types
from pathlib import Path
from typing import Any

import numpy as np

from gyrobench.scenarios.bench.compensators import resolve_compensator
from gyrobench.scenarios.bench.scoring import resolve_scenario

__all__ = [
    "bench_source_hash",
    "campaign_id",
    "campaign_id_of",
    "canonical",
    "compensator_identity",
    "file_hash",
    "module_file",
    "module_hash",
    "scenario_identity",
    "source_closure",
    "versions",
]

#: gyrobench's own packages: a scenario's or compensator's imports are followed into these
_OWN_PACKAGES = frozenset({"gyrobench"})


def file_hash(path: str) -> str:
    """First 16 hex digits of the SHA-256 of the file at ``path`` (``"unreadable"`` if it cannot be read).

    Parameters
    ----------
    path : str
        The file.

    Returns
    -------
    str
        16 hex digits or ``"unreadable"``.
    """
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]
    except OSError:
        return "unreadable"


def module_file(name: str) -> str | None:
    """The source file of module ``name``, found without importing the module itself.

    Parent packages are imported (their ``__init__`` files only: for gyrobench these are
    cheap) because a package's ``__path__`` is the only reliable way to its submodules when
    setuptools maps folders to packages (an editable install's finder).

    Parameters
    ----------
    name : str
        A dotted module name.

    Returns
    -------
    str or None
        Its source file (None: none found).
    """
    import importlib.util
    import sys

    mod = sys.modules.get(name)
    path = getattr(mod, "__file__", None) if mod is not None else None
    if path:
        return path
    parent, _, leaf = name.rpartition(".")
    if not parent:
        try:
            spec = importlib.util.find_spec(name)  # a top-level find_spec imports nothing
        except (ImportError, ValueError, AttributeError):
            return None
        return spec.origin if spec is not None and spec.has_location else None
    try:
        package = importlib.import_module(parent)
    except Exception:  # a user package that fails to import has no file to hash
        return None
    for d in map(Path, getattr(package, "__path__", None) or []):
        if (d / leaf / "__init__.py").is_file():
            return str(d / leaf / "__init__.py")
        if (d / f"{leaf}.py").is_file():
            return str(d / f"{leaf}.py")
    return None


def _is_third_party(path: str) -> bool:
    import sysconfig

    parts = Path(path).parts
    if "site-packages" in parts or "dist-packages" in parts:
        return True
    stdlib = sysconfig.get_paths().get("stdlib")
    if not stdlib:
        return False
    return Path(path).resolve().is_relative_to(Path(stdlib).resolve())


def _imports(path: str, name: str, is_pkg: bool) -> frozenset[str]:
    """Module names imported anywhere in the file (relative imports resolved)."""
    try:
        st = os.stat(path)
    except OSError:
        return frozenset()
    return _imports_cached(path, st.st_mtime_ns, st.st_size, name, is_pkg)


@functools.lru_cache(maxsize=1024)
def _imports_cached(path: str, mtime_ns: int, size: int, name: str, is_pkg: bool) -> frozenset[str]:
    """:func:`_imports`, cached on the file's modification time and size."""
    import ast

    try:
        tree = ast.parse(Path(path).read_bytes())
    except (OSError, SyntaxError, ValueError):
        return frozenset()
    package = name if is_pkg else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            try:
                base = (
                    importlib.util.resolve_name("." * node.level + (node.module or ""), package)
                    if node.level
                    else node.module
                )
            except (ImportError, ValueError):
                continue
            if not base:
                continue
            out.add(base)
            out.update(f"{base}.{a.name}" for a in node.names if a.name != "*")  # may be submodules
    return frozenset(out)


@functools.lru_cache(maxsize=4096)
def _top_level_is_ours(top: str) -> bool:
    """Whether top-level module ``top`` is followed by :func:`source_closure`: gyrobench, or any
    module whose file lies outside the standard library and site-packages (user code: the
    compensator's own package, a helper module beside it, a project package on sys.path)."""
    import sys

    if top in _OWN_PACKAGES:
        return True
    if top in sys.builtin_module_names:
        return False
    path = module_file(top)  # a top-level lookup imports nothing
    return path is not None and path.endswith(".py") and not _is_third_party(path)


def source_closure(name: str) -> list[tuple[str, str]]:
    """A module and every user or gyrobench module it imports, with their file hashes.

    (module, file hash) for ``name`` and every module it imports, transitively, that is
    gyrobench's or the user's (:func:`_top_level_is_ours`: not in the standard library or
    site-packages); package ``__init__`` files included. Third-party and standard-library
    modules are represented by their versions in the campaign identity instead.

    Parameters
    ----------
    name : str
        A dotted module name.

    Returns
    -------
    list of (str, str)
        (module, file hash) pairs.
    """
    seen: dict[str, str] = {}
    todo = [name]
    while todo:
        mod = todo.pop()
        if mod in seen or not (mod == name or _top_level_is_ours(mod.partition(".")[0])):
            continue
        path = module_file(mod)
        if path is None or not path.endswith(".py"):
            continue
        seen[mod] = file_hash(path)
        parent = mod.rpartition(".")[0]
        if parent:
            todo.append(parent)
        todo.extend(_imports(path, mod, Path(path).name == "__init__.py"))
    return sorted(seen.items())


def module_hash(module_name: str | None) -> str:
    """Hash of a module's source and, for user and gyrobench code, its closure.

    Hash of a module's source: with its closure (:func:`source_closure`) for user and
    gyrobench code, the file alone for third-party modules (their version is in the identity).

    Parameters
    ----------
    module_name : str or None
        A dotted module name.

    Returns
    -------
    str
        Hex digest.
    """
    if not module_name:
        return "none"
    path = module_file(module_name)
    if not path:
        return "builtin"
    if _is_third_party(path):
        return file_hash(path)
    return hashlib.sha256(json.dumps(source_closure(module_name)).encode()).hexdigest()[:16]


def versions() -> str:
    """The versions of gyrobench, numpy, scipy and scikit-learn, as one string.

    Returns
    -------
    str
        The library versions.
    """
    import scipy
    import sklearn

    from gyrobench.io.recording import package_version

    return (
        f"gyrobench {package_version()} numpy {np.__version__} scipy {scipy.__version__} "
        f"sklearn {sklearn.__version__}"
    )


def canonical(obj: Any, depth: int = 0) -> Any:
    """A JSON-able description of ``obj`` that is stable across processes and runs.

    Parameters
    ----------
    obj : object
        Any value.
    depth : int
        Recursion depth (deeper than 20 is cut).

    Returns
    -------
    object
        JSON-able.
    """
    if depth > 20:
        return "..."
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    if isinstance(obj, float):
        return repr(obj)
    if isinstance(obj, np.generic):
        return canonical(obj.item(), depth + 1)
    if isinstance(obj, np.ndarray):
        return {
            "ndarray": list(obj.shape),
            "dtype": str(obj.dtype),
            "sha": hashlib.sha256(np.ascontiguousarray(obj).tobytes()).hexdigest()[:16],
        }
    if isinstance(obj, (list, tuple)):
        return [canonical(o, depth + 1) for o in obj]
    if isinstance(obj, dict):
        return {
            str(k): canonical(v, depth + 1)
            for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))
        }
    if isinstance(obj, type) or inspect.isroutine(obj):
        mod = getattr(obj, "__module__", None)
        return {
            "object": f"{mod}:{getattr(obj, '__qualname__', repr(obj))}",
            "source": module_hash(mod),
        }
    if isinstance(obj, functools.partial):
        return {
            "partial": canonical(obj.func, depth + 1),
            "args": canonical(obj.args, depth + 1),
            "kwargs": canonical(obj.keywords, depth + 1),
        }
    if hasattr(obj, "get_params"):
        cls = type(obj)
        return {
            "class": canonical(cls, depth + 1),
            "params": canonical(obj.get_params(deep=False), depth + 1),
        }
    if dataclasses.is_dataclass(obj):
        return {
            "dataclass": canonical(type(obj), depth + 1),
            "fields": {
                f.name: canonical(getattr(obj, f.name), depth + 1) for f in dataclasses.fields(obj)
            },
        }
    if isinstance(obj, (set, frozenset)):  # iteration order varies with hash randomization
        return {"set": sorted((canonical(o, depth + 1) for o in obj), key=lambda c: json.dumps(c, sort_keys=True))}
    if isinstance(obj, types.ModuleType):
        return {"module": obj.__name__, "source": module_hash(obj.__name__)}
    text = repr(obj)
    if " at 0x" not in text and not _top_level_is_ours(str(type(obj).__module__).partition(".")[0]):
        return text  # a library value (a Path, a Decimal): its repr is its state
    return {"object": canonical(type(obj), depth + 1), "state": _state(obj, depth)}


def _state(obj: Any, depth: int) -> Any:
    """An instance's full state: its attributes (``__dict__`` and ``__slots__``), canonical and
    recursive; else the SHA-256 of its pickled bytes; else its repr (never a memory address)."""
    attrs: dict[str, Any] = dict(getattr(obj, "__dict__", None) or {})
    for cls in type(obj).__mro__:
        slots = cls.__dict__.get("__slots__", ())
        for slot in (slots,) if isinstance(slots, str) else slots:
            if slot not in ("__dict__", "__weakref__") and hasattr(obj, slot):
                attrs[slot] = getattr(obj, slot)
    if attrs:
        return canonical(attrs, depth + 1)
    try:
        import pickle

        return {"pickle_sha": hashlib.sha256(pickle.dumps(obj, protocol=4)).hexdigest()[:16]}
    except Exception:  # noqa: BLE001 - an object that does not pickle: its repr, without addresses
        import re

        return re.sub(r" at 0x[0-9a-fA-F]+", "", repr(obj))


def compensator_identity(compensator: Any) -> str:
    """A stable JSON description of a compensator (class or function, parameters, source hash).

    Parameters
    ----------
    compensator : object
        The compensator.

    Returns
    -------
    str
        JSON text.
    """
    return json.dumps(
        canonical(resolve_compensator(compensator)), sort_keys=True, separators=(",", ":")
    )


def scenario_identity(module: types.ModuleType, config: Any) -> dict[str, Any]:
    """What identifies a scenario's results, as a JSON-able dict.

    What identifies a scenario's results: its module name, the hash of its source closure
    (:func:`module_hash`), the library versions (:func:`versions`) and its configuration
    (:func:`canonical`), as a JSON-able dict.

    Parameters
    ----------
    module : module
        The scenario.
    config : object
        Its Config.

    Returns
    -------
    dict of str to object
        The identity.
    """
    return {
        "scenario": module.__name__,
        "scenario_source": module_hash(module.__name__),
        "versions": versions(),
        "config": canonical(config),
    }


def bench_source_hash() -> str:
    """Hash of the bench's own modules (every ``.py`` file of this package).

    Returns
    -------
    str
        Hex digest.
    """
    folder = Path(__file__).parent
    parts = [(p.name, file_hash(str(p))) for p in sorted(folder.glob("*.py"))]
    return hashlib.sha256(json.dumps(parts).encode()).hexdigest()[:16]


def campaign_id(scenario: str | types.ModuleType, compensator: Any, config: Any = None) -> str:
    """Hash of scenario (config, source closure, versions) and compensator (16 hex digits).

    Parameters
    ----------
    scenario : str or module
        The scenario.
    compensator : object
        The compensator.
    config : object
        The scenario's Config (None: its default).

    Returns
    -------
    str
        16 hex digits.
    """
    module = resolve_scenario(scenario)
    if config is None:
        config = module.Config()
    return campaign_id_of(module, config, compensator_identity(compensator))


def campaign_id_of(module: types.ModuleType, config: Any, compensator_ident: str) -> str:
    """The campaign id from a compensator identity already computed.

    :func:`campaign_id` from a compensator identity already computed (by the compensator's own
    process, :mod:`~gyrobench.scenarios.bench.sandbox`, so this process never imports it).

    Parameters
    ----------
    module : module
        The scenario.
    config : object
        Its Config.
    compensator_ident : str
        The compensator's identity (:func:`compensator_identity`).

    Returns
    -------
    str
        16 hex digits.
    """
    ident = {
        **scenario_identity(module, config),
        "bench_source": bench_source_hash(),
        "compensator": json.loads(compensator_ident),
    }
    return hashlib.sha256(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16]
