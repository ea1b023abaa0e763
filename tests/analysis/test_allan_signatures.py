"""The public Allan functions keep their signatures through the BLAS decorator: mypy sees them.

``allan_deviation`` and ``fit_noise`` are wrapped by ``_blas._single_blas``; a wrapper typed
``Callable -> Callable`` made mypy see ``(*Any, **Any) -> Any``, so no wrong call was caught.
Here mypy (``mypy.api.run``, as a user's type check would) checks small snippets against the
installed package: wrong calls must give an error naming the function and the argument, a
correct call none, and the return types must come through.
"""

from __future__ import annotations

import textwrap

import pytest

mypy_api = pytest.importorskip("mypy.api", reason="mypy is in the [test] extra")


@pytest.fixture(scope="module")
def check(tmp_path_factory):
    """Run mypy on a snippet against gyrobench; returns its report lines (``file:line: ...``).

    mypy finds the installed package as the tests import it: a regular install in
    site-packages, an editable one through its path entry (``src/``).
    """
    root = tmp_path_factory.mktemp("mypy")
    config = root / "mypy.ini"
    config.write_text(
        "[mypy]\n"
        "python_version = 3.10\n"
        "follow_imports = silent\n"
        f"cache_dir = {root / 'cache'}\n"
        "[mypy-allantools.*,scipy.*,sklearn.*,pywt.*,h5py.*,threadpoolctl.*]\n"
        "ignore_missing_imports = true\n"
    )

    def run(code: str) -> list[str]:
        snippet = root / "snippet.py"
        snippet.write_text(textwrap.dedent(code))
        out, err, status = mypy_api.run(["--config-file", str(config), "--no-error-summary", str(snippet)])
        assert status in (0, 1), f"mypy failed to run (status {status}): {err or out}"
        return [line for line in out.splitlines() if line.strip()]

    return run


@pytest.mark.slow  # seconds of the default tier (issue 23: under 3 minutes); CI runs it
def test_wrong_calls_are_type_errors(check):
    lines = check(
        """
        import numpy as np
        from gyrobench.analysis.allan import allan_deviation, fit_noise

        y = np.zeros(1000)
        curve = allan_deviation(y, 1.0, kind=2)
        fit_noise(curve, terms=3)
        fit_noise(curve, tau_min=0.1, unknown=1)
        allan_deviation(y)
        n: int = allan_deviation(y, 1.0)
        """
    )
    errors = [line for line in lines if ": error:" in line]
    want = [
        (6, 'Argument "kind" to "allan_deviation" has incompatible type "int"; expected "str"'),
        (7, 'Argument "terms" to "fit_noise" has incompatible type "int"; expected "Sequence[str]"'),
        (8, 'Unexpected keyword argument "unknown" for "fit_noise"'),
        (9, 'Missing positional argument "fs" in call to "allan_deviation"'),
        (10, 'Incompatible types in assignment (expression has type "AllanCurve", variable has type "int")'),
    ]
    for line_no, message in want:
        assert any(f":{line_no}: error: {message}" in e for e in errors), (message, lines)
    assert len(errors) == len(want), lines


def test_a_correct_call_type_checks_and_keeps_its_return_type(check):
    lines = check(
        """
        import numpy as np
        from gyrobench.analysis.allan import allan_deviation, fit_noise

        curve = allan_deviation(np.zeros(1000), 10.0, taus="octave", kind="overlapping")
        fit = fit_noise(curve, terms=("N", "B"), tau_min="auto", misfit_p=0.05)
        fit2 = fit_noise(np.zeros(1000), 10.0)
        reveal_type(curve)
        reveal_type(fit)
        reveal_type(fit2.coefficients["N"].ci95)
        """
    )
    assert not [line for line in lines if ": error:" in line], lines
    revealed = [  # (mypy before 1.11 spells builtins out)
        line.split("Revealed type is ", 1)[1].replace("builtins.", "") for line in lines if "Revealed type is" in line
    ]
    assert revealed == [
        '"gyrobench.analysis.allan._results.AllanCurve"',
        '"gyrobench.analysis.allan._results.NoiseFit"',
        '"tuple[float, float]"',
    ], lines
