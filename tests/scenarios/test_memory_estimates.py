"""The paper scenarios' memory estimates bound the measured peak, and an absurd config is refused.

Each paper scenario states ``memory_estimate(config)``: the peak memory of ONE unit (its
``simulate`` or ``experiment`` in one worker process). Measured here as the peak RSS increase
of a forked child of one interpreter that has imported the scenarios and their libraries
(one BLAS thread, as the runner's workers): the child's ``ru_maxrss`` minus its RSS when it
starts. The estimate must bound the measured peak, and by at most :data:`FACTOR`, at the
default configuration (fast) and at larger ones that scale each field the formula names
(slow). Every memory_estimate docstring quotes the figures measured this way.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from gyrobench.scenarios import registry
from gyrobench.scenarios.cli.main import main

#: an estimate may exceed the measured peak by at most this factor (each formula states its
#: margin; this bounds how pessimistic it may be, so a feasible run is not refused)
FACTOR = 2.5

_MEASURE = textwrap.dedent(
    """
    import importlib, json, os, resource, sys
    import numpy, scipy.linalg, scipy.optimize, scipy.signal, scipy.interpolate
    import sklearn.neural_network
    from threadpoolctl import threadpool_limits
    from gyrobench.scenarios import registry

    def rss():
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024

    out = []
    for name, func, over in json.loads(sys.argv[1]):
        mod = registry.get(name)
        cfg = registry.override(mod.Config(), over) if over else mod.Config()
        est = mod.memory_estimate(cfg)
        sys.stdout.flush()
        r, w = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child's own RSS at its start: a fork does not copy every page
            base = rss()
            with threadpool_limits(limits=1):
                getattr(mod, func)(cfg, 0)
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
            os.write(w, str(peak - base).encode())
            os._exit(0)
        os.close(w)
        with os.fdopen(r) as fh:
            peak = int(fh.read())
        _, status = os.waitpid(pid, 0)
        assert status == 0, (name, func, over, status)
        out.append({"name": name, "func": func, "over": over, "estimate": est, "peak": peak})
    print(json.dumps(out))
    """
)


#: measuring interpreters run side by side (CI has 2 cores and runs the tests one at a time).
#: Each job's peak is its own forked child's ru_maxrss minus that child's starting RSS, which
#: another process's memory does not change, so the figures are those of a serial run.
PARALLEL = 2


def _measure(jobs: list[tuple[str, str, dict]]) -> list[dict]:
    shares = [jobs[i::PARALLEL] for i in range(PARALLEL)]  # jobs alternate: simulate, experiment
    procs = [
        subprocess.Popen([sys.executable, "-c", _MEASURE, json.dumps(share)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for share in shares if share
    ]
    rows: list[list[dict]] = []
    for proc in procs:
        out, err = proc.communicate(timeout=900)
        assert proc.returncode == 0, err[-3000:]
        rows.append(json.loads(out.strip().splitlines()[-1]))
    back = [row for i in range(len(jobs)) for row in [rows[i % PARALLEL][i // PARALLEL]]]
    assert [(r["name"], r["func"], r["over"]) for r in back] == [tuple(j) for j in jobs]
    return back


def _check_bounds(rows: list[dict]) -> None:
    bad = [
        f"{r['name']}.{r['func']} {r['over']}: estimate {r['estimate'] / 1e6:.0f} MB, "
        f"measured {r['peak'] / 1e6:.0f} MB"
        for r in rows
        if not (r["peak"] <= r["estimate"] <= FACTOR * r["peak"])
    ]
    assert not bad, bad


SCENARIOS = ("mems_scale_factor", "ifog_thermal", "rlg_thermal", "fog_vibration")

#: two larger configurations per scenario, each scaling a field its formula names
LARGER = {
    "mems_scale_factor": [{"average_s": 240}, {"fs_hz": 400, "n_fit_runs": 6}],
    "ifog_thermal": [{"fs_hz": 10}, {"validation1_runs": 20, "identification_hold_h": 8}],
    "rlg_thermal": [{"fs_hz": 25}, {"ramp_c_per_min": 0.1, "high_soak_min": 240}],
    "fog_vibration": [{"vibration_s": 900.0}, {"static_before_s": 2400.0, "static_after_s": 2400.0}],
}
#: a term of the formula the record length does not show
EXTRA = [
    ("mems_scale_factor", "experiment", {"dense_step_dps": 0.5}),  # the dense sweep, in bounded blocks
    ("ifog_thermal", "experiment", {"thermal_step_s": 2}),  # thermal steps, on the grid
    ("ifog_thermal", "experiment", {"thermal_step_s": 7}),  # off the grid: the dt / 2 check
]


@pytest.mark.slow  # runs every paper unit at its default config under a memory probe (tens of seconds): slow tier
def test_estimates_bound_the_measured_peak_at_the_default_config():
    _check_bounds(_measure([(s, f, {}) for s in SCENARIOS for f in ("simulate", "experiment")]))


@pytest.mark.slow
def test_estimates_bound_the_measured_peak_at_larger_configs():
    jobs = [(s, f, o) for s in SCENARIOS for o in LARGER[s] for f in ("simulate", "experiment")]
    rows = _measure(jobs + EXTRA)
    _check_bounds(rows)
    # the larger configs are larger: the check above is not of the default thrice
    for s in SCENARIOS:
        est = [r["estimate"] for r in rows if r["name"] == s and r["func"] == "simulate"]
        assert min(est) > 1.5 * _default_estimate(s), s


def _default_estimate(name: str) -> float:
    mod = registry.get(name)
    return float(mod.memory_estimate(mod.Config()))


@pytest.mark.parametrize("name", SCENARIOS)
def test_estimate_grows_with_the_fields_it_names(name):
    import dataclasses

    mod = registry.get(name)
    base = mod.memory_estimate(mod.Config())
    assert 10e6 < base < 1e9  # default configs: tens to hundreds of MB (measured above)
    for over in LARGER[name]:
        assert mod.memory_estimate(dataclasses.replace(mod.Config(), **over)) > 1.5 * base


#: 1e4-hour records (absurd; IFOG and RLG at 100 Hz): estimates of terabytes, refused on any machine
ABSURD = {
    "mems_scale_factor": "average_s = 3.6e7\n",
    "ifog_thermal": "identification_hold_h = 1000.0\nfs_hz = 1e4\n",  # the top of both documented ranges
    "rlg_thermal": "high_soak_min = 6e4\nfs_hz = 1e4\n",  # the top of both documented ranges
    "fog_vibration": "vibration_s = 3.6e7\n",
}


@pytest.mark.parametrize("verb", ["reproduce", "simulate"])
@pytest.mark.parametrize("name", SCENARIOS)
def test_absurd_config_is_refused_in_one_line_before_allocating(
    name, verb, tmp_path, capsys, monkeypatch
):
    import tracemalloc

    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("GYROBENCH_MEMORY_LIMIT", raising=False)  # the machine's own limit
    (tmp_path / "big.toml").write_text(ABSURD[name])
    argv = [verb, name, "--config", "big.toml", "--out", "o"]
    if verb == "reproduce":
        argv += ["-q"]
    main(argv)  # once untraced, so the verb's lazy imports are done: only the refusal's allocations count
    capsys.readouterr()
    tracemalloc.start()
    try:
        code = main(argv)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err.splitlines()
    assert code == 2, err
    assert len(err) == 1 and "Traceback" not in err[0], err
    assert err[0].startswith(
        f"gyrobench: error: scenario {name} with config file 'big.toml' needs about "
    ), err
    assert "TB of memory, more than the limit of" in err[0] or "PB of memory" in err[0], err
    assert peak < 20e6, peak  # refused before allocating
    assert not (tmp_path / "o").exists()


def test_units_at_once_multiply_the_per_unit_estimate(tmp_path, capsys, monkeypatch):
    from gyrobench.base import memory
    from gyrobench.scenarios.papers import p004_rlg_thermal as rlg_thermal
    from gyrobench.scenarios.runner import units

    est = rlg_thermal.memory_estimate(rlg_thermal.Config())  # ~250 MB
    monkeypatch.setenv(memory.LIMIT_ENV, str(int(1.5 * est)))
    assert units.concurrent_units(20, 0) == 1
    assert units.concurrent_units(20, 2) == 2
    assert units.concurrent_units(1, 8) == 1
    units.check_unit_memory(rlg_thermal, rlg_thermal.Config(), concurrent=1)  # one unit fits
    with pytest.raises(memory.MemoryLimitError, match=r"\(2 unit\(s\) at once, one per worker"):
        units.check_unit_memory(rlg_thermal, rlg_thermal.Config(), concurrent=2)
    # the runner's own pool: refused before any unit starts (nothing stored)
    db = tmp_path / "u.sqlite"
    with pytest.raises(memory.MemoryLimitError, match="lower --workers"):
        units.run_units(rlg_thermal, rlg_thermal.Config(), n_units=2, workers=2, db=db)
    # and through the CLI, one line naming the scenario and its configuration
    monkeypatch.chdir(tmp_path)
    code = main(["reproduce", "rlg_thermal", "--units", "2", "--workers", "2", "--out", "o", "-q"])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(
        "gyrobench: error: scenario rlg_thermal with its default configuration (2 unit(s) at once"
    ), err
    assert not (tmp_path / "o").exists()


def test_bench_workers_multiply_the_per_seed_estimate(tmp_path, monkeypatch):
    """A campaign on its own local pool refuses, before any seed starts, more seeds at once
    than fit: the same one check as reproduce (units.check_unit_memory)."""
    from gyrobench.base.memory import MemoryLimitError
    from gyrobench.scenarios import bench
    from gyrobench.scenarios.papers import p004_rlg_thermal as rlg_thermal

    est = rlg_thermal.memory_estimate(rlg_thermal.Config())
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", str(int(1.5 * est / 0.8)))
    with pytest.raises(MemoryLimitError, match=r"scenario rlg_thermal .* \(2 unit\(s\) at once"):
        bench.run_campaign(
            "rlg_thermal", "sklearn.linear_model:LinearRegression", range(2), workers=2,
            db=tmp_path / "b.sqlite", progress=False,
        )
