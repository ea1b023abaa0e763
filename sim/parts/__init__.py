"""Real gyro parts from their public datasheets, and the user's own parts from TOML.

Three lines from a part to a file::

    part = gyrobench.sim.parts.get("stim300")
    rec = part.simulate(Environment(3600.0), fs=100.0, rng=np.random.default_rng(1))
    save_hdf5("stim300.h5", rec)

:func:`names` lists the built-in parts, :func:`get` returns one as a :class:`Part`, and
:func:`load_toml` reads a user's part from a TOML file with the :class:`Datasheet` fields
(one table, or top-level keys). The solve from figures to models is in
:mod:`gyrobench.sim.parts._part` (see :class:`Part`); the figures and their sources in
:mod:`gyrobench.sim.parts._catalogue`. :func:`rlg_spec`, :func:`fog_spec` and :func:`mems_spec` map a
part onto its technology's physics model (the source power, the pick-off noise or the lock-in
rate solved for the sheet's ARW; below the default design's floor the FOG coil or the MEMS proof
mass too, inside the stated physical ranges: :mod:`gyrobench.sim.parts._physics`).
"""

from __future__ import annotations

import os
import sys
from dataclasses import fields
from pathlib import Path

from gyrobench.sim.parts._catalogue import CATALOGUE
from gyrobench.sim.parts._device import MODELS, draw_unit, physics_spec, simulate_part, simulate_unit
from gyrobench.sim.parts._part import (
    ADEV_MIN_PER_B,
    ERROR_COMPONENTS,
    GRADES,
    PHYSICS_MAPPING,
    TECHNOLOGIES,
    Datasheet,
    Part,
    PartUnit,
    oversampling,
)
from gyrobench.sim.parts._physics import (
    BROWNIAN_SHARE,
    FIBRE_LOSS_DB_PER_M,
    FOG_DIAMETER_MAX,
    FOG_LENGTH_MAX,
    FOG_POWER_MAX,
    MEMS_MASS_MAX,
    fog_spec,
    mems_spec,
    physics_summary,
    rlg_spec,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "ADEV_MIN_PER_B",
    "ERROR_COMPONENTS",
    "GRADES",
    "PHYSICS_MAPPING",
    "TECHNOLOGIES",
    "Datasheet",
    "Part",
    "PartUnit",
    "oversampling",
    "get",
    "names",
    "load_toml",
    "loads_toml",
    "datasheets",
    "rlg_spec",
    "fog_spec",
    "mems_spec",
    "physics_summary",
    "physics_spec",
    "simulate_part",
    "draw_unit",
    "simulate_unit",
    "MODELS",
    "FOG_POWER_MAX",
    "FOG_LENGTH_MAX",
    "FOG_DIAMETER_MAX",
    "FIBRE_LOSS_DB_PER_M",
    "MEMS_MASS_MAX",
    "BROWNIAN_SHARE",
]

_BY_NAME = {d.name: d for d in CATALOGUE}


def names() -> list[str]:
    """Keys of the built-in parts, in catalogue order.

    Returns
    -------
    list of str
        The keys.
    """
    return [d.name for d in CATALOGUE]


def datasheets() -> tuple[Datasheet, ...]:
    """The built-in parts' datasheets.

    Returns
    -------
    tuple of Datasheet
        One per built-in part, in catalogue order.
    """
    return CATALOGUE


def get(name: str) -> Part:
    """The built-in part ``name`` (case-insensitive), or a part read from a ``.toml`` path.

    Parameters
    ----------
    name : str
        A key of :func:`names` (case-insensitive) or the path of a ``.toml`` part file.

    Returns
    -------
    Part
        The part.
    """
    if not isinstance(name, str):
        raise TypeError(f"part name must be a str; got {type(name).__name__}")
    if name.lower().endswith(".toml"):
        return load_toml(name)
    key = name.strip().lower()
    if key not in _BY_NAME:
        raise ValueError(f"unknown part {name!r}; built-in parts: {', '.join(names())} (or a .toml file)")
    return Part(_BY_NAME[key])


def load_toml(path: str | os.PathLike) -> Part:
    """A user's part from a TOML file holding the :class:`Datasheet` fields.

    The fields may be top-level keys or the single table ``[part]``. Errors are one line
    naming the file and the key.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file.

    Returns
    -------
    Part
        The part.
    """
    p = Path(path)
    try:
        with p.open("rb") as fh:
            text = fh.read().decode("utf-8")
    except FileNotFoundError:
        raise ValueError(f"part file {str(p)!r} does not exist") from None
    return loads_toml(text, source=f"part file {str(p)!r}")


def loads_toml(text: str, *, source: str = "part file") -> Part:
    """A user's part from the text of a TOML part file (what :func:`load_toml` reads from a file).

    Parameters
    ----------
    text : str
        The TOML text: the :class:`Datasheet` fields as top-level keys or the single table ``[part]``.
    source : str
        What the messages call it (``"part file 'mine.toml'"``).

    Returns
    -------
    Part
        The part.

    Raises
    ------
    ValueError
        One line naming ``source``: not TOML, an unknown key, a field out of its range.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{source} is not valid TOML: {exc}") from None
    if set(data) == {"part"} and isinstance(data["part"], dict):
        data = data["part"]
    known = {f.name for f in fields(Datasheet)}
    unknown = sorted(set(data) - known)
    if unknown:
        raise ValueError(f"{source}: unknown key(s) {unknown}; allowed: {sorted(known)}")
    data = {k: (float(v) if isinstance(v, int) and not isinstance(v, bool) else v) for k, v in data.items()}
    try:
        return Part(Datasheet(**data))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{source}: {exc}") from None
