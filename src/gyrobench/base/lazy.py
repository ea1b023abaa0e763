"""Lazy package attributes: a package names its public objects and the submodules defining them,
and each is imported on first use, so importing the package costs nothing until a name is used.

Every ``gyrobench`` package's ``__init__`` uses :func:`attach` (PEP 562 module ``__getattr__``
and ``__dir__``); the pattern is that of scientific-python's ``lazy_loader.attach``.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["attach"]


def attach(
    package: str, names: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package`` for the lazily imported ``names``.

    Parameters
    ----------
    package : str
        The package's ``__name__`` (named in the AttributeError of an unknown name).
    names : mapping of str to str
        Public name -> the module that defines it.

    Returns
    -------
    getattr, dir : callable
        Assign them to the package's ``__getattr__`` and ``__dir__``. A name is looked up in its
        module on every access and never cached in the package: a caller that drops submodules
        from ``sys.modules`` (pytest's pytester between inline runs) gets the objects of the
        modules it re-imports, never a stale class.
    """
    table = dict(names)

    def __getattr__(name: str) -> Any:
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(module), name)

    def __dir__() -> list[str]:
        mod = importlib.import_module(package)
        return sorted(set(vars(mod)) | set(table))

    return __getattr__, __dir__
