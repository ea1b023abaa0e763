"""The noise files ``gyrobench allan`` writes from the analysed channels
(:func:`gyrobench.scenarios.reports.allan.analyse`): the Kalibr IMU noise file (imu.yaml) and the
filter's noise model. Formatting only: nothing here computes or decides.
"""

from __future__ import annotations

from gyrobench.scenarios.reports.allan import ChannelResult
from gyrobench.scenarios.reports.allan_json import _motion_fitted, _si_unit

__all__ = ["filter_yaml", "kalibr_yaml"]


def kalibr_yaml(log, results: list[ChannelResult]) -> str:
    """The Kalibr IMU noise file (imu.yaml) from the fits of a log's gyro and accelerometer axes.

    Conversions (Kalibr wiki "IMU Noise Model"; continuous-time densities equal the IEEE 952
    coefficients in SI):

    * gyroscope_noise_density [rad/s/sqrt(Hz)] = N [rad/sqrt(s)] (angle random walk);
    * gyroscope_random_walk [rad/s^2/sqrt(Hz)] = K [rad/s/sqrt(s)] (rate random walk);
    * accelerometer_noise_density [m/s^2/sqrt(Hz)] = N [m/s/sqrt(s)] (velocity random walk);
    * accelerometer_random_walk [m/s^3/sqrt(Hz)] = K [m/s^2/sqrt(s)] (acceleration random walk);
    * update_rate [Hz] = the sample rate.

    Kalibr takes one value per sensor: the largest over the axes (conservative). A term not
    identifiable on an axis contributes its 95 % upper bound, and the file says so in a
    comment. Bias instability has no place in Kalibr's model and is given as a comment.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.

    Returns
    -------
    str
        The imu.yaml text.
    """
    lines = [
        "# Kalibr IMU noise parameters written by gyrobench allan",
        f"# from {log.path.name}: {len(results[0].channel.data)} samples at {log.fs:g} Hz",
        "# densities are the IEEE 952 N and K of each axis (largest over the axes), continuous time",
    ]
    moving = [r.channel.label for r in results if _motion_fitted(r)]
    if moving:
        lines.append(f"# WARNING not stationary (motion or steps; the values describe them too): {', '.join(moving)}")
    quiet = [r.channel.label for r in results if r.nonstationary and not _motion_fitted(r)]
    if quiet:
        lines.append(f"# not stationary as a whole; fitted from the quiet stretches: {', '.join(quiet)}")
    keys = {
        ("rate", "N"): ("gyroscope_noise_density", "rad/s/sqrt(Hz)"),
        ("rate", "K"): ("gyroscope_random_walk", "rad/s^2/sqrt(Hz)"),
        ("accel", "N"): ("accelerometer_noise_density", "m/s^2/sqrt(Hz)"),
        ("accel", "K"): ("accelerometer_random_walk", "m/s^3/sqrt(Hz)"),
    }
    body = []
    for (q, term), (key, unit) in keys.items():
        fits = [
            r
            for r in results
            if r.fit is not None and r.channel.quantity == q and term in r.fit.coefficients
        ]
        if not fits:
            continue
        vals, bounds = [], []
        for r in fits:
            c = r.fit.coefficients[term]
            vals.append(c.value if c.identifiable else c.upper_bound)
            if not c.identifiable:
                bounds.append(r.channel.label)
        floored = [r.channel.label for r in fits if r.fit.coefficients[term].bound_note]
        note = f"  # 95 % upper bound on {', '.join(bounds)} (not identifiable)" if bounds else ""
        note += f"; bound from a sub-segment on {', '.join(floored)}" if floored else ""
        body.append(
            f"{key}: {max(vals):.6e}  # [{unit}] max over {', '.join(r.channel.label for r in fits)}{note}"
        )
        if term == "N":
            bis = [r.fit.coefficients["B"] for r in fits if "B" in r.fit.coefficients]
            bi = [c.value for c in bis if c.identifiable]
            if bi:
                lines.append(
                    f"# {'gyroscope' if q == 'rate' else 'accelerometer'} bias instability B (not used by "
                    f"Kalibr): {max(bi):.4e} [{_si_unit(q)}]"
                )
    if not body:
        raise ValueError(
            "--kalibr needs a fitted gyro or accelerometer channel (N and K terms); none was fitted"
        )
    return "\n".join(lines + body + [f"update_rate: {log.fs:g}  # [Hz]", ""])


# ----------------------------------------------------------------------------- filter process noise
def filter_yaml(log, results: list[ChannelResult], *, overbound: bool = False) -> str:
    """The fitted model as a navigation filter's process noise (:func:`gyrobench.analysis.filter_model.filter_model`).

    Sections: ``gyrobench`` (every key carries its unit: each axis's white and random-walk
    densities, B as a Gauss-Markov state and as a random-walk equivalent, the inflation),
    ``kalibr`` (imu.yaml) and ``openvins`` (kalibr_imu_chain.yaml ``imu0``), whose key names
    the tools fix, with the unit in a comment on every line, and ``ros`` (the diagonal of
    ``sensor_msgs/Imu`` covariances: the per-sample white-noise variance N^2 fs). Kalibr,
    OpenVINS and ROS take one value per sensor: the largest over the axes.

    Parameters
    ----------
    log : ImuLog
        The log analysed.
    results : list of ChannelResult
        Its channels' results.
    overbound : bool
        Scale the model to overbound the data's 95 % bound.

    Returns
    -------
    str
        The YAML text.
    """
    from gyrobench.analysis.filter_model import filter_model

    lines = [f"# gyrobench filter process noise from {log.path.name} ({log.fs:g} Hz)",
             "# conversions: white density = N; random-walk density = K; B as Gauss-Markov sigma = 0.664 B / 0.6174,",
             "# Tc = tau_B / 1.8926 (its ADEV peaks at the B plateau at tau_B),",
             "# or as random walk 0.664 B sqrt(3 / tau_B)"]
    if overbound:
        lines.append("# overbounded: every density scaled by the smallest k putting the model ADEV on or above the "
                     "data's upper 95 % bound at every tau")
    moving = [r.channel.label for r in results if r.nonstationary]
    if moving:
        lines.append("# not stationary as a whole (fitted from the quiet stretches where possible): "
                     + ", ".join(moving))
    per: dict[str, list] = {"rate": [], "accel": []}
    lines.append("gyrobench:")
    for r in results:
        if r.fit is None:
            continue
        fm = filter_model(r.fit, overbound=overbound)
        q = r.channel.quantity
        per[q].append(fm)
        u = "m_per_s2" if q == "accel" else "rad_per_s"
        u2 = "m_per_s3" if q == "accel" else "rad_per_s2"
        key = "".join(ch if ch.isalnum() else "_" for ch in r.channel.label).strip("_")
        lines += [f"  {key}:",
                  f"    white_density_{u}_per_sqrt_hz: {fm.white_density:.6e}",
                  f"    white_variance_per_sample_{u}_squared: {fm.white_variance_per_sample:.6e}",
                  f"    random_walk_density_{u2}_per_sqrt_hz: {fm.random_walk_density:.6e}",
                  f"    bias_gauss_markov_sigma_{u}: {fm.gm_sigma:.6e}",
                  f"    bias_gauss_markov_time_constant_s: {fm.gm_tc:.6g}",
                  f"    bias_random_walk_equivalent_{u2}_per_sqrt_hz: {fm.rw_equivalent_density:.6e}",
                  f"    bias_tau_s: {fm.tau_b:.6g}",
                  f"    inflation_factor_1: {fm.inflation:.4g}",
                  f"    upper_bounds_not_identified: [{', '.join(fm.bounds)}]"]
    if not per["rate"] and not per["accel"]:
        raise ValueError("--filter-model needs a fitted gyro or accelerometer channel; none was fitted")
    tool = []
    for q, pre, unit_w, unit_rw in (("rate", "gyroscope", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)"),
                                    ("accel", "accelerometer", "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)")):
        if per[q]:
            w = max(f.white_density for f in per[q])
            rw = max(max(f.random_walk_density, f.rw_equivalent_density) for f in per[q])
            tool += [f"  {pre}_noise_density: {w:.6e}  # [{unit_w}]",
                     f"  {pre}_random_walk: {rw:.6e}  # [{unit_rw}] max of K and B's random-walk equivalent"]
    lines += ["kalibr:", *tool, f"  update_rate: {log.fs:g}  # [Hz]"]
    lines += ["openvins:", *tool, f"  update_rate: {log.fs:g}  # [Hz]"]
    lines.append("ros:")
    for q, name, unit in (("rate", "angular_velocity_covariance", "rad^2/s^2"),
                          ("accel", "linear_acceleration_covariance", "m^2/s^4")):
        if per[q]:
            d = max(f.white_variance_per_sample for f in per[q])
            lines.append(f"  {name}: [{d:.6e}, 0.0, 0.0, 0.0, {d:.6e}, 0.0, 0.0, 0.0, {d:.6e}]  # [{unit}] row-major")
    return "\n".join(lines) + "\n"
