"""A data-only JSON codec for the papers' typed unit results: no pickle, no code from data.

A stored unit result must never run code when it is read back (a crafted database is data,
not a program). :func:`dumps` writes a JSON document with a schema tag; :func:`loads` reads
it and builds ONLY these values:

==========================  =================================================================
JSON node                   value
==========================  =================================================================
``null``, bool, int, str    itself
number                      float (``{"$float": "nan"|"inf"|"-inf"}`` for non-finite ones)
list                        list
``{"$tuple": [...]}``       tuple
``{"$dict": [[k, v]...]}``  dict (keys decoded like values: any hashable value above)
``{"$nd": ...}``            numpy array: ``dtype`` (numeric kinds b/i/u/f/c only, as
                            ``numpy.dtype.str``), ``shape``, ``data`` (base64 raw bytes,
                            C order); its byte count is checked before it is read
``{"$np": ...}``            numpy scalar (the same fields, no shape)
``{"$dc": ...}``            a frozen dataclass named ``type`` (``module:qualname``) with
                            ``fields``; the module must lie under ``gyrobench.`` and the
                            class must be a frozen dataclass defined in it, whose fields are
                            exactly the stored ones
==========================  =================================================================

Anything else (an unknown tag, a type outside ``gyrobench``, a class that is not a frozen
dataclass, a missing or extra field, an object dtype) is refused with one
:class:`CodecError` line naming the path inside the document. Decoding imports only modules
of the ``gyrobench`` package itself and calls only a frozen dataclass's own constructor.
Arrays round-trip bit-identically (dtype, byte order, shape, every byte, NaN payloads).

A stored row is :func:`dumps_compressed`: the document zlib-compressed (level 6) after the
magic :data:`COMPRESSED_MAGIC`; :func:`loads` reads it back (refusing a stream that would inflate
beyond :data:`MAX_DOCUMENT_BYTES`, a crafted "zip bomb") as well as the plain text.
"""

from __future__ import annotations

import base64
import dataclasses
import importlib
import json
import math
import re
import zlib
from typing import Any

import numpy as np

__all__ = ["COMPRESSED_MAGIC", "MAX_DOCUMENT_BYTES", "SCHEMA", "CodecError", "dumps", "dumps_compressed", "loads"]

#: the schema tag of a stored document (bumped when the format changes)
SCHEMA = "gyrobench.unit-result/1"

#: the only package whose dataclasses are decoded
_PACKAGE = "gyrobench"
_MODULE_RE = re.compile(r"^gyrobench(\.[A-Za-z_][A-Za-z0-9_]*)+$")
_QUALNAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")
_NUMERIC_KINDS = frozenset("biufc")
#: the largest array one node may declare (bytes), checked before its data is decoded
MAX_ARRAY_BYTES = 1 << 31
_MAX_DEPTH = 64
#: the first bytes of a compressed document (:func:`dumps_compressed`)
COMPRESSED_MAGIC = b"GBZ1"
#: the largest document a compressed row may inflate to (bytes)
MAX_DOCUMENT_BYTES = 1 << 31


class CodecError(ValueError):
    """A stored document that is not a unit result this codec writes (one line)."""


def _is_frozen_dataclass_type(cls: Any) -> bool:
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        return False
    params: Any = cls.__dict__.get("__dataclass_params__")
    return params is not None and bool(params.frozen)


def _encode(value: Any, path: str) -> Any:
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int) and not isinstance(value, np.generic):
        return int(value)
    if isinstance(value, float) and not isinstance(value, np.generic):
        return float(value) if math.isfinite(value) else {"$float": repr(float(value))}
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in _NUMERIC_KINDS:
            raise CodecError(f"{path}: array of dtype {value.dtype} cannot be stored (numeric dtypes only)")
        return {"$nd": {"dtype": value.dtype.str, "shape": list(value.shape),
                        "data": base64.b64encode(np.ascontiguousarray(value).tobytes()).decode("ascii")}}
    if isinstance(value, np.generic):
        if value.dtype.kind not in _NUMERIC_KINDS:
            raise CodecError(f"{path}: numpy scalar of dtype {value.dtype} cannot be stored")
        return {"$np": {"dtype": value.dtype.str, "data": base64.b64encode(value.tobytes()).decode("ascii")}}
    if isinstance(value, tuple):
        return {"$tuple": [_encode(v, f"{path}[{i}]") for i, v in enumerate(value)]}
    if isinstance(value, list):
        return [_encode(v, f"{path}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, dict) or type(value).__name__ == "mappingproxy":
        return {"$dict": [[_encode(k, f"{path}.key"), _encode(v, f"{path}[{k!r}]")] for k, v in value.items()]}
    cls = type(value)
    if _is_frozen_dataclass_type(cls) and cls.__module__.startswith(_PACKAGE + "."):
        fields = {f.name: _encode(getattr(value, f.name), f"{path}.{f.name}") for f in dataclasses.fields(value)}
        return {"$dc": {"type": f"{cls.__module__}:{cls.__qualname__}", "fields": fields}}
    raise CodecError(
        f"{path}: a value of type {cls.__module__}.{cls.__qualname__} cannot be stored (only None, bool, int, "
        "float, str, list, tuple, dict, numeric numpy arrays and scalars, and frozen gyrobench dataclasses)"
    )


def dumps(value: Any) -> str:
    """``value`` as a JSON document of this codec's schema (:data:`SCHEMA`).

    Parameters
    ----------
    value : object
        A unit's result: frozen dataclasses of the gyrobench package, numpy arrays and
        scalars, and containers of them (the module docstring lists the nodes).

    Returns
    -------
    str
        The JSON document.

    Raises
    ------
    CodecError
        A value the codec does not store, with its path (e.g. ``result.figures.t``).
    """
    return json.dumps({"schema": SCHEMA, "value": _encode(value, "result")}, allow_nan=False,
                      separators=(",", ":"))


def dumps_compressed(value: Any) -> bytes:
    """:func:`dumps` of ``value``, zlib-compressed (level 6) after :data:`COMPRESSED_MAGIC`.

    Parameters
    ----------
    value : object
        A value :func:`dumps` can store.

    Returns
    -------
    bytes
        :data:`COMPRESSED_MAGIC` then the zlib-compressed document.
    """
    return COMPRESSED_MAGIC + zlib.compress(dumps(value).encode("utf-8"), 6)


def _inflate(raw: bytes) -> bytes:
    """The document inside a compressed row, or a one-line refusal (corrupt, or too large)."""
    d = zlib.decompressobj()
    try:
        out = d.decompress(raw[len(COMPRESSED_MAGIC):], MAX_DOCUMENT_BYTES + 1)
    except zlib.error as exc:
        raise CodecError(f"stored result is not a valid compressed document ({exc}); refused") from None
    if len(out) > MAX_DOCUMENT_BYTES:
        raise CodecError(f"stored result inflates beyond {MAX_DOCUMENT_BYTES} bytes; refused")
    if not d.eof:
        raise CodecError("stored result is a truncated compressed document; refused")
    return out


def _class(name: Any, path: str) -> type:
    """The frozen gyrobench dataclass ``module:qualname``, or a one-line refusal."""
    if not isinstance(name, str) or name.count(":") != 1:
        raise CodecError(f"{path}: type {name!r} is not 'module:class'")
    mod_name, qualname = name.split(":")
    if not _MODULE_RE.match(mod_name) or not _QUALNAME_RE.match(qualname):
        raise CodecError(f"{path}: type {name!r} is outside the {_PACKAGE} package; refused")
    try:
        module = importlib.import_module(mod_name)
    except ImportError:
        raise CodecError(f"{path}: type {name!r}: no module {mod_name!r} in {_PACKAGE}") from None
    obj: Any = module
    for part in qualname.split("."):
        obj = obj.__dict__.get(part) if hasattr(obj, "__dict__") else None
        if obj is None:
            raise CodecError(f"{path}: type {name!r} does not exist")
    if not _is_frozen_dataclass_type(obj) or obj.__module__ != mod_name:
        raise CodecError(f"{path}: type {name!r} is not a frozen dataclass of {mod_name}; refused")
    return obj


def _array_fields(node: Any, path: str, *, scalar: bool) -> tuple[np.dtype, tuple[int, ...], bytes]:
    want = {"dtype", "data"} if scalar else {"dtype", "shape", "data"}
    if not isinstance(node, dict) or set(node) != want:
        raise CodecError(f"{path}: array node must have exactly the keys {sorted(want)}")
    try:
        dtype = np.dtype(node["dtype"]) if isinstance(node["dtype"], str) else None
    except TypeError:
        dtype = None
    if dtype is None or dtype.kind not in _NUMERIC_KINDS or dtype.str != node["dtype"]:
        raise CodecError(f"{path}: array dtype {node['dtype']!r} is not a numeric numpy dtype")
    shape_raw = [] if scalar else node["shape"]
    if not isinstance(shape_raw, list) or not all(type(n) is int and n >= 0 for n in shape_raw):
        raise CodecError(f"{path}: array shape {shape_raw!r} is not a list of integers >= 0")
    shape = tuple(shape_raw)
    n_bytes = math.prod(shape) * dtype.itemsize
    if n_bytes > MAX_ARRAY_BYTES:
        raise CodecError(f"{path}: array of {n_bytes} bytes exceeds the limit {MAX_ARRAY_BYTES}")
    data = node["data"]
    if not isinstance(data, str) or len(data) != 4 * ((n_bytes + 2) // 3):
        raise CodecError(f"{path}: array data does not hold {n_bytes} bytes for dtype {dtype.str} shape {shape}")
    try:
        raw = base64.b64decode(data, validate=True)
    except ValueError:
        raise CodecError(f"{path}: array data is not base64") from None
    if len(raw) != n_bytes:
        raise CodecError(f"{path}: array data holds {len(raw)} bytes, not {n_bytes}")
    return dtype, shape, raw


def _decode(node: Any, path: str, depth: int) -> Any:
    if depth > _MAX_DEPTH:
        raise CodecError(f"{path}: nested deeper than {_MAX_DEPTH} levels")
    if node is None or isinstance(node, (bool, int, str)):
        return node
    if isinstance(node, float):
        return node
    if isinstance(node, list):
        return [_decode(v, f"{path}[{i}]", depth + 1) for i, v in enumerate(node)]
    if not isinstance(node, dict) or len(node) != 1:
        raise CodecError(f"{path}: not a node of schema {SCHEMA} (an object with one tag key)")
    ((tag, body),) = node.items()
    if tag == "$float":
        if body not in ("nan", "inf", "-inf"):
            raise CodecError(f"{path}: $float must be 'nan', 'inf' or '-inf'; got {body!r}")
        return float(body)
    if tag == "$tuple":
        if not isinstance(body, list):
            raise CodecError(f"{path}: $tuple must hold a list")
        return tuple(_decode(v, f"{path}[{i}]", depth + 1) for i, v in enumerate(body))
    if tag == "$dict":
        if not isinstance(body, list) or not all(isinstance(p, list) and len(p) == 2 for p in body):
            raise CodecError(f"{path}: $dict must hold a list of [key, value] pairs")
        out = {}
        for i, (k, v) in enumerate(body):
            key = _decode(k, f"{path}.key{i}", depth + 1)
            try:
                hash(key)
            except TypeError:
                raise CodecError(f"{path}: dict key {i} is not hashable") from None
            out[key] = _decode(v, f"{path}[{key!r}]", depth + 1)
        return out
    if tag == "$nd":
        dtype, shape, raw = _array_fields(body, path, scalar=False)
        return np.frombuffer(raw, dtype=dtype).reshape(shape).copy()
    if tag == "$np":
        dtype, _, raw = _array_fields(body, path, scalar=True)
        return np.frombuffer(raw, dtype=dtype)[0]
    if tag == "$dc":
        return _decode_dataclass(body, path, depth)
    raise CodecError(f"{path}: unknown tag {tag!r} (schema {SCHEMA})")


def _decode_dataclass(body: Any, path: str, depth: int) -> Any:
    if not isinstance(body, dict) or set(body) != {"type", "fields"} or not isinstance(body["fields"], dict):
        raise CodecError(f"{path}: $dc must have exactly the keys 'type' and 'fields' (an object)")
    cls = _class(body["type"], path)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    stored = body["fields"]
    if set(stored) != set(fields):
        raise CodecError(
            f"{path}: {body['type']} has fields {sorted(fields)}; the document has {sorted(stored)}"
        )
    values = {k: _decode(v, f"{path}.{k}", depth + 1) for k, v in stored.items()}
    try:
        obj = cls(**{k: v for k, v in values.items() if fields[k].init})
    except (TypeError, ValueError) as exc:
        raise CodecError(f"{path}: {body['type']} refuses the stored fields: {exc}") from None
    for k, v in values.items():
        if not fields[k].init:
            object.__setattr__(obj, k, v)
    return obj


def loads(text: str | bytes) -> Any:
    """Read back a value stored by :func:`dumps` or :func:`dumps_compressed`.

    The value stored by :func:`dumps` or :func:`dumps_compressed`; never unpickles, imports only
    ``gyrobench`` modules.

    Parameters
    ----------
    text : str or bytes
        A document written by :func:`dumps`.

    Returns
    -------
    object
        The stored value.

    Raises
    ------
    CodecError
        One line: not JSON, not this schema, or a node the codec refuses (with its path).
    """
    if isinstance(text, (bytes, bytearray, memoryview)):
        raw = bytes(text)
        if raw.startswith(COMPRESSED_MAGIC):
            raw = _inflate(raw)
        if raw[:1] == b"\x80":
            raise CodecError("stored result is a pickle (an old or crafted store); refused, never unpickled")
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise CodecError("stored result is not UTF-8 JSON; refused") from None
    try:
        doc = json.loads(text, parse_constant=_no_constant)
    except (ValueError, RecursionError) as exc:
        raise CodecError(f"stored result is not valid JSON ({exc}); refused") from None
    if not isinstance(doc, dict) or set(doc) != {"schema", "value"} or doc["schema"] != SCHEMA:
        got = doc.get("schema") if isinstance(doc, dict) else type(doc).__name__
        raise CodecError(f"stored result is not of schema {SCHEMA!r} (got {got!r}); refused")
    return _decode(doc["value"], "result", 0)


def _no_constant(name: str) -> Any:
    raise CodecError(f"stored result holds the non-JSON constant {name}; refused")
