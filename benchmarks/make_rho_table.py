"""Write analysis/allan/_rho_table.py: the stored octave correlation table of the Allan noise fit.

The fit's point covariance needs, for each pair of octave taus and each pair of noise types,
the correlation rho of their Allan-variance estimates (``gyrobench.analysis.allan._covariance._rho_blocks``),
an integral over a 16384-point frequency grid. For power-of-two m every pair maps onto
m = 1 .. 1024 (pairs above the cap are scaled down keeping their ratio), so the Gram matrix
of the 4 noise types x 11 octaves (44 x 44) holds every octave correlation. This script
evaluates it by the direct computation (``_covariance._octave_gram_direct``) and stores it
as it is, exactly, as the base64 text of its little-endian float64 bytes (one string literal:
a tuple of 990 float literals took ~4 ms to compile on every import where no bytecode is
cached, e.g. under PYTHONDONTWRITEBYTECODE; the string decodes in microseconds).
tests/analysis/test_allan_rho_table.py checks the stored table against the direct computation.

Run after changing ``_RHO_GRID``, ``_RHO_M_CAP``, ``_rate_psd_shape`` or ``_h``:
``python benchmarks/make_rho_table.py``.
"""

from __future__ import annotations

import base64
import os
import textwrap

import numpy as np

from gyrobench.analysis.allan import _covariance as cov

OUT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "analysis", "allan", "_rho_table.py")


def render() -> str:
    gram = cov._octave_gram_direct()
    text = base64.b64encode(np.ascontiguousarray(gram, dtype="<f8").tobytes()).decode("ascii")
    body = "\n".join(f'    "{line}"' for line in textwrap.wrap(text, 88))
    return (
        '"""Stored octave correlation table of the Allan noise fit (generated: do not edit).\n\n'
        "Written by benchmarks/make_rho_table.py from ``gyrobench.analysis.allan._covariance._octave_gram_direct``:\n"
        "the Gram matrix of the unit-norm vectors g = S_alpha |H_m|^2 on the midpoint grid of\n"
        "(0, 1/2] cycles/sample, rows and columns ordered alpha-major (ALPHAS) then m (MS), row by\n"
        "row, as base64 of little-endian float64 (numpy.frombuffer(base64.b64decode(GRAM), '<f8')\n"
        ".reshape(44, 44)). tests/analysis/test_allan_rho_table.py checks it against the computation.\n"
        '"""\n\n'
        f"GRID = {cov._RHO_GRID}\n"
        f"M_CAP = {cov._RHO_M_CAP}\n"
        f"ALPHAS = {cov._TABLE_ALPHAS!r}\n"
        f"MS = {cov._TABLE_MS!r}\n"
        f"GRAM = (\n{body}\n)\n"
    )


def main() -> int:
    with open(OUT + ".part", "w") as f:
        f.write(render())
    os.replace(OUT + ".part", OUT)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
