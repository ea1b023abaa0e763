"""IMU records in the formats navigation tools read: EuRoC/ASL CSV and Kalibr's ``imu.yaml``.

EuRoC/ASL (the ``mav0/imu0/data.csv`` of the EuRoC MAV data set; Burri et al., Int. J. Robot.
Res. 35(10) 1157 (2016)): the header line :data:`EUROC_HEADER` (``#timestamp [ns]``, then
``w_RS_S_x..z [rad s^-1]`` and ``a_RS_S_x..z [m s^-2]``), then one row per sample: the integer
timestamp [ns] and the six values in SI.

Kalibr ``imu.yaml`` (ethz-asl/kalibr wiki, "IMU Noise Model"): ``gyroscope_noise_density``
[rad/s/sqrt(Hz)], ``gyroscope_random_walk`` [rad/s^2/sqrt(Hz)], ``accelerometer_noise_density``
[m/s^2/sqrt(Hz)], ``accelerometer_random_walk`` [m/s^3/sqrt(Hz)], ``update_rate`` [Hz] and
``rostopic``. The continuous-time densities equal the IEEE-952 N and K in SI (a white rate
noise of density N has an angle random walk N), so no conversion factor enters.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gyrobench.base.atomic import atomic_path, ensure_free_space

__all__ = ["EUROC_HEADER", "FORMAT_MARKER", "write_euroc", "kalibr_imu_yaml"]

EUROC_HEADER = (
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]"
)
#: the first line of a Kalibr file gyrobench writes (a YAML comment), by which it is recognised
FORMAT_MARKER = "# written by gyrobench"


def write_euroc(
    path: str | os.PathLike,
    gyro: NDArray[np.float64],
    accel: NDArray[np.float64],
    *,
    fs: float,
    t0: float = 0.0,
) -> Path:
    """Write an EuRoC/ASL ``data.csv``: timestamps [ns], body rates [rad/s], specific forces [m/s^2].

    Parameters
    ----------
    path : path-like
        The file (written atomically: complete or not at all).
    gyro, accel : ndarray, shape (n, 3)
        Rates about x, y, z [rad/s] and specific forces along x, y, z [m/s^2].
    fs : float
        Sample rate [Hz]; sample k is stamped t0 + k/fs, rounded to the nanosecond.
    t0 : float
        Time of the first sample [s], >= 0.

    Returns
    -------
    Path
        The path written.
    """
    g = np.asarray(gyro, dtype=float)
    a = np.asarray(accel, dtype=float)
    if g.ndim != 2 or g.shape[1] != 3 or a.shape != g.shape:
        raise ValueError(f"gyro and accel must both have shape (n, 3); got {g.shape} and {a.shape}")
    if not (math.isfinite(fs) and fs > 0) or not (math.isfinite(t0) and t0 >= 0):
        raise ValueError(f"fs must be > 0 Hz and t0 >= 0 s; got fs={fs!r}, t0={t0!r}")
    if not (np.all(np.isfinite(g)) and np.all(np.isfinite(a))):
        raise ValueError("gyro and accel must be finite: a EuRoC file has no missing values")
    stamps = np.round((t0 + np.arange(len(g)) / fs) * 1e9).astype(np.int64)
    ensure_free_space(path, 7 * 25 * len(g))
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="ascii", newline="\n") as fh:
            fh.write(EUROC_HEADER + "\n")
            for lo in range(0, len(g), 65536):
                block = np.column_stack([g[lo : lo + 65536], a[lo : lo + 65536]])
                rows = [
                    f"{s}," + ",".join(f"{v:.17g}" for v in row)
                    for s, row in zip(stamps[lo : lo + 65536], block, strict=True)
                ]
                fh.write("\n".join(rows) + "\n")
    return Path(path)


def kalibr_imu_yaml(
    *,
    gyro_noise_density: float,
    gyro_random_walk: float,
    accel_noise_density: float,
    accel_random_walk: float,
    update_rate: float,
    rostopic: str = "/imu0",
) -> str:
    """Kalibr's ``imu.yaml`` text, with the unit of every key in a comment.

    Parameters
    ----------
    gyro_noise_density : float
        N of the gyros [rad/s/sqrt(Hz)] (= [rad/sqrt(s)]).
    gyro_random_walk : float
        K of the gyros [rad/s^2/sqrt(Hz)].
    accel_noise_density : float
        VRW of the accelerometers [m/s^2/sqrt(Hz)].
    accel_random_walk : float
        Acceleration random walk [m/s^3/sqrt(Hz)].
    update_rate : float
        Sample rate [Hz].
    rostopic : str
        The IMU topic name.

    Returns
    -------
    str
        The YAML text, its first line :data:`FORMAT_MARKER`.
    """
    vals = {
        "gyroscope_noise_density": gyro_noise_density,
        "gyroscope_random_walk": gyro_random_walk,
        "accelerometer_noise_density": accel_noise_density,
        "accelerometer_random_walk": accel_random_walk,
        "update_rate": update_rate,
    }
    for k, v in vals.items():
        if not (math.isfinite(v) and v >= 0):
            raise ValueError(f"{k} must be a finite number >= 0; got {v!r}")
    if not rostopic or any(c in rostopic for c in "\n\r:#'\""):
        raise ValueError(f"rostopic must be a plain topic name; got {rostopic!r}")
    units = {
        "gyroscope_noise_density": "rad/s/sqrt(Hz)",
        "gyroscope_random_walk": "rad/s^2/sqrt(Hz)",
        "accelerometer_noise_density": "m/s^2/sqrt(Hz)",
        "accelerometer_random_walk": "m/s^3/sqrt(Hz)",
        "update_rate": "Hz",
    }
    lines = [FORMAT_MARKER, f"rostopic: {rostopic}"]
    lines += [f"{k}: {v:.9g}  # [{units[k]}]" for k, v in vals.items()]
    return "\n".join(lines) + "\n"
