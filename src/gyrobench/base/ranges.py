"""The one config system: declared field specs and the validation derived from them.

A frozen configuration dataclass (a paper's ``Config``, a profile, a part, a device family)
declares, as class attributes,

``RANGES: ClassVar[Mapping[str, FieldRange | FieldChoice]]``
    one spec per field: a :class:`FieldRange` (valid range, unit, integer or not, and ``why``:
    what the field is and what sets its bounds) for every numeric field, a
    :class:`FieldChoice` for a text field that takes one of a few values;
``CONSTRAINTS: ClassVar[tuple[Constraint, ...]]``
    the cross-field constraints (``low_degC < high_degC``), each a named predicate with the
    message that names the fields, the constraint, the unit and the values;

and its ``__post_init__`` calls :func:`validate` (then builds whatever it delegates to, which
validates itself). ``bool`` and ``Literal[...]`` fields are checked from their annotation. The
configuration layer (:func:`gyrobench.scenarios.registry.override`, the TOML loaders and the
command line's overrides) checks each value with :func:`check_field` before building, so a
value gets the same one-line message wherever it is given. This is scikit-learn's
``_parameter_constraints`` (a class-level mapping from parameter to constraint, checked by
one function) for frozen dataclasses.

Kept free of numpy so the command line's flag types can use it without importing anything
heavy (``gyrobench --help`` imports only the standard library)."""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Callable
from dataclasses import dataclass
from numbers import Integral, Real
from typing import Any

__all__ = [
    "Constraint",
    "FieldChoice",
    "FieldRange",
    "as_array",
    "as_tuple",
    "check_field",
    "check_ranges",
    "field_range",
    "field_spec",
    "finite_array",
    "ordered",
    "range_error",
    "shown",
    "validate",
]


@dataclass(frozen=True, slots=True)
class FieldRange:
    """The documented valid range of one numeric configuration field, in the field's own unit.

    A scenario's ``Config`` (and any dataclass nested in it) states these as the class
    attribute ``RANGES: ClassVar[Mapping[str, FieldRange]]``, one per numeric field; the
    configuration layer (:func:`gyrobench.scenarios.registry.override`) and the config's own
    ``__post_init__`` (:func:`check_ranges`) refuse a value outside it in one line naming the
    field, the range and the unit. Declare it as
    ``RANGES: ClassVar[Mapping[str, FieldRange]] = {...}`` (``ClassVar`` imported from
    :mod:`typing` in that module, so the dataclass does not take it for a field). The bounds
    are physical (what the model is valid for) or practical (what one run can hold), as
    ``why`` says.

    Parameters
    ----------
    low, high : float
        Bounds, in ``unit``; each inclusive unless ``low_open`` / ``high_open``.
    unit : str
        The field's unit as a user writes it (``"m"``, ``"degC/min"``, ``"1"`` for a pure number).
    why : str
        What sets the bounds (shown by nothing; read by a maintainer and the meta-test's failures).
    low_open, high_open : bool
        The bound is exclusive.
    integer : bool
        The field holds an integer count.
    infinite : bool
        An infinite value is valid where its bound is infinite (``high = inf`` admits
        ``inf``: "no limit", "off"); otherwise every value must be finite.
    """

    low: float
    high: float
    unit: str
    why: str = ""
    low_open: bool = False
    high_open: bool = False
    integer: bool = False
    infinite: bool = False

    def contains(self, value: object) -> bool:
        """Whether a value lies in the range.

        Parameters
        ----------
        value : object
            The candidate value.

        Returns
        -------
        bool
            True when ``value`` is a real number (numpy's too, never a bool) inside the range:
            finite, or infinite at an infinite bound when ``infinite`` is set.
        """
        if isinstance(value, bool) or not isinstance(value, Real):
            return False
        if isinstance(value, Integral) and abs(int(value)) > 2**63 - 1:  # never converted to float (10**400)
            return False
        v = float(value)
        if math.isnan(v):
            return False
        if math.isinf(v):
            return self.infinite and v == (self.high if v > 0 else self.low)
        above = v > self.low if self.low_open else v >= self.low
        below = v < self.high if self.high_open else v <= self.high
        return above and below

    def text(self) -> str:
        """The range as a user reads it: ``"(0, 1e+05] m"``, ``"> 0 Hz"`` (no upper bound),
        ``"a finite number [K]"`` (no bound)."""
        text = self._bounds()
        return f"{text} or inf".rstrip() if self.infinite and math.isinf(self.high) else text

    def _bounds(self) -> str:
        kind = "an integer " if self.integer else ""
        lo_inf, hi_inf = math.isinf(self.low), math.isinf(self.high)
        if lo_inf and hi_inf:
            return f"an integer [{self.unit}]" if self.integer else f"a finite number [{self.unit}]"
        if hi_inf:
            return f"{kind}{'>' if self.low_open else '>='} {self.low:g} {self.unit}".rstrip()
        if lo_inf:
            return f"{kind}{'<' if self.high_open else '<='} {self.high:g} {self.unit}".rstrip()
        lo, hi = ("(" if self.low_open else "["), (")" if self.high_open else "]")
        return f"{kind + 'in ' if kind else ''}{lo}{self.low:g}, {self.high:g}{hi} {self.unit}".rstrip()


@dataclass(frozen=True, slots=True)
class FieldChoice:
    """A text field's declared values: it takes one of ``choices``.

    Parameters
    ----------
    choices : tuple of str
        The values the field accepts.
    why : str
        What the field selects.
    """

    choices: tuple[str, ...]
    why: str = ""

    def contains(self, value: object) -> bool:
        """True when ``value`` is one of the choices."""
        return isinstance(value, str) and value in self.choices

    def text(self) -> str:
        """The choices as a user reads them: ``"one of ('a', 'b')"``."""
        return f"one of {self.choices}"


@dataclass(frozen=True, slots=True)
class Constraint:
    """A declared constraint across fields: a named predicate and its one-line message.

    Parameters
    ----------
    name : str
        The constraint as a formula of field names (``"low_degC < high_degC"``).
    holds : callable
        ``holds(config) -> bool``; evaluated after every field passed its own spec.
    message : callable
        ``message(config) -> str``: the refusal after ``"<Class>."``, naming the field, the
        constraint, the unit and the values (``"low_degC must be < high_degC; got 5 and 1"``).
    error : type
        The exception raised when it does not hold: ``ValueError`` (a wrong value), or
        ``TypeError`` for a constraint on a field's kind (``"gyros must be three sensor specs"``).
    """

    name: str
    holds: Callable[[Any], bool]
    message: Callable[[Any], str]
    error: type[Exception] = ValueError


def ordered(low: str, high: str, *, strict: bool = True, unit: str = "") -> Constraint:
    """The declared constraint that one field is below another.

    The constraint ``low < high`` (``low <= high`` when not ``strict``) between two fields,
    refused as ``"<low> must be < <high> [unit]; got <a> and <b>"``.

    Parameters
    ----------
    low, high : str
        The two fields' names.
    strict : bool
        ``low < high`` when True, ``low <= high`` when False.
    unit : str
        Their common unit, for the message ("" for none).

    Returns
    -------
    Constraint
        For a ``CONSTRAINTS`` tuple; refused as ``"<low> must be < <high> [unit]; got <a> and <b>"``.
    """
    op = "<" if strict else "<="
    where = f" [{unit}]" if unit else ""

    def holds(c: Any) -> bool:
        a, b = getattr(c, low), getattr(c, high)
        return bool(a < b) if strict else bool(a <= b)

    def message(c: Any) -> str:
        return f"{low} must be {op} {high}{where}; got {getattr(c, low)!r} and {getattr(c, high)!r}"

    return Constraint(f"{low} {op} {high}", holds, message)


def shown(value: object) -> str:
    """A value as one line of a refusal: an array by its shape, anything else by its repr.

    Parameters
    ----------
    value : object
        The refused value.

    Returns
    -------
    str
        ``"an array of shape (2, 3)"`` (``"... with a non-finite value"`` when it holds one) for
        an array, else ``repr(value)`` with its line breaks removed.
    """
    shape = getattr(value, "shape", None)
    if isinstance(shape, tuple) and hasattr(value, "dtype"):
        import numpy as np

        array: Any = value
        try:
            bad = not bool(np.all(np.isfinite(array)))
        except TypeError:  # not numeric
            bad = False
        return f"an array of shape {shape}" + (" with a non-finite value" if bad else "")
    return " ".join(repr(value).split())


def as_array(value: object) -> object:
    """``value`` as a float64 numpy array when it converts, else ``value`` itself (never raising).

    No copy is made of a float64 array.

    A ``__post_init__`` stores its array fields through this before :func:`validate`, so that a
    declared :func:`finite_array` constraint, not numpy, refuses a value that does not convert.

    Parameters
    ----------
    value : object
        An array-like, None or anything else.

    Returns
    -------
    object
        A float64 array, or ``value`` unchanged (None, or something that is not numeric).
    """
    if value is None:
        return None
    import numpy as np

    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return value


def as_tuple(value: object) -> object:
    """``value`` as a tuple when it is a list, else ``value`` itself (never raising).

    Parameters
    ----------
    value : object
        A list, a tuple or anything else.

    Returns
    -------
    object
        A tuple for a list; ``value`` unchanged otherwise (a declared constraint then judges it).
    """
    return tuple(value) if isinstance(value, list) else value


def finite_array(name: str, shape: tuple[int | None, ...], unit: str = "", *, optional: bool = False) -> Constraint:
    """The declared constraint that a field is a finite float array of a given shape.

    Parameters
    ----------
    name : str
        The field's name.
    shape : tuple of int or None
        The required shape; None on an axis admits any length >= 1.
    unit : str
        The unit, for the message ("" for none).
    optional : bool
        None is also accepted.

    Returns
    -------
    Constraint
        For a ``CONSTRAINTS`` tuple; refused as ``"<name> must be a finite array of shape (3, 3)
        [unit]; got an array of shape (2, 3)"``.
    """
    text = "(" + ", ".join("n" if n is None else str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"
    where = f" [{unit}]" if unit else ""
    extra = " or None" if optional else ""

    def holds(c: Any) -> bool:
        import numpy as np

        v = getattr(c, name)
        if v is None:
            return optional
        return (
            isinstance(v, np.ndarray)
            and v.ndim == len(shape)
            and all(n is None and m >= 1 or n == m for n, m in zip(shape, v.shape, strict=True))
            and bool(np.all(np.isfinite(v)))
        )

    def message(c: Any) -> str:
        return f"{name} must be a finite array of shape {text}{where}{extra}; got {shown(getattr(c, name))}"

    return Constraint(f"{name} is a finite array of shape {text}", holds, message)


def field_spec(config_type: type, name: str) -> FieldRange | FieldChoice | None:
    """The declared spec of one field of a configuration class.

    The declared spec of field ``name`` of the dataclass ``config_type`` (its ``RANGES``
    entry), or None when it declares none.

    Parameters
    ----------
    config_type : type
        The dataclass.
    name : str
        The field's name.

    Returns
    -------
    FieldRange, FieldChoice or None
        Its ``RANGES`` entry; None when it declares none.
    """
    specs = getattr(config_type, "RANGES", None) or {}
    return specs.get(name)


def field_range(config_type: type, name: str) -> FieldRange | None:
    """The declared numeric range of one field of a configuration class.

    The documented :class:`FieldRange` of field ``name`` of the dataclass ``config_type`` (None
    when it states none, or a :class:`FieldChoice`).

    Parameters
    ----------
    config_type : type
        The dataclass.
    name : str
        The field's name.

    Returns
    -------
    FieldRange or None
        The field's :class:`FieldRange`; None when it declares none or a :class:`FieldChoice`.
    """
    spec = field_spec(config_type, name)
    return spec if isinstance(spec, FieldRange) else None


def range_error(owner: str, name: str, rng: FieldRange, value: Any) -> ValueError:
    """The one-line error for ``value`` outside ``rng`` (a huge integer shown by its size only).

    Parameters
    ----------
    owner : str
        The class named in the message.
    name : str
        The field (``name[i]`` for an element of a tuple).
    rng : FieldRange
        The range the value left.
    value : object
        The refused value (an integer of more than 30 digits is shown by its size only).

    Returns
    -------
    ValueError
        ``"<owner>.<name> must be <range with unit>; got <value>"``, to be raised by the caller.
    """
    shown = f"an integer of {len(str(abs(value)))} digits" if isinstance(value, int) and abs(value) > 10**30 else (
        repr(value)
    )
    return ValueError(f"{owner}.{name} must be {rng.text()}; got {shown}")


def _annotation_kinds(config_type: type) -> dict[str, Any]:
    """field -> ``bool``, a dataclass type or a tuple of ``Literal`` values, from the dataclass's
    annotations."""
    cached = _KINDS.get(config_type)
    if cached is None:
        cached = {}
        try:
            hints = typing.get_type_hints(config_type)
        except (NameError, TypeError):  # a base's annotation does not resolve: field by field
            hints = _field_hints(config_type)
        for f in dataclasses.fields(config_type):
            hint = hints.get(f.name)
            if hint is bool or (isinstance(hint, type) and dataclasses.is_dataclass(hint)):
                cached[f.name] = hint
            elif typing.get_origin(hint) is tuple:
                cached[f.name] = tuple
            elif typing.get_origin(hint) is typing.Literal:
                cached[f.name] = typing.get_args(hint)
        _KINDS[config_type] = cached
    return cached


_KINDS: dict[type, dict[str, Any]] = {}


def _field_hints(config_type: type) -> dict[str, Any]:
    """field -> its resolved annotation, each evaluated in the module of the class that declares
    it (a field whose annotation does not resolve there is left out: no derived check)."""
    import sys

    out: dict[str, Any] = {}
    for f in dataclasses.fields(config_type):
        owner = next((c for c in config_type.__mro__ if f.name in c.__dict__.get("__annotations__", {})), config_type)
        try:
            out[f.name] = typing.get_type_hints(
                type("_Field", (), {"__annotations__": {f.name: f.type}, "__module__": owner.__module__}),
                globalns=vars(sys.modules[owner.__module__]),
            )[f.name]
        except (NameError, TypeError, KeyError):
            continue
    return out


def check_field(owner: str, config_type: type, name: str, value: Any) -> None:
    """Refuse one field's value in one line, by the field's declared spec and annotation.

    Refuse ``value`` for field ``name`` of ``config_type`` in one line, by the field's declared
    spec and annotation: a ``bool`` field takes a bool, a dataclass-typed field an instance of it, a
    ``Literal`` field one of its values, a
    :class:`FieldChoice` field one of its choices, a :class:`FieldRange` field a finite number in
    range (an integer when it says so; None passes: an optional field left unset); a tuple is
    checked element by element.

    Parameters
    ----------
    owner : str
        The class named in the message.
    config_type : type
        The dataclass that declares the field (its ``RANGES`` and annotations).
    name : str
        The field.
    value : object
        The value given for it.

    Raises
    ------
    TypeError
        A ``bool`` or dataclass-typed field given anything else, a numeric field given a
        non-number.
    ValueError
        Naming ``owner.name``, the constraint with its unit, and the value.
    """
    kind = _annotation_kinds(config_type).get(name)
    if kind is bool and not isinstance(value, bool):
        raise TypeError(f"{owner}.{name} must be a bool; got {value!r}")
    if kind is tuple:  # a tuple field with a declared spec must hold a tuple (a list is not frozen)
        if field_spec(config_type, name) is not None and not isinstance(value, tuple):
            raise TypeError(f"{owner}.{name} must be a tuple; got {type(value).__name__} {shown(value)}")
    elif isinstance(kind, type) and kind is not bool and not isinstance(value, kind):
        raise TypeError(f"{owner}.{name} must be a {kind.__name__}; got {type(value).__name__}")
    if isinstance(kind, tuple) and value not in kind:
        raise ValueError(f"{owner}.{name} must be one of {list(kind)}; got {value!r}")
    spec = field_spec(config_type, name)
    if spec is None:
        return
    values = value if isinstance(value, tuple) else (value,)
    for i, v in enumerate(values):
        key = f"{name}[{i}]" if isinstance(value, tuple) else name
        if isinstance(spec, FieldChoice):
            if not spec.contains(v):
                why = f" ({spec.why})" if spec.why else ""
                raise ValueError(f"{owner}.{key} must be {spec.text()}{why}; got {v!r}")
        elif v is not None:
            if isinstance(v, bool) or not isinstance(v, Real):
                raise TypeError(f"{owner}.{key} must be a real number [{spec.unit}]; got {v!r}")
            if not spec.contains(v) or (spec.integer and not isinstance(v, Integral)):
                raise range_error(owner, key, spec, v)


def validate(config: Any) -> None:
    """Check a configuration dataclass against its declared field specs and constraints.

    Check the dataclass ``config`` against its declarations, in one line per refusal: every
    field by :func:`check_field` (in declaration order), then every declared
    :class:`Constraint` of its ``CONSTRAINTS`` (in order). A config's ``__post_init__`` calls
    it; nothing else is hand-written there. Fields with ``init=False`` (what the class derives
    after validating) are not checked.

    Parameters
    ----------
    config : dataclass instance
        The configuration (its class declares ``RANGES`` and, optionally, ``CONSTRAINTS``).

    Raises
    ------
    TypeError, ValueError
        Naming the class, the field, the constraint with its unit and the value.
    """
    cls = type(config)
    owner = cls.__name__
    for f in dataclasses.fields(cls):
        if f.init:  # a field the class derives (init=False) is set after validation
            check_field(owner, cls, f.name, getattr(config, f.name))
    for c in getattr(cls, "CONSTRAINTS", ()):
        if not c.holds(config):
            raise c.error(f"{owner}.{c.message(config)}")


def check_ranges(config: Any) -> None:
    """Refuse, in one line, any field of a dataclass outside its declared range.

    Refuse, in one line, any field of the dataclass ``config`` outside its documented range
    (:class:`FieldRange`, the class attribute ``RANGES``). A None value (an optional field left
    unset) passes; a tuple is checked element by element.

    Parameters
    ----------
    config : dataclass instance
        The configuration whose class declares ``RANGES``.

    Raises
    ------
    ValueError
        Naming the field, its range with unit and the value.
    """
    cls = type(config)
    for name, rng in (getattr(cls, "RANGES", None) or {}).items():
        value = getattr(config, name)
        values = value if isinstance(value, tuple) else (value,)
        for i, v in enumerate(values):
            if v is None:
                continue
            key = f"{name}[{i}]" if isinstance(value, tuple) else name
            if not rng.contains(v) or (rng.integer and not isinstance(v, Integral)):
                raise range_error(cls.__name__, key, rng, v)
