"""The README's bench examples can fail (issue 31 item 5).

:data:`README_SECTION` is the text proposed for README.md's "Bench: regression-test your own
compensator" section (README.md is merged by the lead; paste it there verbatim). The tests run
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

README_SECTION = """\
## Bench: regression-test your own compensator

A scenario with a compensation stage (`[bench]` in `gyrobench list`: `mems_scale_factor`,
`ifog_thermal`, `rlg_thermal`, `fog_vibration`) defines the features a real test would log,
one training run and the held-out runs, all with known truth. The bench fits your
compensator on the training run, compensates every held-out run and scores it against
the truth, for every seed. A compensator is any scikit-learn regressor or pipeline, an
estimator class, or a plain function `fit(X, y) -> predict`. On the IFOG thermal scenario
(features T, dT/dt and T x dT/dt from the logged coil temperature; target: output minus
true rate, in deg/h), a project folder holding a package `mylab` with this module:

```python
# mylab/models.py  (beside an empty mylab/__init__.py)
from sklearn.ensemble import GradientBoostingRegressor
from sklearn.linear_model import Ridge
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import PolynomialFeatures, StandardScaler

mine = make_pipeline(StandardScaler(), PolynomialFeatures(2), Ridge(alpha=1e-3))
changed = make_pipeline(StandardScaler(), GradientBoostingRegressor(n_estimators=20, max_depth=2))
```

From that folder, in Python (`run_mine.py`):

```python
# run_mine.py
from gyrobench.scenarios.bench import format_summary, run_campaign
from mylab.models import mine

if __name__ == "__main__":  # worker processes re-import this file
    campaign = run_campaign("ifog_thermal", mine, seeds=range(12), workers=2, db="mine.sqlite")
    print(format_summary(campaign))  # every score: unit, mean and 95 % interval over the seeds
```

or from the shell (`module:attr` is found from the current folder first, as `python -m`
would find it):

```console
gyrobench bench ifog_thermal --compensator mylab.models:mine --seeds 0:12 --save-baseline good.json
gyrobench bench ifog_thermal --compensator mylab.models:changed --baseline good.json
```

The second command exits 1: `changed` has a larger held-out RMS error than `mine` on
nearly every seed (0.10 against 0.08 deg/h over seeds 0-11; uncompensated: 0.26 deg/h).

- **Primary scores.** Each scenario gates a regression on one or two *primary* scores
  (ifog_thermal and fog_vibration: `mean/rms` [deg/h]; rlg_thermal:
  `mean/bias_stability_deg_h` [deg/h]; mems_scale_factor: `mean/nonlinearity_pct` [%] and
  `mean/rms_dps` [deg/s]). The other scores (each held-out run's, the other means) are
  tested and reported, never gated.
- **The test.** `--baseline` compares per-seed scores with a paired two-sided Wilcoxon
  signed-rank test (seed s of both campaigns sees the same simulated data), Holm-adjusted
  over the primary scores at `--alpha` (0.05); the output states the test and correction,
  prints each score with its unit beside the uncompensated output and the paper's method
  (where the bench knows it; `--no-references` skips both), and exits 1 on a significant
  regression of a primary score.
- **Enough seeds, checked before the run.** With n seeds and m primary scores the smallest
  p the gate can report is m x 2/2^n. A comparison (or a baseline written) whose seeds
  cannot reach `--alpha` is refused in one line naming the seeds needed (exit 2; 6 seeds
  for one primary score, 7 for two); `--allow-underpowered` runs it anyway with a WARNING
  on the first line. `--seeds auto` picks the count that detects a 20 % change of each
  primary score (`--min-change`) with power 0.8, from the baseline's seed-to-seed spread
  (without a baseline it assumes a change larger than that spread, and says so); the
  baseline file stores, under `"power"`, the change its seeds can detect.
- Seeds run on local processes (`--workers N`) or on a dask.distributed cluster
  (`--scheduler tcp://host:8786`, through `Client.get_executor()`); a seed gives the
  same scores, bit for bit, on any executor.
- The summary gives each score's mean over the seeds with a 95 % interval: Student t
  for scores of either sign, and for scores that cannot be negative (MSE, RMS, bias
  stability, nonlinearity) the modified-Cox lognormal interval, which stays above 0.
- Every finished seed is committed to SQLite (`--db`, default `gyrobench-bench.sqlite`)
  in its own transaction: a campaign killed at any moment resumes where it stopped and
  recomputes nothing. Changing the scenario's code or configuration, or the
  compensator's, starts a new campaign instead of mixing results.
- Exit status: 0 no significant regression; 1 a primary score significantly worse; 2 bad
  input, a compensator that raises, or too few seeds; 3 a comparison that cannot be made or
  a compensator that fails (non-finite output) on some seed; never 0 with "FAILED" printed.
- In your own test suite, installing gyrobench registers a pytest plugin whose fixture
  does the same (it loads nothing heavy until a test uses it, and never collides with your
  own package names). In the same project, `tests/test_mine.py`:

```python
# tests/test_mine.py
def test_my_compensator_does_not_regress(gyrobench_bench):
    gyrobench_bench.assert_no_regression(
        "ifog_thermal", "mylab.models:mine", baseline="baselines/ifog.json", seeds=range(12)
    )
```

  Write the baseline once from the compensator you trust, then run the tests as usual
  (`module:attr` is found from pytest's rootdir; the baseline path is relative to the test
  file, so this writes `tests/baselines/ifog.json`):

```console
python -m pytest --gyrobench-save-baselines tests/test_mine.py
python -m pytest tests/test_mine.py
```

  The test fails if the compensator regresses, and fails at once, naming the seeds needed,
  if its seeds could never show a regression (`allow_underpowered=True` turns that into a
  warning in pytest's report; `seeds="auto"` sizes the run from the baseline).
"""


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


def test_every_bench_flag_is_in_the_section_or_the_rest_of_the_readme():
    """tests/test_readme.py checks README.md for every flag once the section is merged; this
    checks now that the section (with the rest of README.md) names every ``bench`` option."""
    from gyrobench.scenarios.cli import build_parser

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    flags = [f for a in sub.choices["bench"]._actions for f in a.option_strings if f.startswith("--")]
    missing = [f for f in flags if f != "--help" and f not in README_SECTION and f not in readme]
    assert not missing
