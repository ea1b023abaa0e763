"""The README's bench examples (with docs/own-compensator.md's) can fail.

:data:`README_SECTION` is README.md's "Bench: regression-test your own compensator" section,
read from the file. The tests run
its own code blocks in a fresh project folder: the module ``mylab/models.py``, the two shell
commands, and the pytest example, with the README's "worse" compensator (``changed``), and
expect failure: exit 1 on the command line, a failing pytest run through the plugin.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from gyrobench.scenarios.bench.gate import plan_power
from gyrobench.scenarios.bench.power import min_attainable_p


def _readme_section() -> str:
    """README.md's "Bench: regression-test your own compensator" section, as shipped, followed by
    docs/own-compensator.md (the page it links for the Python and pytest forms of the same example)."""
    root = Path(__file__).resolve().parents[2]
    text = (root / "README.md").read_text(encoding="utf-8")
    start = text.index("## Bench: regression-test your own compensator")
    page = (root / "docs" / "own-compensator.md").read_text(encoding="utf-8")
    return text[start:text.index("\n## ", start + 3)] + "\n" + page


README_SECTION = _readme_section()


def _blocks(kind: str) -> list[str]:
    """The README section's fenced code blocks of language ``kind``, in order."""
    return re.findall(rf"```{kind}\n(.*?)```", README_SECTION, flags=re.S)


def _python_block(first_line: str) -> str:
    (block,) = [b for b in _blocks("python") if b.startswith(first_line)]
    return block


def test_the_readme_seed_counts_can_reach_alpha():
    """Without computing: every seed count in the section's examples can fire the gate on
    ifog_thermal's primary score (the refusal would say otherwise)."""
    counts = [int(m) for m in re.findall(r"--seeds 0:(\d+)", README_SECTION)]
    counts += [int(m) for m in re.findall(r"seeds=range\((\d+)\)", README_SECTION)]
    assert counts and len(counts) == 3
    for n in counts:
        plan = plan_power("ifog_thermal", tuple(range(n)), baseline=None, alpha=0.05, gate=True)
        assert plan.warning == "" and min_attainable_p(n, 1) < 0.05


def _project(tmp_path: Path) -> Path:
    proj = tmp_path / "project"
    (proj / "mylab").mkdir(parents=True)
    (proj / "mylab" / "__init__.py").write_text("")
    (proj / "mylab" / "models.py").write_text(_python_block("# mylab/models.py"))
    return proj


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)  # the project folder alone, as a user's
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    return env


@pytest.mark.slow
def test_readme_shell_example_exits_1_with_the_worse_compensator(tmp_path):
    proj = _project(tmp_path)
    commands = [shlex.split(line) for line in _blocks("console")[0].strip().splitlines()]
    assert [c[:2] for c in commands] == [["gyrobench", "bench"]] * 2 and "mylab.models:changed" in commands[1]
    codes, outs = [], []
    for cmd in commands:
        run = subprocess.run(cmd, cwd=proj, env=_env(), capture_output=True, text=True, timeout=900)
        codes.append(run.returncode)
        outs.append(run.stdout + run.stderr)
    assert codes == [0, 1], outs
    assert "REGRESSION: 1 of 1 primary score(s) significantly worse: mean/rms" in outs[1]
    assert "uncompensated" in outs[1] and "deg/h" in outs[1]


@pytest.mark.slow
def test_readme_pytest_example_fails_with_the_worse_compensator(tmp_path):
    proj = _project(tmp_path)
    (proj / "tests").mkdir()
    test_file = proj / "tests" / "test_mine.py"
    test_file.write_text(_python_block("# tests/test_mine.py"))
    commands = [shlex.split(line) for line in _blocks("console")[1].strip().splitlines()]
    save = subprocess.run(
        [sys.executable, *commands[0][1:]], cwd=proj, env=_env(), capture_output=True, text=True, timeout=900
    )
    assert save.returncode == 0, save.stdout + save.stderr
    assert (proj / "tests" / "baselines" / "ifog.json").is_file()
    same = subprocess.run(
        [sys.executable, *commands[1][1:]], cwd=proj, env=_env(), capture_output=True, text=True, timeout=900
    )
    assert same.returncode == 0, same.stdout + same.stderr  # unchanged against its own baseline
    # the README's "worse" compensator in the same test: the run must fail
    test_file.write_text(test_file.read_text().replace("mylab.models:mine", "mylab.models:changed"))
    worse = subprocess.run(
        [sys.executable, *commands[1][1:]], cwd=proj, env=_env(), capture_output=True, text=True, timeout=900
    )
    assert worse.returncode == 1, worse.stdout + worse.stderr
    assert "regressed against ifog.json" in worse.stdout and "mean/rms" in worse.stdout


def test_every_bench_flag_is_in_the_section_or_the_cli_reference():
    """Every ``bench`` option is named in the section, the rest of README.md or the CLI reference the
    README links for every option (docs/cli.md)."""
    from gyrobench.scenarios.cli.main import build_parser

    root = Path(__file__).resolve().parents[2]
    readme = (root / "README.md").read_text() + (root / "docs" / "cli.md").read_text()
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    flags = [f for a in sub.choices["bench"]._actions for f in a.option_strings if f.startswith("--")]
    missing = [f for f in flags if f != "--help" and f not in README_SECTION and f not in readme]
    assert not missing
