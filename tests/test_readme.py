"""The README's two first commands are what CI runs, verbatim, and every CLI verb is documented."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _readme_commands():
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```bash\n(.+?)\n```", text, flags=re.S)


def test_readme_starts_with_install_and_test_commands():
    cmds = _readme_commands()
    assert len(cmds) >= 2
    install, tests = cmds[0].strip(), cmds[1].strip()
    assert "pip install" in install and "gyrobench reproduce --all" in install
    assert "pytest" in tests
    ci = (ROOT / ".ci" / "run").read_text()
    assert install in ci, "CI must run README command 1 verbatim"
    assert tests in ci, "CI must run README command 2 verbatim"


def test_every_cli_verb_is_in_the_readme():
    from gyrobench.scenarios.cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    text = (ROOT / "README.md").read_text()
    for verb in sub.choices:
        assert f"gyrobench {verb}" in text, f"README does not mention 'gyrobench {verb}'"


def test_every_cli_flag_is_documented():
    """Each long option of the top level and of every verb appears in the README's command table
    or in the CLI reference it links (docs/cli.md)."""
    from gyrobench.scenarios.cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    text = (ROOT / "README.md").read_text() + (ROOT / "docs" / "cli.md").read_text()
    for name, p in [("gyrobench", parser), *sub.choices.items()]:
        for action in p._actions:
            if action.help == "==SUPPRESS==":  # hidden (internal) options
                continue
            for flag in action.option_strings:
                if flag.startswith("--") and flag != "--help":
                    assert flag in text, f"neither README.md nor docs/cli.md mentions {name}'s {flag}"


#: the user's guide pages whose examples are run as written: the README and the pages it sends a
#: new user to for the longer examples
EXAMPLE_PAGES = ("README.md", "docs/own-gyro.md", "docs/own-compensator.md")


def _blocks(lang: str) -> list[str]:
    text = "\n".join((ROOT / page).read_text() for page in EXAMPLE_PAGES)
    return re.findall(rf"```{lang}\n(.+?)\n```", text, flags=re.S)


def _file_blocks() -> dict[str, str]:
    """Python blocks whose first line is ``# path`` (a file of the README's example project)."""
    out = {}
    for code in _blocks("python"):
        m = re.match(r"# ([\w/.]+\.py)\b", code)
        if m:
            out[m.group(1)] = code
    return out


def test_readme_example_project_is_complete():
    files = _file_blocks()
    assert {"mylab/models.py", "run_mine.py", "tests/test_mine.py"} <= set(files)
    consoles = "\n".join(_blocks("console"))
    assert "mylab.models:mine" in consoles and "--gyrobench-save-baselines" in consoles


def _console_argv(line: str) -> list[str]:
    """A README console line as argv, with this environment's gyrobench and python."""
    argv = shlex.split(line)
    if argv[0] == "gyrobench":
        argv[0] = str(Path(sys.executable).with_name("gyrobench"))
    elif argv[0] == "python":
        argv[0] = sys.executable
    return argv


def _console_lines_run_by_the_bench_readme_tests() -> set[str]:
    """The console lines tests/scenarios/test_bench_readme.py runs from a project folder, with
    the exit codes and output they must give: the bench section's first two console blocks."""
    from tests.scenarios.test_bench_readme import _blocks as bench_blocks

    return {ln.strip() for block in bench_blocks("console")[:2] for ln in block.splitlines() if ln.strip()}


@pytest.mark.slow
def test_readme_example_project_runs_as_written(tmp_path):
    """The README's bench project: its files, its Python script and every console line, run
    from the project folder exactly as written (the shell bench finds mylab from the current
    folder; the pytest plugin finds it from the rootdir). The bench section's console lines
    are run, with their exit codes and messages checked, by tests/scenarios/test_bench_readme.py
    (same project files, same commands); running them here again cost ~110 s of the slow tier
    for a weaker check (exit 0 or 1), so this runs every other console line."""
    (tmp_path / "mylab").mkdir()
    (tmp_path / "mylab" / "__init__.py").write_text("")
    for path, code in _file_blocks().items():
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text(code + "\n")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTEST_ADDOPTS")}

    def run(argv):
        return subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=1200)

    r = run([sys.executable, "run_mine.py"])
    assert r.returncode == 0, r.stderr[-3000:]
    assert (tmp_path / "mine.sqlite").exists()
    assert "mean/rms" in r.stdout, r.stdout[-3000:]  # the summary of every score
    lines = [ln for block in _blocks("console") for ln in block.splitlines() if ln.strip()]
    elsewhere = _console_lines_run_by_the_bench_readme_tests()
    assert elsewhere and elsewhere <= {ln.strip() for ln in lines}  # they are README lines
    for line in lines:
        if line.strip() in elsewhere:
            continue
        r = run(_console_argv(line))
        # 'changed' against the baseline may regress (exit 1, as the README says); all else is 0
        allowed = (0, 1) if "--baseline" in line else (0,)
        assert r.returncode in allowed, f"{line!r} exited {r.returncode}: {r.stderr[-3000:]}"
        assert "Traceback" not in r.stderr, r.stderr[-3000:]


@pytest.mark.slow
def test_readme_python_examples_run(tmp_path, monkeypatch):
    """Every Python block of the README and docs/own-gyro.md that is not a file of the example project runs as
    written."""
    files = set(_file_blocks().values())
    blocks = [b for b in _blocks("python") if b not in files]
    assert blocks
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {"__name__": "__main__"})
