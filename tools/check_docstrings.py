"""Check that every public function and class of gyrobench has a numpydoc docstring.

Usage::

    python tools/check_docstrings.py                  # every layer; exit 1 when anything fails
    python tools/check_docstrings.py gyrobench.sim    # one package (and its subpackages)
    python tools/check_docstrings.py --count          # failures per module, then the total

``tests/test_docstrings.py`` runs the same check over the packages in :data:`PACKAGES`.

What is public
    A name in a module's ``__all__``; when the module has no ``__all__``, every function and
    class defined in it whose name has no leading underscore. Modules whose own name (or a
    parent package's name) starts with an underscore are private: what they define is public
    only when a public module lists it in its ``__all__``, and it is checked there.

What a docstring must have (an equivalent of numpydoc's validation, GL08, SS06, PR01, PR02,
PR04 and RT01, without the dependency)
    - a docstring whose first line is a one-line summary (a non-empty line followed by a blank
      line or by nothing);
    - a ``Parameters`` section that names every parameter of the signature (``self`` and ``cls``
      excluded; ``*args`` and ``**kwargs`` by their names, with or without the stars), each with
      a type (``name : type``), and names no parameter the signature lacks. For a class the
      signature is its constructor's; a class whose constructor is inherited from outside the
      package (an exception, an enum) needs none. A dataclass may document its fields in an
      ``Attributes`` section instead, since they are both;
    - a ``Returns`` (or ``Yields``) section when a function returns something: its return
      annotation is not ``None``/``NoReturn``, or, unannotated, its body has a ``return value``.
"""

from __future__ import annotations

import argparse
import ast
import dataclasses
import enum
import importlib
import inspect
import pkgutil
import re
import sys
import textwrap
import types
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any

#: the layers whose public names are checked (every subpackage included)
PACKAGES = ("gyrobench.base", "gyrobench.io", "gyrobench.sim", "gyrobench.analysis", "gyrobench.scenarios")

_SECTION = re.compile(r"^([A-Z][A-Za-z ]+)\n-{3,}$", re.M)
_NO_RETURN = {"None", "NoReturn", "Never", "typing.NoReturn", "typing.Never"}


@dataclass(frozen=True)
class Failure:
    """One public name whose docstring misses something.

    Attributes
    ----------
    qualname : str
        The dotted name the object is public under (``module.name``).
    problem : str
        What is missing or wrong, in one line.
    """

    qualname: str
    problem: str

    def __str__(self) -> str:
        return f"{self.qualname}: {self.problem}"


def sections(doc: str) -> dict[str, str]:
    """Split a cleaned numpydoc docstring into its underlined sections.

    Parameters
    ----------
    doc : str
        The docstring, dedented (``inspect.cleandoc``).

    Returns
    -------
    dict of str to str
        Section title (``"Parameters"``, ``"Returns"``, ...) -> the section's text up to the
        next section; the summary and extended summary are under ``""``.
    """
    out: dict[str, str] = {}
    matches = list(_SECTION.finditer(doc))
    out[""] = doc[: matches[0].start()] if matches else doc
    for i, m in enumerate(matches):
        end = matches[i + 1].start() if i + 1 < len(matches) else len(doc)
        out[m.group(1).strip()] = doc[m.end() : end]
    return out


def documented_parameters(section: str) -> dict[str, str]:
    """The entries of a Parameters (or Attributes) section and their types.

    Parameters
    ----------
    section : str
        The section's text, below its underline.

    Returns
    -------
    dict of str to str
        Parameter name (stars stripped) -> its type text (empty when the entry has no
        ``name : type`` form). ``a, b : float`` documents both ``a`` and ``b``.
    """
    out: dict[str, str] = {}
    lines = section.strip("\n").splitlines()
    if not lines:
        return out
    base = min(len(ln) - len(ln.lstrip()) for ln in lines if ln.strip())
    for line in lines:
        if not line.strip() or len(line) - len(line.lstrip()) != base:
            continue
        head, sep, kind = line.strip().partition(" : ")
        if not sep and line.rstrip().endswith(" :"):
            head, kind = line.strip()[:-2], ""
        for name in head.split(","):
            name = name.strip().lstrip("*")
            if name.isidentifier():
                out[name] = kind.strip()
    return out


def _signature_parameters(obj: Any) -> list[str] | None:
    """The names a docstring must document: None when the object has no signature of ours."""
    if inspect.isclass(obj):
        if issubclass(obj, enum.Enum) or getattr(obj, "_is_protocol", False):
            return []
        init = obj.__dict__.get("__init__")
        if init is None:
            own = [c for c in obj.__mro__[1:] if "__init__" in c.__dict__]
            init = own[0].__dict__["__init__"] if own else None
            if init is None or not getattr(init, "__module__", "").startswith("gyrobench"):
                if not (dataclasses.is_dataclass(obj) or _is_namedtuple(obj)):
                    return []
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return None
    return [p for p in sig.parameters if p not in ("self", "cls")]


def _is_namedtuple(obj: Any) -> bool:
    return inspect.isclass(obj) and issubclass(obj, tuple) and hasattr(obj, "_fields")


def _returns_something(func: Any) -> bool | None:
    """Whether a function returns a value: True, False, or None when it yields (a generator)."""
    func = inspect.unwrap(func)
    if inspect.isgeneratorfunction(func):
        return None
    ann = inspect.signature(func).return_annotation
    if ann is not inspect.Signature.empty:
        text = ann if isinstance(ann, str) else getattr(ann, "__name__", repr(ann))
        return text not in _NO_RETURN and ann is not None and ann is not type(None)
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    except (OSError, TypeError, SyntaxError):
        return False
    top = tree.body[0]
    for node in _own_nodes(top):
        if isinstance(node, ast.Return) and node.value is not None:
            if not (isinstance(node.value, ast.Constant) and node.value.value is None):
                return True
    return False


def _own_nodes(func: ast.AST) -> Iterator[ast.AST]:
    """The nodes of a function's body, not of functions or classes nested in it."""
    stack = list(ast.iter_child_nodes(func))
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            stack.extend(ast.iter_child_nodes(node))


def check_object(qualname: str, obj: Any) -> list[Failure]:
    """Check one public function or class.

    Parameters
    ----------
    qualname : str
        The name it is public under, for the messages.
    obj : object
        The function or class.

    Returns
    -------
    list of Failure
        Empty when the docstring has all it must have.
    """
    raw = obj.__dict__.get("__doc__") if inspect.isclass(obj) else getattr(obj, "__doc__", None)
    if not raw or not raw.strip():
        return [Failure(qualname, "no docstring")]
    doc = inspect.cleandoc(raw)
    fails = []
    lines = doc.splitlines()
    if not lines[0].strip() or (len(lines) > 1 and lines[1].strip()):
        fails.append(Failure(qualname, "summary is not one line followed by a blank line"))
    secs = sections(doc)
    names = _signature_parameters(obj)
    if names:
        key = "Parameters"
        if key not in secs and inspect.isclass(obj) and "Attributes" in secs:
            key = "Attributes"
        if key not in secs:
            fails.append(Failure(qualname, f"no Parameters section (parameters: {', '.join(names)})"))
        else:
            documented = documented_parameters(secs[key])
            missing = [n for n in names if n not in documented]
            untyped = [n for n in names if documented.get(n) == ""]
            extra = [n for n in documented if n not in names] if key == "Parameters" else []
            if missing:
                fails.append(Failure(qualname, f"{key} does not name: {', '.join(missing)}"))
            if untyped:
                fails.append(Failure(qualname, f"{key} gives no type for: {', '.join(untyped)}"))
            if extra:
                fails.append(Failure(qualname, f"Parameters names what the signature lacks: {', '.join(extra)}"))
    if not inspect.isclass(obj) and callable(obj):
        returns = _returns_something(obj)
        if returns is None and "Yields" not in secs:
            fails.append(Failure(qualname, "a generator with no Yields section"))
        elif returns and "Returns" not in secs and "Yields" not in secs:
            fails.append(Failure(qualname, "returns a value but has no Returns section"))
    return fails


def public_names(module: types.ModuleType) -> list[tuple[str, Any]]:
    """The public functions and classes of a module.

    Parameters
    ----------
    module : module
        An imported module.

    Returns
    -------
    list of (str, object)
        ``(name, object)`` for each name of ``__all__`` that is a function or class, or, with
        no ``__all__``, for each function and class defined in the module whose name has no
        leading underscore.
    """
    exported = getattr(module, "__all__", None)
    out = []
    if exported is not None:
        for name in exported:
            obj = getattr(module, name, None)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                out.append((name, obj))
        return out
    for name, obj in vars(module).items():
        if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        if getattr(obj, "__module__", None) == module.__name__:
            out.append((name, obj))
    return out


def modules(package: str) -> Iterator[types.ModuleType]:
    """Import a package and every public module below it.

    Parameters
    ----------
    package : str
        A dotted package or module name.

    Yields
    ------
    module
        The package, then each public submodule (no name part with a leading underscore).
    """
    root = importlib.import_module(package)
    yield root
    if not hasattr(root, "__path__"):
        return
    for info in pkgutil.walk_packages(root.__path__, prefix=package + ".", onerror=lambda name: None):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        yield importlib.import_module(info.name)


def check(packages: Iterable[str] = PACKAGES) -> list[Failure]:
    """Check every public function and class below the given packages.

    Parameters
    ----------
    packages : iterable of str
        Dotted package names.

    Returns
    -------
    list of Failure
        Every failure, each public object checked once and named where it is defined
        (``module.qualname``), whichever public module exports it.
    """
    seen: set[int] = set()
    fails: list[Failure] = []
    for package in packages:
        for module in modules(package):
            for name, obj in public_names(module):
                if id(obj) in seen:
                    continue
                seen.add(id(obj))
                home = getattr(obj, "__module__", "") or ""
                where = f"{home}.{obj.__qualname__}" if home.startswith("gyrobench") else f"{module.__name__}.{name}"
                fails.extend(check_object(where, obj))
    return fails


def main(argv: list[str] | None = None) -> int:
    """List the docstring failures of the given packages.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (``sys.argv[1:]`` when None).

    Returns
    -------
    int
        0 when nothing fails, else 1.
    """
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("packages", nargs="*", default=list(PACKAGES), help="dotted package names")
    parser.add_argument("--count", action="store_true", help="failures per module and the total")
    args = parser.parse_args(argv)
    fails = check(args.packages)
    if args.count:
        per: dict[str, int] = {}
        for f in fails:
            per[f.qualname.rsplit(".", 1)[0]] = per.get(f.qualname.rsplit(".", 1)[0], 0) + 1
        for mod, n in sorted(per.items()):
            print(f"{n:5d}  {mod}")
    else:
        for f in fails:
            print(f)
    print(f"{len(fails)} failure(s) in {len({f.qualname for f in fails})} public name(s)", file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
