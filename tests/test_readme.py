"""The README's two first commands are what CI runs, verbatim, and every CLI verb is documented."""

import re
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
    from gyrobench.scenarios.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    text = (ROOT / "README.md").read_text()
    for verb in sub.choices:
        assert f"gyrobench {verb}" in text, f"README does not mention 'gyrobench {verb}'"


def _python_blocks():
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```python\n(.+?)\n```", text, flags=re.S)


@pytest.mark.slow
def test_readme_python_examples_run(tmp_path, monkeypatch):
    """Every Python block of the README runs as written (the bench example as a script)."""
    blocks = _python_blocks()
    assert len(blocks) >= 2
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {"__name__": "__main__"})
    assert (tmp_path / "mine.sqlite").exists()  # the bench example ran its campaign
