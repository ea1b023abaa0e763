"""``gyrobench simulate noise`` writes only what ``gyrobench allan`` accepts (issue 32).

Every accepted ``simulate noise`` (exit 0) writes a file that ``allan`` reads and analyses (exit
0, or 5 for a record it finds non-stationary: a rate ramp is that by nature); every refusal is one
line, exit 2, and leaves no file. The grid covers the sample-rate range's edges and beyond, tiny,
ordinary and huge coefficients, and both file kinds; the slow tier draws them at random.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gyrobench.io.recording import FS_RANGE_HZ
from gyrobench.scenarios.cli.main import main

# every test runs among planted user files and fails if one changes (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("user_files")

#: samples per record: enough for an Allan fit's five octave taus, small enough to be quick
N_SAMPLES = 1000

COEFFICIENTS = {
    "ordinary": ["--N", "0.1", "--B", "0.5"],
    "tiny": ["--N", "1e-170"],
    "huge": ["--N", "1e300"],
    "ramp-only": ["--R", "10"],
    "none": [],
}


def _simulate_then_allan(tmp_path, capsys, fs: float, coefficients: list[str], ext: str) -> None:
    out = tmp_path / f"rec.{ext}"
    duration = N_SAMPLES / fs
    try:
        code = main(["simulate", "noise", *coefficients, "--fs", repr(fs), "--duration", f"{duration!r}s", "-o",
                     str(out), "-q"])
    except SystemExit as exc:  # refused by a flag's own parser
        code = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    if code != 0:
        assert code == 2 and len(err) == 1 and err[0].startswith("gyrobench: error:"), (code, err)
        assert not out.exists() and not list(tmp_path.glob(".*")), list(tmp_path.iterdir())
        return
    assert out.exists()
    code = main(["allan", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code in (0, 5), (fs, coefficients, ext, code, err)


@pytest.mark.parametrize("ext", ["csv", "h5"])
@pytest.mark.parametrize("coefficients", list(COEFFICIENTS), ids=list(COEFFICIENTS))
@pytest.mark.parametrize("fs", [FS_RANGE_HZ[0] / 10, FS_RANGE_HZ[0], 100.0, FS_RANGE_HZ[1], FS_RANGE_HZ[1] * 10])
def test_every_accepted_simulate_noise_writes_a_file_allan_reads(tmp_path, capsys, fs, coefficients, ext):
    _simulate_then_allan(tmp_path, capsys, fs, COEFFICIENTS[coefficients], ext)


@pytest.mark.parametrize("fs", ["1e-12", "1e20"])
def test_simulate_noise_refuses_a_rate_allan_refuses_in_one_line(tmp_path, capsys, fs):
    code = main(["simulate", "noise", "--N", "0.1", "--fs", fs, "--duration", "10s", "-o", str(tmp_path / "r.h5")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--fs must be in [1e-09, 1e+15] Hz" in err[0], err


@pytest.mark.slow
@settings(max_examples=40, deadline=None, derandomize=False,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(
    log_fs=st.floats(-13.0, 17.0),
    log_coefficient=st.floats(-200.0, 305.0),
    term=st.sampled_from(["--Q", "--N", "--B", "--K", "--R"]),
    ext=st.sampled_from(["csv", "h5"]),
)
def test_random_simulate_noise_writes_only_what_allan_accepts(tmp_path_factory, capsys, log_fs, log_coefficient,
                                                              term, ext):
    """Random seeds (``derandomize=False``): any rate, any size of any one term."""
    tmp_path = tmp_path_factory.mktemp("sim")
    _simulate_then_allan(tmp_path, capsys, 10.0**log_fs, [term, repr(10.0**log_coefficient)], ext)
