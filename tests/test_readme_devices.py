"""The README's "Simulate your own gyro" examples (and docs/own-gyro.md's) run verbatim on a fresh clone: the
FOG, MEMS and RLG commands and the Python form write HDF5 and CSV whose truth error components sum
to ``output - true_rate``, and the twin example matches its real record."""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow  # five CLI processes and three device simulations: about 20 s


def _section() -> str:
    """The README's "Simulate your own gyro" section followed by docs/own-gyro.md, the page it links
    for the Python form, the twin and the IMU."""
    text = (ROOT / "README.md").read_text()
    start = text.index("## Simulate your own gyro")
    return text[start:text.index("\n## ", start + 1)] + "\n" + (ROOT / "docs" / "own-gyro.md").read_text()


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.+?)\n```", _section(), flags=re.S)


def _run_bash(block: str, cwd: Path) -> None:
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    done = subprocess.run(["bash", "-euo", "pipefail", "-c", block], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr


def _error_sum_matches(path: Path) -> None:
    """``output - truth/true_rate`` equals the sum of the rad/s truth components (the error terms;
    temperature and specific force are the environment, in K and m/s^2)."""
    if path.suffix == ".csv":
        with open(path) as fh:
            header = next(line for line in fh if not line.startswith("#")).strip().split(",")
        data = np.loadtxt(path, delimiter=",", comments="#", skiprows=1 + sum(
            1 for line in open(path) if line.startswith("#")))
        cols = {h: data[:, i] for i, h in enumerate(header)}
        out, true = cols["output [rad/s]"], cols["truth/true_rate [rad/s]"]
        errors = [v for h, v in cols.items() if h.startswith("truth/") and h.endswith("[rad/s]")
                  and h != "truth/true_rate [rad/s]"]
    else:
        from gyrobench.io.recording import load_hdf5

        rec = load_hdf5(path)
        out, true = rec["output"], rec["truth/true_rate"]
        errors = [rec[f"truth/{k}"] for k, ch in rec.truth.items() if ch.unit == "rad/s" and k != "true_rate"]
    assert len(errors) >= 3
    scale = float(np.max(np.abs(out)))
    # rounding only: the components are float64 sums of at most ~10 terms
    np.testing.assert_allclose(out - true, np.sum(errors, axis=0), rtol=0, atol=1e-12 * scale + 1e-15)


def test_readme_device_examples_run_verbatim(tmp_path):
    bash = _blocks("bash")
    assert len(bash) == 2, "the section holds the device commands and the twin command"
    _run_bash(bash[0], tmp_path)
    for name in ("fog.h5", "mems.csv", "rlg.h5"):
        _error_sum_matches(tmp_path / name)


def test_readme_python_example_runs_verbatim(tmp_path, monkeypatch):
    # the parts' example (the section's second Python block is the IMU's, run by tests/test_readme.py)
    (code,) = [b for b in _blocks("python") if 'for name, out in (("dsp-1760", "fog.h5")' in b]
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(code, "README.md", "exec"), scope)
    for name in ("fog.h5", "mems.csv", "rlg.h5"):
        _error_sum_matches(tmp_path / name)
    rec = scope["rec"]
    errors = sum(rec[f"truth/{k}"] for k, ch in rec.truth.items() if ch.unit == "rad/s" and k != "true_rate")
    np.testing.assert_allclose(scope["error"], errors, rtol=0, atol=1e-12 * float(np.max(np.abs(rec["output"]))))


def test_readme_twin_example_matches(tmp_path):
    (tmp_path / "tests").symlink_to(ROOT / "tests")  # the command names the shipped excerpt by its clone path
    _run_bash(_blocks("bash")[1], tmp_path)
    assert (tmp_path / "twin.h5").is_file() and (tmp_path / "twin.png").is_file()
