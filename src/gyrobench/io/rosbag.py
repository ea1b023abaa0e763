"""IMU records as ROS bags: one ``sensor_msgs/msg/Imu`` message per sample, written with ``rosbags``.

``rosbags`` (Ternaris, Apache-2.0; a pure-Python reader and writer of ROS 1 and ROS 2 bags, no
ROS installation needed) is the optional extra ``ros`` (``pip install gyrobench[ros]``);
without it :func:`write_imu_bag` raises :class:`RosbagsMissing`, whose message says how to
install it.

Formats (:func:`bag_format`): a path ending ``.bag`` is a ROS 1 bag (format 2.0, the one
Kalibr, VINS-Mono and ROS 1 drivers read); any other path is a ROS 2 bag, a folder holding
``metadata.yaml`` (rosbag2 version 8) and one SQLite ``.db3`` file, with CDR messages.

Each message (the ``sensor_msgs/msg/Imu`` definition, ROS 1 Noetic and ROS 2 Humble alike):

* ``header.stamp``: the sample's time [s] as seconds and nanoseconds (the bag's receive time is
  the same instant); ``header.frame_id``: ``frame_id``;
* ``angular_velocity`` [rad/s] and ``linear_acceleration`` [m/s^2]: the body rates and specific
  forces, SI as the message requires;
* ``orientation_covariance[0] = -1``: no orientation is produced (the message's convention;
  the quaternion is then the identity and to be ignored);
* ``angular_velocity_covariance`` and ``linear_acceleration_covariance``: the per-sample
  variance on the diagonal when the spec gives one (a white noise of density N sampled at fs
  has variance N^2 fs per sample), all zeros when it does not (the message's "covariance
  unknown").
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobench.base.atomic import AtomicWriteError, ensure_free_space, temp_name

__all__ = ["IMU_MSGTYPE", "RosbagsMissing", "bag_format", "write_imu_bag", "rosbags_available"]

#: the message type every sample is written as
IMU_MSGTYPE = "sensor_msgs/msg/Imu"


class RosbagsMissing(ImportError):
    """The optional ``rosbags`` package is not installed (its message says how to install it)."""


def rosbags_available() -> bool:
    """Whether the optional ``rosbags`` package can be imported.

    Returns
    -------
    bool
        True when its ROS 1, ROS 2 and type-system modules import.
    """
    try:
        import rosbags.rosbag1  # noqa: F401
        import rosbags.rosbag2  # noqa: F401
        import rosbags.typesys  # noqa: F401
    except ImportError:
        return False
    return True


def bag_format(path: str | os.PathLike) -> Literal["ros1", "ros2"]:
    """The bag format a path names.

    Parameters
    ----------
    path : path-like
        The bag's path.

    Returns
    -------
    {"ros1", "ros2"}
        ``"ros1"`` for a path ending ``.bag`` (a ROS 1 bag file), else ``"ros2"`` (a ROS 2 bag folder).
    """
    return "ros1" if Path(path).suffix.lower() == ".bag" else "ros2"


def _covariance(variance: float | None, what: str) -> NDArray[np.float64]:
    c = np.zeros(9)
    if variance is not None:
        if not (math.isfinite(variance) and variance >= 0):
            raise ValueError(f"{what} must be a finite variance >= 0 or None (unknown); got {variance!r}")
        c[[0, 4, 8]] = variance
    return c


def write_imu_bag(
    path: str | os.PathLike,
    gyro: ArrayLike,
    accel: ArrayLike,
    *,
    stamps: ArrayLike,
    gyro_variance: float | None = None,
    accel_variance: float | None = None,
    topic: str = "/imu0",
    frame_id: str = "imu0",
) -> Path:
    """Write a ROS 1 or ROS 2 bag of ``sensor_msgs/msg/Imu`` messages (module docstring).

    Parameters
    ----------
    path : path-like
        ``NAME.bag`` (ROS 1) or a folder name (ROS 2). It must not exist; its parent folders
        are created; the bag is written beside it under a temporary name and renamed onto it
        complete (or not at all).
    gyro, accel : array_like, shape (n, 3)
        Body rates [rad/s] and specific forces [m/s^2] about and along x, y, z.
    stamps : array_like, shape (n,)
        Sample times [s], >= 0 and strictly increasing (rounded to the nanosecond).
    gyro_variance, accel_variance : float, optional
        Per-sample variance of each axis [(rad/s)^2], [(m/s^2)^2]; None: unknown (zeros).
    topic : str
        The topic (Kalibr's default ``/imu0``).
    frame_id : str
        ``header.frame_id``.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    RosbagsMissing
        ``rosbags`` is not installed.
    ValueError
        Shapes, non-finite values, stamps, variances or names out of their ranges, or an
        existing ``path``.
    """
    g = np.asarray(gyro, dtype=float)
    a = np.asarray(accel, dtype=float)
    t = np.asarray(stamps, dtype=float)
    if g.ndim != 2 or g.shape[1] != 3 or a.shape != g.shape or t.shape != (len(g),) or len(g) == 0:
        raise ValueError(f"gyro and accel must have shape (n, 3), n >= 1, and stamps (n,); got {g.shape}, {a.shape} "
                         f"and {t.shape}")
    if not (np.all(np.isfinite(g)) and np.all(np.isfinite(a)) and np.all(np.isfinite(t))):
        raise ValueError("gyro, accel and stamps must be finite: a bag message has no missing values")
    ns = np.round(t * 1e9).astype(np.int64)
    if ns[0] < 0 or np.any(np.diff(ns) <= 0):
        raise ValueError("stamps must be >= 0 s and strictly increasing (to the nanosecond)")
    if not topic.startswith("/") or any(c.isspace() for c in topic) or len(topic) < 2:
        raise ValueError(f"topic must be a ROS name starting with '/' and without spaces; got {topic!r}")
    if not frame_id or any(c.isspace() for c in frame_id):
        raise ValueError(f"frame_id must be a name without spaces; got {frame_id!r}")
    cov_g = _covariance(gyro_variance, "gyro_variance")
    cov_a = _covariance(accel_variance, "accel_variance")
    target = Path(path)
    if target.exists() or target.is_symlink():
        raise ValueError(f"{str(target)!r} exists: a bag is written only to a new path")
    kind = bag_format(target)
    try:
        from rosbags.typesys import Stores, get_typestore

        if kind == "ros1":
            from rosbags.rosbag1 import Writer as Ros1Writer
        else:
            from rosbags.rosbag2 import Writer as Ros2Writer
    except ImportError:
        raise RosbagsMissing("writing a ROS bag needs the optional package rosbags: pip install 'gyrobench[ros]' "
                             "(or pip install rosbags)") from None
    store = get_typestore(Stores.ROS1_NOETIC if kind == "ros1" else Stores.ROS2_HUMBLE)
    types: Any = store.types
    imu_t, header_t, time_t = types[IMU_MSGTYPE], types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    quat_t, vec_t = types["geometry_msgs/msg/Quaternion"], types["geometry_msgs/msg/Vector3"]
    serialize = store.serialize_ros1 if kind == "ros1" else store.serialize_cdr
    cov_o = np.zeros(9)
    cov_o[0] = -1.0
    identity = quat_t(x=0.0, y=0.0, z=0.0, w=1.0)
    ensure_free_space(target, 450 * len(g))  # one message takes 375-390 bytes with its index
    work = temp_name(target, "tmpdir")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        work.mkdir()
        inner = work / target.name
        writer = Ros1Writer(inner) if kind == "ros1" else Ros2Writer(inner, version=8)
        with writer:
            conn = writer.add_connection(topic, IMU_MSGTYPE, typestore=store)
            for k in range(len(g)):
                sec, nsec = divmod(int(ns[k]), 1_000_000_000)
                stamp = time_t(sec=sec, nanosec=nsec)
                header = header_t(seq=k, stamp=stamp, frame_id=frame_id) if kind == "ros1" else header_t(
                    stamp=stamp, frame_id=frame_id)
                msg = imu_t(header=header, orientation=identity, orientation_covariance=cov_o,
                            angular_velocity=vec_t(x=g[k, 0], y=g[k, 1], z=g[k, 2]), angular_velocity_covariance=cov_g,
                            linear_acceleration=vec_t(x=a[k, 0], y=a[k, 1], z=a[k, 2]),
                            linear_acceleration_covariance=cov_a)
                writer.write(conn, int(ns[k]), serialize(msg, IMU_MSGTYPE))
        os.replace(inner, target)
    except OSError as exc:
        raise AtomicWriteError(exc.errno, f"cannot write {str(target)!r}: {exc.strerror or exc}", str(target)) from None
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return target
