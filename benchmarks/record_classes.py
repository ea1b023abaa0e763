"""Coverage of the shared analysis on the phone and HVAC record classes over seeds.

For S seeds each: the phone class (tests/analysis/record_classes.py: 6 h at 10 Hz, filtfilt-decimated,
0.5 % of 0.8 s windows bumped; truth N 3 deg/sqrt(h), B 25 deg/h) through
:func:`gyrobench.analysis.record.analyse_record`: how often N and B are identified and their 95 %
intervals hold the truth, their medians, how often the low-pass term is found; and the HVAC class
(1 h at 100 Hz, a 20 deg/h sine of period 1200 s): how often the sinusoid is chosen.

    PYTHONPATH=. python benchmarks/record_classes.py [SEEDS]
"""

from __future__ import annotations

import math
import sys

import numpy as np

from gyrobench.analysis.record import analyse_record
from tests.analysis.record_classes import hvac_record, phone_record

DPH = math.radians(1.0) / 3600.0
DSH = math.radians(1.0) / 60.0


def main(seeds: int = 20) -> None:
    rows, sines = [], 0
    for s in range(seeds):
        y, fs, _ = phone_record(np.random.default_rng([7, s]))
        ra = analyse_record(y, fs)
        n, b = ra.fit.coefficients["N"], ra.fit.coefficients["B"]
        rows.append((n.identifiable, (n.value or math.nan) / DSH, n.ci95[0] / DSH, n.ci95[1] / DSH,
                     b.identifiable, (b.value or math.nan) / DPH, b.ci95[0] / DPH, b.ci95[1] / DPH,
                     ra.model is not None and ra.model.term("lowpass") is not None))
        yh, fsh, _ = hvac_record(np.random.default_rng([8, s]))
        rh = analyse_record(yh, fsh)
        sines += rh.model is not None and rh.model.term("sinusoid") is not None
    r = np.array(rows, dtype=float)
    print(f"phone: N identified {int(r[:, 0].sum())}/{seeds}, 95 % interval holds 3 deg/sqrt(h) "
          f"{int(np.sum((r[:, 2] <= 3) & (3 <= r[:, 3])))}/{seeds}, median {np.nanmedian(r[:, 1]):.3g}; "
          f"B identified {int(r[:, 4].sum())}/{seeds}, holds 25 deg/h {int(np.sum((r[:, 6] <= 25) & (25 <= r[:, 7])))}"
          f"/{seeds}, median {np.nanmedian(r[:, 5]):.3g}; low-pass found {int(r[:, 8].sum())}/{seeds}")
    print(f"hvac: sinusoid chosen {sines}/{seeds}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
