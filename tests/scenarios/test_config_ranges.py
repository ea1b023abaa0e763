"""Meta-test over EVERY numeric configuration field of every registered scenario (issue 32).

Each numeric field (nested tables too) is fed NaN, +-inf, -1, 0, 1e308 and a huge integer
(10**400) through a TOML file and :func:`gyrobench.scenarios.registry.load_config`, the layer
every verb reads its configuration with. A value is either

* refused fast (under a second) with a one-line ``ValueError`` / ``TypeError`` naming the
  field (the command line prints it and exits 2), or
* accepted, and then it lies inside the field's documented range
  (:class:`gyrobench.scenarios.base.FieldRange`, the config class's ``RANGES``), which states
  the unit.

So no absurd value is accepted without a documented reason, and none reaches a model. Every
registered scenario is walked, nested simulator dataclasses too (their ``RANGES`` live in
``gyrobench.sim``: the FOG loop, optics and mount of paper 000, the MEMS population of paper 001).
"""

from __future__ import annotations

import dataclasses
import math
import time
import typing

import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.base import FieldRange, field_range
from gyrobench.scenarios.cli.main import main

#: the hostile values every numeric field is fed
BAD_VALUES = (math.nan, math.inf, -math.inf, -1, 0, 1e308, 10**400)

#: registered scenarios whose config.py states no RANGES: none since papers 000 and 001 state theirs
#: (kept, empty, for test_fuzz_random, which draws only from scenarios with ranges)
WITHOUT_RANGES: frozenset[str] = frozenset()

NUMERIC = (int, float)


def _numeric_hint(hint: typing.Any) -> bool:
    """int, float, their Optional forms, or a tuple of them."""
    if hint in NUMERIC:
        return True
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    origin = typing.get_origin(hint)
    if origin is tuple:
        return bool(args) and all(a in NUMERIC or a is Ellipsis for a in args)
    return origin in (typing.Union, getattr(__import__("types"), "UnionType", None)) and len(args) == 1 and (
        args[0] in NUMERIC
    )


def numeric_fields(config: typing.Any, path: tuple[str, ...] = ()) -> list[tuple[tuple[str, ...], type, typing.Any]]:
    """Every numeric field of the dataclass ``config`` and of the dataclasses nested in it: its
    key path, the class that declares it and its type hint."""
    out = []
    hints = typing.get_type_hints(type(config))
    for f in dataclasses.fields(config):
        value = getattr(config, f.name)
        if dataclasses.is_dataclass(value):
            out += numeric_fields(value, (*path, f.name))
        elif _numeric_hint(hints[f.name]):
            out.append(((*path, f.name), type(config), hints[f.name]))
    return out


def _toml_value(value: typing.Any, tuple_field: bool) -> str:
    text = {math.nan: "nan", math.inf: "inf", -math.inf: "-inf"}.get(value) if isinstance(value, float) else None
    if text is None:
        text = repr(value)
    if isinstance(value, float) and math.isnan(value):
        text = "nan"
    return f"[{text}]" if tuple_field else text


def _toml(path: tuple[str, ...], value_text: str) -> str:
    *tables, key = path
    header = f"[{'.'.join(tables)}]\n" if tables else ""
    return f"{header}{key} = {value_text}\n"


def _scenarios() -> list[str]:
    return list(registry.available())


def _is_tuple(hint: typing.Any) -> bool:
    return typing.get_origin(hint) is tuple


@pytest.mark.parametrize("name", _scenarios())
def test_every_numeric_field_states_a_range_with_a_unit(name):
    module = registry.get(name)
    missing = []
    for path, owner, _hint in numeric_fields(module.Config()):
        rng = field_range(owner, path[-1])
        if not isinstance(rng, FieldRange) or not rng.unit.strip() or not rng.low <= rng.high:
            missing.append(".".join(path))
    assert not missing, f"{name}: fields without a documented range and unit: {missing}"


@pytest.mark.parametrize("name", _scenarios())
def test_every_numeric_field_refuses_absurd_values_in_one_line_or_documents_them(name, tmp_path):
    module = registry.get(name)
    cfg = tmp_path / "c.toml"
    wrong = []
    for path, owner, hint in numeric_fields(module.Config()):
        rng = field_range(owner, path[-1])
        for value in BAD_VALUES:
            cfg.write_text(_toml(path, _toml_value(value, _is_tuple(hint))))
            t0 = time.monotonic()
            try:
                registry.load_config(module, cfg)
            except (ValueError, TypeError) as exc:  # MemoryLimitError is a ValueError too
                text = str(exc)
                took = time.monotonic() - t0
                if "\n" in text or path[-1] not in text or took > 1.0:
                    wrong.append(f"{'.'.join(path)}={value!r}: refused in {took:.2f} s as {text!r}")
                continue
            if rng is None or not rng.contains(value):
                wrong.append(f"{'.'.join(path)}={value!r}: accepted outside any documented range ({rng})")
    assert not wrong, "\n".join(wrong[:40])


@pytest.mark.parametrize(
    "name, toml, words",
    [
        ("ifog_thermal", "fibre_length_m = -1000\n", "fibre_length_m must be (0, 20000] m; got -1000"),
        ("ifog_thermal", f"validation1_runs = {2 * 10**7}\n", "validation1_runs must be an integer in [1, 1000] runs"),
        ("rlg_thermal", "fs_hz = 1e308\n", "fs_hz must be [0.001, 10000] Hz; got 1e+308"),
        ("rlg_thermal", f"leg_current_ma = {10**400}\n", "leg_current_ma must be"),
        ("static_noise", "[fog]\nB_deg_h = inf\n", "fog.B_deg_h must be a finite number"),
        ("fog_vibration", "[fog.loop]\nlength = -1\n", "fog.loop.length must be (0, 100000] m; got -1"),
        ("fog_vibration", "[fog.mount.x]\nquality = 0\n", "fog.mount.x.quality must be (0, 1e+06] 1; got 0"),
        ("mems_scale_factor", "[gyro.nominal]\noutput_bits = 65\n", "output_bits must be an integer in [2, 64]"),
        ("mems_scale_factor", "rates_dps = [1, 2, 1e308]\n", "rates_dps[2] must be [-36000, 36000] deg/s; got 1e+308"),
    ],
)
def test_cli_refuses_an_out_of_range_field_in_one_line_exit_2(name, toml, words, tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(toml)
    t0 = time.monotonic()
    code = main(["simulate", name, "--config", str(cfg), "--out", str(tmp_path / "o")])
    assert time.monotonic() - t0 < 10
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], (code, err)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("name", _scenarios())
def test_the_defaults_lie_inside_their_documented_ranges(name):
    """Guards the ranges themselves: a range that refused the paper's own setup would be wrong."""
    module = registry.get(name)
    config = module.Config()
    for path, owner, _hint in numeric_fields(config):
        value = config
        for key in path:
            value = getattr(value, key)
        rng = field_range(owner, path[-1])
        for v in value if isinstance(value, tuple) else (value,):
            assert v is None or rng.contains(v), (path, v, rng)
