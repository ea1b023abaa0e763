"""Write the 1 Hz ADIS16405 excerpt in this folder from the full records in ../shared/validation.

Run from the repository root: ``python tests/data/adis16405_1hz/make_excerpt.py``. For each of
the six 100 Hz static records it keeps the three gyro columns and averages blocks of 100
samples (one mean per second; t = k + 0.5 s). Every 100 Hz value is a multiple of the
0.05 deg/s LSB, so a block mean is a multiple of 0.0005 deg/s and is printed exactly with
four decimals: the excerpt is the exact block-mean decimation of the source.
"""

from __future__ import annotations

import gzip
import io
from pathlib import Path

import numpy as np

SOURCE = Path(__file__).resolve().parents[4] / "shared" / "validation" / "smac_imudata_adis16405"
HERE = Path(__file__).resolve().parent
BLOCK = 100  # samples per mean: 100 Hz -> 1 Hz
LSB_DPS = 0.05


def main() -> None:
    for k in range(1, 7):
        with gzip.open(SOURCE / f"adis16405_imu{k}_100Hz.csv.gz", "rt") as fh:
            lines = (ln for ln in fh if ln[:1] not in ("#", "g"))
            gyro = np.loadtxt(lines, delimiter=",", usecols=(0, 1, 2))
        counts = np.rint(gyro / LSB_DPS).astype(np.int64)
        if not np.allclose(counts * LSB_DPS, gyro, rtol=0, atol=1e-9):
            raise ValueError(f"record {k}: gyro values are not multiples of {LSB_DPS} deg/s")
        sums = counts.reshape(-1, BLOCK, 3).sum(axis=1)
        buf = io.StringIO()
        buf.write(
            f"# ADIS16405 static record {k} of 6 (SMAC-Group/imudata @eec6e5b, CC BY-NC-SA 4.0), gyro only, "
            f"means of {BLOCK} samples of the 100 Hz output: 1 Hz, sample j covers t = j .. j+1 s; deg/s\n"
        )
        buf.write("gyro_x_dps,gyro_y_dps,gyro_z_dps\n")
        for row in sums:
            buf.write(",".join(f"{v * LSB_DPS / BLOCK:.4f}" for v in row) + "\n")
        (HERE / f"adis16405_imu{k}_1Hz.csv.gz").write_bytes(gzip.compress(buf.getvalue().encode(), 9, mtime=0))


if __name__ == "__main__":
    main()
