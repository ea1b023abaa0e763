"""Meta-test over EVERY numeric command-line flag (issue 32).

The parser is walked for every flag whose value is converted to a number; each is fed NaN,
+-inf, -1, 0, 1e308 and a huge integer (10**400) on a cheap command of its verb. The verb either
refuses it in one line naming the flag (exit 2, under a few seconds: a huge integer is refused
fast, never hangs) or accepts it, and then the value is one the flag documents as valid
(:data:`ACCEPTED`, each entry quoting the flag's help). Never exit 4, never a traceback.
"""

from __future__ import annotations

import argparse
import math
import time

import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.cli.main import build_parser, main

BAD_VALUES = ("nan", "inf", "-inf", "-1", "0", "1e308", str(10**400))

#: values a flag documents as valid among BAD_VALUES (its help text, quoted)
ACCEPTED: dict[tuple[str, str], set[str]] = {
    # "noise coefficients" default 0: a term left out
    **{("simulate", f): {"0"} for f in ("--Q", "--N", "--B", "--K", "--R")},
    ("simulate", "--seed"): {"0"},  # "seed of the noise" (>= 0)
    ("simulate", "--chunk"): {str(10**400)},  # samples per chunk: any count > 0, used up to the record's length
    ("allan", "--start"): {"0"},  # "from this time [s] of the record" (>= 0)
    ("reproduce", "--seed"): {"0"},  # "seed of the first unit (default 0)"
    ("reproduce", "--workers"): {"0"},  # "0 = in this process"
    ("bench", "--workers"): {"0"},  # "0 = one seed at a time"
    ("twin", "--seed"): {"0"},  # "seed of the twin's noise (default 0)" (the twin verb, where it exists)
}


def _flag_type(verb: str, flag: str):
    """The argparse type converter of ``flag`` of ``verb``."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return next(a.type for a in sub.choices[verb]._actions if flag in a.option_strings)


def _parse_only(verb: str, flag: str, value: str) -> tuple[int, list[str]]:
    """A verb without a cheap command here: its flag's converter alone, as argparse would report it."""
    try:
        _flag_type(verb, flag)(value)
    except argparse.ArgumentTypeError as exc:
        return 2, [f"gyrobench: error: argument {flag}: {exc}"]
    except (ValueError, TypeError):  # a plain int/float type: argparse names the flag itself
        return 2, [f"gyrobench: error: argument {flag}: invalid value: {value[:40]!r}"]
    return 0, []


def numeric_flags() -> list[tuple[str, str]]:
    """(verb, flag) of every option whose value argparse converts with a type other than str."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = []
    for verb, sp in sub.choices.items():
        for action in sp._actions:
            if action.option_strings and action.type not in (None, str) and action.nargs != 0:
                out.append((verb, max(action.option_strings, key=len)))
    return out


@pytest.fixture
def cheap_commands(tmp_path, monkeypatch):
    """A command per verb that finishes in about a second when the flag is accepted."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setitem(registry.SCENARIOS, "toy_paper", "tests.scenarios.toy_paper")
    csv = tmp_path / "r.csv"
    csv.write_text("time [s],rate [rad/s]\n" + "".join(f"{i / 10!r},{math.sin(i * 1.3):.6f}\n" for i in range(3000)))
    (tmp_path / "taken").write_text("a file: --out refuses it after every other check")
    return {
        "simulate": ["simulate", "noise", "--N", "0.1", "--B", "0.5", "--fs", "10", "--duration", "100s", "-o", "o.h5"],
        "allan": ["allan", str(csv)],
        "twin": ["twin", str(csv), "-o", "t.h5"],
        "reproduce": ["reproduce", "toy_paper", "--units", "2", "--out", "taken", "-q"],
        "bench": ["bench", "tests.scenarios.toy_scenario", "--compensator", "tests.scenarios.toy_scenario:good",
                  "--seeds", "0:2", "--no-references", "--allow-underpowered", "--db", "c.db", "-q"],
    }


def test_the_walk_finds_the_numeric_flags():
    flags = numeric_flags()
    assert ("reproduce", "--units") in flags and ("allan", "--fs") in flags and ("bench", "--alpha") in flags
    assert len(flags) >= 20


@pytest.mark.parametrize("verb, flag", numeric_flags())
def test_every_numeric_flag_refuses_absurd_values_in_one_line_or_documents_them(verb, flag, cheap_commands, capsys):
    wrong = []
    for value in BAD_VALUES:
        t0 = time.monotonic()
        if verb in cheap_commands:
            argv = [*cheap_commands[verb], f"{flag}={value}"]  # '=': argparse takes "-inf" for a value
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse's own refusal: one line, exit 2
                code = exc.code
            err = capsys.readouterr().err.strip().splitlines()
        else:  # a verb this test has no cheap command for (add one): at least its parsing is checked
            code, err = _parse_only(verb, flag, value)
        took = time.monotonic() - t0
        named = code == 2 and len(err) == 1 and flag in err[0]
        accepted = value in ACCEPTED.get((verb, flag), set())
        if code not in (0, 1, 2, 3, 5) or any("Traceback" in line for line in err) or took > 20:
            wrong.append(f"{value[:12]}: exit {code} in {took:.1f} s: {err[-3:]}")
        elif not accepted and not named:
            wrong.append(f"{value[:12]}: not refused naming {flag} (exit {code}): {err[:2]}")
        elif accepted and named:
            wrong.append(f"{value[:12]}: documented as valid but refused: {err}")
    assert not wrong, f"{verb} {flag}:\n" + "\n".join(wrong)


#: values at the bottom of the float range: accepted by a "> 0" flag, they must still end in success or
#: one line (the random fuzzer of the slow tier found ``allan --bandwidth=5e-324`` computing inf * 0)
TINY_VALUES = ("5e-324", "1e-180", "-0.0")


@pytest.mark.parametrize("verb, flag", numeric_flags())
def test_every_numeric_flag_takes_the_smallest_floats_without_an_internal_failure(verb, flag, cheap_commands,
                                                                                   capsys):
    if verb not in cheap_commands:
        pytest.skip(f"no cheap command for {verb}: its parsing is checked above")
    wrong = []
    for value in TINY_VALUES:
        try:
            code = main([*cheap_commands[verb], f"{flag}={value}"])
        except SystemExit as exc:
            code = exc.code
        err = capsys.readouterr().err.strip().splitlines()
        if code not in (0, 1, 3, 5, 2) or any("Traceback" in line for line in err):
            wrong.append(f"{value}: exit {code}: {err[-3:]}")
        elif code == 2 and not (len(err) == 1 and err[0].startswith("gyrobench: error:")):
            wrong.append(f"{value}: exit 2 in more than one line: {err[:3]}")
    assert not wrong, f"{verb} {flag}:\n" + "\n".join(wrong)
