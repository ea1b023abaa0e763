"""``gyrobench simulate imu PART --trajectory FILE.toml``: a triad of a part moving along a motion definition.

The trajectory file (TOML, field units; every key optional but one ``[[motion]]`` row)::

    [site]                      # where the block is (held over the record)
    latitude_deg = 45.0         # -89.9..89.9
    height_m = 0.0
    earth_rotation = true       # false: a non-rotating Earth

    [initial]
    attitude_deg = [0, 0, 90]   # rotation vector of body -> NED [deg] (here: heading east)
    velocity_mps = [0, 0, 0]    # NED [m/s]

    [[motion]]                  # segments of constant body rate and NED acceleration
    duration_s = 10.0
    rate_dps = [0, 0, 0]
    acceleration_mps2 = [0, 0, 0]

    [accelerometer]             # a datasheet-level accelerometer (AccelerometerSpec.from_datasheet keys);
    vrw_m_s_sqrt_h = 0.05       # it replaces the part's own accelerometer figures for this run
    bias_instability_ug = 20.0

or a CSV of samples (a navigation solution or motion capture) with the header
``time_s,qw,qx,qy,qz,vn_mps,ve_mps,vd_mps``: time from 0 [s], the body-to-NED attitude quaternion
(scalar first) and the NED velocity [m/s], splined between the rows
(:class:`gyrobench.sim.trajectory.SampledMotion`); its site is ``--latitude`` (default 0) at sea
level.

The accelerometers: the trajectory's ``[accelerometer]`` table when it has one, else the part's
own (:meth:`gyrobench.sim.parts.Part.accelerometer`, from its sheet's ``accel_*`` figures), else
ideal (a gyro-only part: the record's output is then the true specific force after the triad's
misalignment). The record's metadata says which (``accelerometer_from``) and holds the spec in SI
(``accelerometer``).

Outputs besides ``-o``: ``--euroc`` (EuRoC/ASL ``data.csv``), ``--kalibr`` (Kalibr ``imu.yaml``)
and ``--rosbag`` (a ROS 1 ``.bag`` or a ROS 2 bag folder of ``sensor_msgs/msg/Imu``, through the
optional extra ``ros``: :mod:`gyrobench.io.rosbag`, :func:`write_bag`).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

from gyrobench.scenarios.cli.common import BadInput, check_outputs, input_file, one_line, read_toml

__all__ = ["simulate_imu", "load_trajectory", "load_trajectory_csv", "CSV_HEADER"]

#: the header line of a sampled trajectory CSV
CSV_HEADER = "time_s,qw,qx,qy,qz,vn_mps,ve_mps,vd_mps"

_ACCEL_KEYS = ("bias_repeatability_mg", "scale_factor_repeatability_ppm", "vrw_m_s_sqrt_h", "bias_instability_ug",
               "bias_tempco_mg_per_k", "scale_factor_tempco_ppm_per_k", "range_g", "bandwidth_hz", "resolution_mg")


def _table(data: dict, name: str, keys: tuple[str, ...], path: str) -> dict:
    t = data.get(name, {})
    if not isinstance(t, dict):
        raise BadInput(f"{path}: [{name}] must be a table")
    if unknown := sorted(set(t) - set(keys)):
        raise BadInput(f"{path}: [{name}] has unknown keys {unknown}; it takes {', '.join(keys)}")
    return t


def _number(t: dict, key: str, where: str, low: float, high: float, default: float) -> float:
    v = t.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and low <= v <= high):
        raise BadInput(f"{where}.{key} must be a number within {low:g}..{high:g}; got {v!r}")
    return float(v)


def load_trajectory(path: str):
    """(motion, site, accelerometer spec or None) from a trajectory TOML (module docstring).

    Parameters
    ----------
    path : str
        The TOML file.

    Returns
    -------
    tuple
        (:class:`~gyrobench.sim.trajectory.SegmentedMotion`, :class:`~gyrobench.sim.earth.Site`,
        :class:`~gyrobench.sim.imu.AccelerometerSpec` or None).
    """
    import numpy as np

    from gyrobench.base import units
    from gyrobench.sim.earth import Site
    from gyrobench.sim.imu import AccelerometerSpec
    from gyrobench.sim.trajectory import SegmentedMotion, segments_from_table

    data = read_toml(path, "--trajectory")
    if unknown := sorted(set(data) - {"site", "initial", "motion", "accelerometer"}):
        raise BadInput(f"{path}: unknown tables {unknown}; a trajectory takes [site], [initial], [[motion]], "
                       "[accelerometer]")
    site_t = _table(data, "site", ("latitude_deg", "height_m", "earth_rotation"), path)
    rot = site_t.get("earth_rotation", True)
    if not isinstance(rot, bool):
        raise BadInput(f"{path}: site.earth_rotation must be true or false; got {rot!r}")
    site = Site(latitude=units.deg(_number(site_t, "latitude_deg", "site", -89.9, 89.9, 0.0)),
                height=_number(site_t, "height_m", "site", -1e4, 1e5, 0.0), earth_rotation=rot)
    init = _table(data, "initial", ("attitude_deg", "velocity_mps"), path)
    rows = data.get("motion")
    if not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
        raise BadInput(f"{path}: needs at least one [[motion]] table (duration_s, rate_dps, acceleration_mps2)")
    try:
        segs = segments_from_table(rows)
        att = np.asarray(init.get("attitude_deg", [0.0, 0.0, 0.0]), dtype=float)
        vel = np.asarray(init.get("velocity_mps", [0.0, 0.0, 0.0]), dtype=float)
        if att.shape != (3,) or vel.shape != (3,) or np.any(np.abs(att) > 360) or np.any(np.abs(vel) > 1e4):
            raise ValueError(f"{path}: initial.attitude_deg (|each| <= 360) and initial.velocity_mps (|each| <= 1e4) "
                             "must be 3 numbers each")
        motion = SegmentedMotion(segs, attitude=units.deg(att), velocity=vel)
    except (TypeError, ValueError) as exc:
        raise BadInput(f"{path}: {one_line(exc)}") from None
    if motion.duration > 1e7:
        raise BadInput(f"{path}: the motion lasts {motion.duration:g} s; at most 1e7 s")
    acc_t = data.get("accelerometer")
    accel = None
    if acc_t is not None:
        acc_t = _table(data, "accelerometer", _ACCEL_KEYS, path)
        try:
            accel = AccelerometerSpec.from_datasheet(**{
                k: _number(acc_t, k, "accelerometer", -1e9 if "tempco" in k else 0.0, 1e9, 0.0) for k in acc_t})
        except (TypeError, ValueError) as exc:
            raise BadInput(f"{path}: {one_line(exc)}") from None
    return motion, site, accel


def load_trajectory_csv(path: str, latitude_deg: float):
    """(motion, site, None) from a sampled trajectory CSV (module docstring).

    Parameters
    ----------
    path : str
        The CSV file, its first line :data:`CSV_HEADER`.
    latitude_deg : float
        The site's latitude [deg].

    Returns
    -------
    tuple
        (:class:`~gyrobench.sim.trajectory.SampledMotion`, :class:`~gyrobench.sim.earth.Site`, None).
    """
    import numpy as np

    from gyrobench.base import memory, units
    from gyrobench.sim.earth import Site
    from gyrobench.sim.trajectory import SampledMotion

    p = Path(path)
    if not p.is_file():
        raise BadInput(f"--trajectory {path!r}: not a regular file")
    size = p.stat().st_size
    memory.check_memory(memory.csv_read_bytes(size, 8 / 20), f"reading --trajectory {path!r}")
    with open(p, encoding="utf-8", errors="replace") as fh:
        head = fh.readline(4096).strip()
    if head.replace(" ", "") != CSV_HEADER:
        raise BadInput(f"--trajectory {path!r}: the first line must be {CSV_HEADER!r}; got {head[:80]!r}")
    try:
        data = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as exc:
        raise BadInput(f"--trajectory {path!r}: {one_line(exc)}") from None
    if data.shape[1] != 8:
        raise BadInput(f"--trajectory {path!r}: rows must have 8 numbers; got {data.shape[1]}")
    try:
        motion = SampledMotion(data[:, 0], data[:, 1:5], data[:, 5:8])
    except ValueError as exc:
        raise BadInput(f"--trajectory {path!r}: {one_line(exc)}") from None
    return motion, Site(latitude=units.deg(latitude_deg)), None


def choose_accelerometer(part, table):
    """(spec, what it is) of the run's accelerometers: the trajectory's table, else the part's, else ideal.

    Parameters
    ----------
    part : gyrobench.sim.parts.Part
        The triad's part.
    table : AccelerometerSpec or None
        The trajectory's ``[accelerometer]`` table, if it has one.

    Returns
    -------
    tuple
        (:class:`~gyrobench.sim.imu.AccelerometerSpec`, a one-line description for the metadata).
    """
    from gyrobench.sim.imu import AccelerometerSpec

    if table is not None:
        return table, "the trajectory's [accelerometer] table"
    own = part.accelerometer()
    if own is not None:
        return own, f"the part's datasheet ({part.name}: {part.datasheet.source})"
    return AccelerometerSpec(), (f"ideal (the {part.name} sheet gives no accelerometer figures and the trajectory "
                                 "has no [accelerometer] table)")


def write_bag(path: str, rec, part, accel, *, increments: bool) -> None:
    """Write the record's six channels as a ROS bag (:func:`gyrobench.io.rosbag.write_imu_bag`) and say so.

    Stamps are the samples' times (the record's t0 + k/fs: each sample's interval centre); rates
    from increments are the increments x fs. The covariances are the per-sample white-noise
    variances of the spec: N^2 fs + q^2/12 for the gyros (N the part's ARW, q its LSB) and
    VRW^2 fs + q^2/12 for the accelerometers, zeros ("unknown") for ideal accelerometers.

    Parameters
    ----------
    path : str
        ``NAME.bag`` (ROS 1) or a new folder (ROS 2).
    rec : Recording
        The triad's record.
    part : gyrobench.sim.parts.Part
        The gyro part (its ARW and LSB set the gyro covariance).
    accel : AccelerometerSpec
        The run's accelerometers.
    increments : bool
        Whether the record holds increments.
    """
    import numpy as np

    from gyrobench.io.rosbag import bag_format, write_imu_bag

    fs = rec.fs
    names, scale = (("dtheta", "dv"), fs) if increments else (("gyro", "accel"), 1.0)
    g = np.column_stack([rec[f"{names[0]}_{a}"] for a in "xyz"]) * scale
    a = np.column_stack([rec[f"{names[1]}_{a}"] for a in "xyz"]) * scale
    d = part.datasheet
    q_g = math.radians(d.resolution or 0.0)
    var_g = d.angle_random_walk() ** 2 * fs + q_g**2 / 12
    var_a = accel.velocity_random_walk**2 * fs + accel.resolution**2 / 12
    stamps = rec.t0 + np.arange(rec.n_samples) / fs
    try:
        out = write_imu_bag(path, g, a, stamps=stamps, gyro_variance=var_g, accel_variance=var_a or None)
    except ValueError as exc:
        raise BadInput(f"--rosbag {path!r}: {one_line(exc)}") from None
    kind = "ROS 1 bag" if bag_format(out) == "ros1" else "ROS 2 bag folder"
    print(f"wrote {out} ({kind}: {rec.n_samples} sensor_msgs/msg/Imu messages on /imu0)")


def simulate_imu(args) -> int:
    """``simulate imu PART --trajectory FILE``: write the triad's record to -o (and EuRoC, Kalibr, ROS bag files).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``simulate`` arguments.

    Returns
    -------
    int
        The exit status (0).
    """
    import numpy as np

    from gyrobench.base import memory
    from gyrobench.base.safety import Output
    from gyrobench.io.imu_formats import kalibr_imu_yaml, write_euroc
    from gyrobench.io.recording import save_hdf5, to_csv
    from gyrobench.sim import parts
    from gyrobench.sim.imu import TriadSpec

    if args.part is None:
        raise BadInput(f"simulate imu needs a PART: one of {', '.join(parts.names())}, or a FILE.toml")
    if args.trajectory is None:
        raise BadInput("simulate imu needs --trajectory FILE.toml (a motion definition)")
    if args.output is None:
        raise BadInput("simulate imu needs -o FILE.h5 or FILE.csv")
    from gyrobench.scenarios.cli.simulate import load_part

    part = load_part(args.part, "PART")  # a missing, non-regular or too deeply nested part file: one line
    out = Path(args.output)
    if out.suffix.lower() not in (".h5", ".hdf5", ".csv"):
        raise BadInput(f"-o must end in .h5, .hdf5 or .csv; got {str(out)!r}")
    outs = [(out, "-o")]
    if args.euroc is not None:
        if not str(args.euroc).lower().endswith(".csv"):
            raise BadInput(f"--euroc must end in .csv; got {args.euroc!r}")
        outs.append((Path(args.euroc), "--euroc"))
    if args.kalibr is not None:
        if not str(args.kalibr).lower().endswith(".yaml"):
            raise BadInput(f"--kalibr must end in .yaml; got {args.kalibr!r}")
        outs.append((Path(args.kalibr), "--kalibr"))
    if args.rosbag is not None:
        from gyrobench.io.rosbag import bag_format, rosbags_available

        if not rosbags_available():
            raise BadInput("--rosbag needs the optional package rosbags: pip install 'gyrobench[ros]' "
                           "(or pip install rosbags)")
        bag = Path(args.rosbag)
        if bag.exists() or bag.is_symlink():
            raise BadInput(f"--rosbag {str(bag)!r} exists: a bag is written only to a new path (a bag carries no "
                           "mark gyrobench could recognise it by); give a new path")
        if bag_format(bag) == "ros2" and bag.suffix:
            raise BadInput(f"--rosbag takes NAME.bag (ROS 1) or a folder name without a suffix (ROS 2); "
                           f"got {str(bag)!r}")
        outs.append((bag, "--rosbag"))
    # the output rule (gyrobench.base.safety): no output is the trajectory, the part file or another output;
    # an existing file is replaced only if gyrobench wrote it (or with --force)
    part_file = args.part if str(args.part).lower().endswith(".toml") else None
    input_file(args.trajectory, "--trajectory")
    check_outputs(args, [Output(p, flag) for p, flag in outs], [("--trajectory", args.trajectory), ("PART", part_file)])
    if str(args.trajectory).lower().endswith(".csv"):
        lat = 0.0 if args.latitude is None else args.latitude
        motion, site, accel = load_trajectory_csv(args.trajectory, lat)
    else:
        if args.latitude is not None:
            raise BadInput("simulate imu: --latitude applies to a CSV trajectory; a TOML one states [site]")
        motion, site, accel = load_trajectory(args.trajectory)
    fs = 100.0 if args.fs is None else float(args.fs)
    n = int(math.floor(motion.duration * fs + 1e-9))
    if n < 2:
        raise BadInput(f"simulate imu: {motion.duration:g} s at {fs:g} Hz gives {n} samples; at least 2")
    # 6 outputs, ~8 truth terms each, the increments and their attitude (9) and the nodes of a chunk
    memory.check_memory(memory.series_bytes(n, 90), "simulate imu", hint="shorten the motion or lower --fs")
    mis = 0.0 if args.misalignment is None else args.misalignment * 1e-3
    cross = 0.0 if args.cross_axis is None else args.cross_axis * 1e-2
    accel, accel_from = choose_accelerometer(part, accel)
    spec = TriadSpec(gyros=(part, part, part), accelerometer=accel, misalignment=mis,
                     cross_axis=cross, accel_misalignment=mis, accel_cross_axis=cross)
    seed = 0 if args.seed is None else args.seed
    rng_unit, rng_run = np.random.default_rng(seed).spawn(2)
    result = spec.realize(rng=rng_unit).simulate(motion, fs=fs, rng=rng_run, site=site,
                                                  as_increments=bool(args.increments))
    rec = dataclasses.replace(result.recording, metadata={**result.recording.metadata,
                                                          "accelerometer_from": accel_from})
    path = (to_csv(out, rec, overwrite=args.force) if out.suffix.lower() == ".csv"
            else save_hdf5(out, rec, compression=args.compress, overwrite=args.force))
    print(f"wrote {path} ({n} samples at {fs:g} Hz of a {part.name} triad; channels {', '.join(rec.channels)}; "
          f"accelerometers: {accel_from})")
    if args.euroc is not None:
        scale = fs if args.increments else 1.0
        names = ("dtheta", "dv") if args.increments else ("gyro", "accel")
        g = np.column_stack([rec[f"{names[0]}_{a}"] for a in "xyz"]) * scale
        a = np.column_stack([rec[f"{names[1]}_{a}"] for a in "xyz"]) * scale
        print(f"wrote {write_euroc(args.euroc, g, a, fs=fs, t0=rec.t0)} (EuRoC/ASL imu0 CSV)")
    if args.rosbag is not None:
        write_bag(args.rosbag, rec, part, accel, increments=bool(args.increments))
    if args.kalibr is not None:
        from gyrobench.base.atomic import atomic_path

        d = part.datasheet
        acc = accel
        text = kalibr_imu_yaml(gyro_noise_density=d.angle_random_walk(), gyro_random_walk=0.0,
                               accel_noise_density=acc.velocity_random_walk,
                               accel_random_walk=acc.acceleration_random_walk, update_rate=fs)
        with atomic_path(args.kalibr) as tmp:
            Path(tmp).write_text(text)
        print(f"wrote {args.kalibr} (Kalibr imu.yaml from the part's and accelerometer's figures; "
              "gyroscope_random_walk 0: a part states no rate random walk)")
    return 0
