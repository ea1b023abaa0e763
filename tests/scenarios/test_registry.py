"""Registry and TOML configuration overrides: validated field by field, unknown keys rejected."""

import dataclasses
from dataclasses import dataclass, field

import pytest

from gyrobench.scenarios import registry


@dataclass(frozen=True, slots=True, kw_only=True)
class _Inner:
    a: float = 1.0
    label: str = "x"


@dataclass(frozen=True, slots=True, kw_only=True)
class _Config:
    fs_hz: float = 100.0
    runs: int = 3
    rates: tuple[float, ...] = (1.0, 2.0)
    band: tuple[float, float] = (0.1, 10.0)
    inner: _Inner = field(default_factory=_Inner)
    maybe: float | None = None

    def __post_init__(self):
        if self.fs_hz <= 0:
            raise ValueError(f"fs_hz must be > 0 Hz; got {self.fs_hz!r}")


class _Module:
    NAME = "toy"
    Config = _Config


def _toml(tmp_path, text):
    p = tmp_path / "c.toml"
    p.write_text(text)
    return p


def test_defaults_without_file():
    assert registry.load_config(_Module, None) == _Config()


def test_override_fields_and_nested(tmp_path):
    toml = 'fs_hz = 200\nruns = 5\nrates = [3, 4.5]\n[inner]\nlabel = "y"\n'
    cfg = registry.load_config(_Module, _toml(tmp_path, toml))
    assert cfg.fs_hz == 200.0 and isinstance(cfg.fs_hz, float)
    assert cfg.runs == 5 and cfg.rates == (3.0, 4.5) and cfg.inner == _Inner(a=1.0, label="y")


def test_table_named_after_scenario(tmp_path):
    cfg = registry.load_config(_Module, _toml(tmp_path, "[toy]\nruns = 7\n"))
    assert cfg.runs == 7


@pytest.mark.parametrize(
    ("text", "exc", "match"),
    [
        ("bogus = 1\n", ValueError, r"_Config has no parameter\(s\) \['bogus'\]; valid: \['fs_hz'"),
        ("[inner]\nb = 2\n", ValueError, r"_Config.inner has no parameter\(s\) \['b'\]"),
        ('fs_hz = "fast"\n', TypeError, "_Config.fs_hz must be a number; got 'fast'"),
        ("runs = 2.5\n", TypeError, "_Config.runs must be an integer; got 2.5"),
        ("band = [1.0]\n", ValueError, r"_Config.band must have 2 elements"),
        ("rates = 3\n", TypeError, "_Config.rates must be a list"),
        ("fs_hz = -1\n", ValueError, r"fs_hz must be > 0 Hz; got -1.0"),
        ("fs_hz = \n", ValueError, "is not valid TOML"),
    ],
)
def test_bad_config_files(tmp_path, text, exc, match):
    with pytest.raises(exc, match=match):
        registry.load_config(_Module, _toml(tmp_path, text))


def test_missing_config_file():
    with pytest.raises(FileNotFoundError, match="config file not found"):
        registry.load_config(_Module, "/nonexistent.toml")


def test_unknown_scenario():
    with pytest.raises(ValueError, match=r"scenario must be one of \[.*'static_noise'.*\]; got 'nope'"):
        registry.get("nope")


def test_every_available_scenario_honours_the_contract():
    for name in registry.available():
        mod = registry.get(name)
        assert mod.NAME == name
        assert isinstance(mod.TITLE, str) and mod.TITLE
        cfg = mod.Config()
        paper = getattr(mod, "PAPER", None)
        assert registry.describe(name).paper == paper
        assert registry.describe(name).title == mod.TITLE
        if paper is not None:  # a paper scenario: experiment, claims, deviations, report
            for attr in ("simulate", "experiment", "report"):
                assert callable(getattr(mod, attr)), f"{name}.{attr}"
            assert not hasattr(mod, "run"), f"{name} still has the old run()"
            assert mod.CLAIMS and all(c.paper == paper for c in mod.CLAIMS)
            assert all(d.paper == paper for d in mod.DEVIATIONS)
        else:
            assert callable(mod.run), f"{name}.run"
        # configs are frozen: a custom profile can never mutate the defaults
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(cfg, next(iter(cfg.__dataclass_fields__)), None)


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), 10**400, -(10**30)])
def test_non_finite_and_huge_config_numbers_are_refused_in_one_line(value):
    """A config number is checked before the config's own code sees it: NaN, inf and integers
    beyond TOML's 64-bit range are refused naming the field (they hung or overflowed before)."""
    from gyrobench.scenarios import registry

    mod = registry.get("static_noise")
    field = next(f for f in dataclasses.fields(mod.Config().fog) if f.type in (float, "float"))
    with pytest.raises(ValueError, match=rf"FogGrade\\.{field.name}|\.{field.name} must be"):
        registry.override(mod.Config(), {"fog": {field.name: value}})
