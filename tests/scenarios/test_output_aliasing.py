"""No output is an input, whatever the path's form: a Hypothesis strategy of aliasing paths (the same
name, absolute, ``./``, ``..``, a symbolic link to the file or to its folder, a chain of links, a hard
link) for every verb's outputs. Each command must exit 2 in one line and leave the input byte-identical.

The examples are drawn from a fixed seed; the example database in ``tests/hypothesis-db`` holds the
examples that broke a weaker rule (an output compared with the inputs by name only), replayed first
on every run. Hypothesis saves a failing example only when no seed is fixed: set
``GYROBENCH_HYPOTHESIS_RECORD=1`` to run unseeded and record what fails (then commit the folder).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st
from hypothesis.database import DirectoryBasedExampleDatabase

from tests.scenarios.test_cli import run

pytestmark = pytest.mark.usefixtures("user_files")

TOY = "tests.scenarios.toy_scenario"
DATABASE = DirectoryBasedExampleDatabase(str(Path(__file__).resolve().parents[1] / "hypothesis-db"))
#: a fixed seed, unless recording failing examples into the database (module docstring)
SEEDED = (lambda f: f) if os.environ.get("GYROBENCH_HYPOTHESIS_RECORD") else seed(20261201)

#: the ways a path can name a file: as given, absolute, with ``./`` or ``sub/..`` inside, a symbolic link
#: to the file, a link to its folder, a chain of two links, a hard link
FORMS = ("same", "absolute", "dot", "dotdot", "symlink", "folder_link", "link_chain", "hardlink")


@st.composite
def aliases(draw) -> tuple[str, int]:
    """A form of alias and how many ``./`` or ``sub/..`` segments it gets (where it takes any)."""
    return draw(st.sampled_from(FORMS)), draw(st.integers(min_value=1, max_value=3))


def alias_path(target: Path, form: str, depth: int, where: Path) -> str:
    """A path that names ``target`` in the way ``form`` says (links made in ``where``)."""
    if form == "same":
        return str(target)
    if form == "absolute":
        return os.path.abspath(target)
    if form == "dot":
        return str(target.parent / ("./" * depth + target.name))
    if form == "dotdot":
        sub = target.parent
        for k in range(depth):
            (sub / f"d{k}").mkdir(exist_ok=True)
            sub = sub / f"d{k}"
        return str(sub) + "/.." * depth + "/" + target.name
    if form == "symlink":
        link = where / f"link{target.suffix}"
        link.symlink_to(target)
        return str(link)
    if form == "folder_link":
        link = where / "folder-link"
        link.symlink_to(target.parent, target_is_directory=True)
        return str(link / target.name)
    if form == "link_chain":
        first, second = where / f"a{target.suffix}", where / f"b{target.suffix}"
        first.symlink_to(target)
        second.symlink_to(first)
        return str(second)
    link = where / f"hard{target.suffix}"
    os.link(target, link)
    return str(link)


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _csv(folder: Path) -> Path:
    """A record gyrobench wrote (its marker line first): only the rule that no output is an input keeps it."""
    p = folder / "real.csv"
    rows = "\n".join(f"{i / 100:.2f},{(i % 7) * 1e-3:.4f}" for i in range(400))
    p.write_text("# written by gyrobench recording 'real'\ntime [s],gyro_z [deg/s]\n" + rows)
    return p


def _json(folder: Path) -> Path:
    p = folder / "base.json"
    p.write_text('{"format": "gyrobench-baseline", "format_version": 1, "scenario": "toy"}\n')
    return p


def _toml(folder: Path) -> Path:
    p = folder / "cfg.toml"
    p.write_text("")
    return p


#: (verb, the input it reads, argv with {IN} and {OUT}); the output named {OUT} is the alias of {IN}
CASES = {
    "simulate device -o": (_csv, ["simulate", "device", "stim300", "--rate-csv", "{IN}", "-o", "{OUT}"]),
    "allan --kalibr": (_csv, ["allan", "{IN}", "--column", "gyro_z", "--kalibr", "{OUT}"]),
    "allan --plot": (_csv, ["allan", "{IN}", "--column", "gyro_z", "--plot", "{OUT}"]),
    "twin -o": (_csv, ["twin", "{IN}", "--column", "gyro_z", "-o", "{OUT}"]),
    "twin --plot": (_csv, ["twin", "{IN}", "--column", "gyro_z", "-o", "{DIR}/t.h5", "--plot", "{OUT}"]),
    "bench --save-baseline": (_json, ["bench", TOY, "--compensator", f"{TOY}:good", "--workers", "0", "-q",
                                      "--db", "{DIR}/b.db", "--baseline", "{IN}", "--save-baseline", "{OUT}"]),
    "bench --db": (_toml, ["bench", TOY, "--compensator", f"{TOY}:good", "--workers", "0", "-q",
                           "--config", "{IN}", "--db", "{OUT}"]),
    "reproduce --db": (_toml, ["reproduce", "static_noise", "--config", "{IN}", "--out", "{DIR}/rep", "--db", "{OUT}"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_an_output_that_aliases_an_input_is_refused_and_the_input_kept(case, tmp_path, capsys):
    make, argv = CASES[case]

    @SEEDED
    @settings(max_examples=12, deadline=None, derandomize=False, database=DATABASE,
              suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
    @given(alias=aliases())
    def check(alias):
        form, depth = alias
        work = Path(tempfile.mkdtemp(dir=tmp_path))
        (work / "data").mkdir()
        src = make(work / "data")
        before = _digest(src)
        out = alias_path(src, form, depth, work)
        code, _, err = run([a.replace("{IN}", str(src)).replace("{OUT}", out).replace("{DIR}", str(work))
                            for a in argv], capsys)
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1 and lines[0].startswith("gyrobench: error:"), (form, err)
        assert _digest(src) == before, (form, out)

    check()
