"""Coverage on real records: do the 95 % intervals of a record's two halves overlap (issue 30, item 2)?

Over the public ADIS16405 records (``../shared/validation/smac_imudata_adis16405``: six static
records of 1e6 samples at 100 Hz, gyro and accelerometer axes, 36 channels) and their 1 Hz
excerpts in tests/data (six records, gyro axes, 18 channels), each channel is split into two
halves and each half fitted as ``gyrobench allan`` does (five terms, ``tau_min="auto"``), once
with :func:`fit_noise` alone and once with :func:`floor_bounds` applied to each half (the CLI
raises an open term's bound to what a half, quarter or eighth of the analysed record identifies).
A pair is a term identified in at least one half; the other half enters with its 95 % interval
or, when it leaves the term open, [0, its one-sided 95 % bound]. A pair is covered when the two
intervals overlap. Target (issue 30): >= 95 % of pairs. Consistent 95 % intervals overlap far
more often than 95 % of the time, so the figure is a floor on honesty, not a calibration.

Measured 2026-11-27 (floor_bounds with halves, quarters and eighths; docs/physics.md 1.8):
1 Hz excerpts 39 of 39 pairs (100 %) with and without the floor; 100 Hz records 78 of 79
(98.7 %) with and without it. The one miss: imu3 accelerometer z, K identified on the first half
[3.9e-5, 6.6e-5] g/sqrt(s), bound 2.8e-5 on the second (whose sub-segments identify no K).

Run: ``python benchmarks/coverage_halves.py [--validation DIR]`` (~1-2 min).
"""

from __future__ import annotations

import argparse
import datetime
import gzip
import os
from pathlib import Path

import numpy as np

from gyrobench.analysis.allan import halves_agreement

ROOT = Path(__file__).resolve().parents[1]
EXCERPTS = ROOT / "tests" / "data" / "adis16405_1hz"


def _read(path: Path) -> np.ndarray:
    """Every numeric column of an ADIS16405 CSV (gz) as printed (header and comment lines skipped)."""
    with gzip.open(path, "rt") as fh:
        return np.loadtxt((ln for ln in fh if ln[:1] not in ("#", "g")), delimiter=",", ndmin=2)


def _pairs(records: list[np.ndarray], fs: float, floor: bool) -> tuple[int, list[tuple]]:
    """Term pairs of the halves of every channel, and the ones whose intervals do not overlap."""
    pairs, apart = 0, []
    for k, data in enumerate(records, start=1):
        for col in range(data.shape[1]):
            found = halves_agreement(data[:, col], fs, floor=floor, tau_min="auto")
            pairs += len(found)
            apart += [(k, col, p.term, p.first, p.second) for p in found if not p.overlap]
    return pairs, apart


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.environ.get("GYROBENCH_VALIDATION") or str(ROOT.parent / "shared" / "validation")
    p.add_argument("--validation", default=default, help="the shared reference-data folder")
    a = p.parse_args(argv)
    sets = [("1 Hz excerpts (tests/data), 6 records x 3 gyro axes",
             [_read(EXCERPTS / f"adis16405_imu{k}_1Hz.csv.gz") for k in range(1, 7)], 1.0)]
    full = Path(a.validation) / "smac_imudata_adis16405"
    if full.is_dir():
        sets.append(("100 Hz records, 6 records x 6 axes (gyro + accelerometer)",
                     [_read(full / f"adis16405_imu{k}_100Hz.csv.gz") for k in range(1, 7)], 100.0))
    else:
        print(f"({full} not found: the 100 Hz records are skipped)")
    print(f"{datetime.date.today()}: 95 % intervals of the two halves of each channel, pairs that overlap")
    for label, records, fs in sets:
        for floor in (False, True):
            pairs, apart = _pairs(records, fs, floor)
            how = "fit_noise + floor_bounds (the CLI)" if floor else "fit_noise alone"
            print(f"  {label}, {how}: {pairs - len(apart)} of {pairs} ({100.0 * (pairs - len(apart)) / pairs:.1f} %)")
            for miss in apart:
                print(f"    apart: imu{miss[0]} column {miss[1]} {miss[2]}: {miss[3]} vs {miss[4]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
