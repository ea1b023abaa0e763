"""``gyrobench twin``: a digital twin of a real static gyro record, and whether its Allan deviation matches.

::

    gyrobench twin REAL.csv --column gyro_z [--fs HZ] [--units deg/s] -o twin.h5|twin.csv [--seed S]
                   [--part NAME | --nearest MEMS|FOG|RLG] [--alpha 0.05] [--json] [--plot twin.png]
                   [--save-part FILE.toml [--technology MEMS|FOG|RLG]]

The real record's noise is fitted (:func:`gyrobench.analysis.allan.fit_noise`, the five IEEE
952 terms, ``tau_min="auto"``); the fitted Allan-variance model sum_n C_n tau^n becomes a
:class:`gyrobench.sim.noise.NoiseModel` (each C_n to its coefficient, Q, N, B, K, R), or with
``--part`` / ``--nearest`` a built-in part's model is used instead; a record of the same
length and rate is simulated and the two curves are compared at the fitted taus by
:func:`gyrobench.analysis.twin.compare_twin`: the pass rule is an F test of the two
independent Allan-variance estimates per tau with Sidak's correction, a family-wise
false-alarm rate of ``--alpha`` (a perfect twin fails at most that often). ``--save-part``
writes the fitted model as a part file (:func:`part_fields`) that ``simulate device`` runs. The twin
itself (the fit to a noise model, the simulated record, the comparison) is
:mod:`gyrobench.scenarios.cli.twin_model`, whose names are importable from here; this module is the
verb (flags, outputs, the part file). The twin lives in the top layer, not in ``sim`` or
``analysis``: it needs both, which never import each other.
"""

from __future__ import annotations

import json
from pathlib import Path

from gyrobench.scenarios.cli.common import (
    MAX_FLAG_VALUE,
    BadInput,
    add_force,
    check_outputs,
    input_file,
    positive_float,
    seed,
)
from gyrobench.scenarios.cli.twin_model import (
    NonStationaryRecord,
    TwinResult,
    gauss_markov_term,
    make_twin,
    nearest_part,
    noise_model_from_fit,
)

__all__ = ["TwinResult", "add_parser", "gauss_markov_term", "make_twin", "nearest_part", "noise_model_from_fit"]


def _table(res: TwinResult, label: str) -> list[str]:
    from gyrobench.base import units

    c = res.comparison
    dph = 1.0 / units.deg_per_h(1.0)
    ra = res.analysis
    basis = "" if ra is None or ra.basis == "whole record" else f" (built from the real record's {ra.basis})"
    lines = [f"twin of {label}: model {res.model}{basis}; {res.recording.n_samples} samples at "
             f"{res.recording.fs:g} Hz",
             f"rule: {c.rule}",
             *([f"Gauss-Markov term (the five power laws misfit): sigma {res.coefficients['gm_sigma'] * dph:.4g} "
                f"deg/h, Tc {res.coefficients['gm_correlation_time']:.4g} s"]
               if "gm_sigma" in res.coefficients else []),
             f"{'tau [s]':>10} {'real ADEV':>11} {'real 95% interval':>23} {'twin ADEV':>11} {'twin/real':>9} "
             f"{'band':>15} {'in real95':>9} {'pass':>5}  [deg/h]"]
    for i in range(c.n_taus):
        lines.append(f"{c.tau[i]:>10.4g} {c.real[i] * dph:>11.4g} "
                     f"[{c.real_low95[i] * dph:>10.4g}, {c.real_high95[i] * dph:>10.4g}] {c.twin[i] * dph:>11.4g} "
                     f"{c.ratio[i]:>9.3f} [{c.ratio_low[i]:.3f}, {c.ratio_high[i]:.3f}] "
                     f"{'yes' if c.inside_real95[i] else 'no':>9} {'ok' if c.inside[i] else 'FAIL':>5}")
    sp = res.samples
    if sp is not None:
        lines.append(f"samples [deg/h]: real mean {sp.real_mean * dph:.5g}, sd {sp.real_std * dph:.4g}, range "
                     f"[{sp.real_range[0] * dph:.4g}, {sp.real_range[1] * dph:.4g}]; "
                     f"twin mean {sp.twin_mean * dph:.5g}, "
                     f"sd {sp.twin_std * dph:.4g}, range [{sp.twin_range[0] * dph:.4g}, {sp.twin_range[1] * dph:.4g}]; "
                     f"sd ratio {sp.std_ratio:.3f} in [{sp.band[0]:.3f}, {sp.band[1]:.3f}]: "
                     f"{'ok' if sp.passed else 'FAIL'}")
    verdict = "MATCHES" if res.passed else "DOES NOT MATCH"
    lines.append(f"twin {verdict}: {int(c.inside.sum())}/{c.n_taus} octave taus inside the band"
                 f"{'' if sp is None else ', sample spread ' + ('ok' if sp.passed else 'outside its band')}; "
                 f"{int(c.inside_real95.sum())}/{c.n_taus} inside the real curve's own 95 % interval (informative)")
    return lines


def _json(res: TwinResult, label: str) -> dict:
    c = res.comparison
    sp = res.samples
    samples = None if sp is None else {
        "real_mean": sp.real_mean, "twin_mean": sp.twin_mean, "real_std": sp.real_std, "twin_std": sp.twin_std,
        "real_range": list(sp.real_range), "twin_range": list(sp.twin_range), "std_ratio": sp.std_ratio,
        "band": list(sp.band), "edf": sp.edf, "passed": sp.passed, "unit": "rad/s"}
    return {"source": label, "model": res.model, "fs": res.recording.fs, "n_samples": res.recording.n_samples,
            "basis": None if res.analysis is None else res.analysis.basis,
            "coefficients_si": res.coefficients, "rule": c.rule, "family_alpha": c.family_alpha,
            "per_tau_alpha": c.per_tau_alpha, "passed": res.passed, "adev_passed": c.passed, "samples": samples,
            "taus": [{"tau": float(c.tau[i]), "real": float(c.real[i]), "real_low95": float(c.real_low95[i]),
                      "real_high95": float(c.real_high95[i]), "twin": float(c.twin[i]), "ratio": float(c.ratio[i]),
                      "ratio_low": float(c.ratio_low[i]), "ratio_high": float(c.ratio_high[i]),
                      "edf_real": float(c.edf_real[i]), "edf_twin": float(c.edf_twin[i]),
                      "inside": bool(c.inside[i]), "inside_real95": bool(c.inside_real95[i])}
                     for i in range(c.n_taus)]}


def _plot(res: TwinResult, label: str, target: Path) -> None:
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gyrobench.base import units
    from gyrobench.base.atomic import atomic_path
    from gyrobench.base.safety import PNG_METADATA

    c = res.comparison
    dph = 1.0 / units.deg_per_h(1.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.fill_between(c.tau, c.real_low95 * dph, c.real_high95 * dph, alpha=0.25, label="real 95 % interval")
    ax.loglog(c.tau, c.real * dph, "o-", label="real")
    ax.loglog(c.tau, c.twin * dph, "s--", label=f"twin ({res.model})")
    bad = ~c.inside
    if np.any(bad):
        ax.loglog(c.tau[bad], c.twin[bad] * dph, "rx", ms=10, label="outside the F band")
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("Allan deviation [deg/h]")
    ax.set_title(f"twin of {label}: {'matches' if res.passed else 'does not match'} "
                 f"(family-wise alpha {c.family_alpha:g})", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format="png", dpi=120, bbox_inches="tight", metadata=PNG_METADATA)
    plt.close(fig)


#: the fitted terms a saved part carries: coefficient key -> (Datasheet field, SI -> field unit)
_PART_FIELDS = {"Q": ("quantization", "to_arcsec"), "N": ("arw", "to_deg_per_sqrt_h"),
                "B": ("bias_instability_dph", "to_deg_per_h"), "K": ("rate_random_walk", "to_deg_per_h_per_sqrt_h"),
                "R": ("rate_ramp", "to_deg_per_h2")}


def _grade(b_dph: float) -> str:
    """A fitted part's grade from its bias instability [deg/h] (a labelling convention: < 0.01 navigation,
    < 1 tactical, < 10 industrial, else consumer; the grade selects nothing in the simulation)."""
    return "navigation" if b_dph < 0.01 else "tactical" if b_dph < 1.0 else "industrial" if b_dph < 10.0 else "consumer"


def part_fields(res: TwinResult, fs: float, *, source: str, technology: str, name: str) -> dict[str, object]:
    """The :class:`~gyrobench.sim.parts.Datasheet` fields of a part whose budget is the twin's fitted model.

    Each fitted term becomes its part field in the field's unit (Q arcsec, N deg/sqrt(h), B deg/h as
    the IEEE coefficient itself, K deg/h/sqrt(h), R deg/h^2, the Gauss-Markov sigma and sine amplitude
    deg/h, its correlation time s, the sine's frequency Hz, the constant bias deg/h); a fitted
    low-pass is the part's output filter (corner and order), the record's rate its output rate; the
    part runs on its budget by default (``default_model = "budget"``). The 95 % intervals of the
    IEEE terms are written in ``notes``.
    """
    from gyrobench.base import units

    c = res.coefficients
    f: dict[str, object] = {
        "name": name, "manufacturer": "gyrobench twin", "model": f"fitted to {source}", "technology": technology,
        "source": f"gyrobench twin fit of {source} ({res.recording.n_samples} samples at {fs:g} Hz)",
        "source_kind": "fit", "default_model": "budget", "bias_instability_is_b": True, "output_rate": float(fs),
    }
    for key, (field_name, conv) in _PART_FIELDS.items():
        v = float(c.get(key, 0.0))
        if v > 0:
            f[field_name] = float(getattr(units, conv)(v))
    if c.get("gm_sigma"):
        f["gauss_markov_sigma"] = float(units.to_deg_per_h(c["gm_sigma"]))
        f["gauss_markov_tau"] = float(c["gm_correlation_time"])
    if c.get("sine_amplitude"):
        f["sine_amplitude"] = float(units.to_deg_per_h(c["sine_amplitude"]))
        f["sine_frequency"] = 1.0 / float(c["sine_period"])
    if c.get("lowpass_corner"):
        f["bandwidth"] = float(c["lowpass_corner"])
        f["filter_order"] = int(c["lowpass_order"])
    if c.get("bias"):
        f["bias_offset"] = float(units.to_deg_per_h(c["bias"]))
    b_dph = f.get("bias_instability_dph", 0.0)
    f["grade"] = _grade(b_dph if isinstance(b_dph, float) else 0.0)
    ci = []
    for key, (field_name, conv) in _PART_FIELDS.items():
        co = res.fit.coefficients.get(key)
        if co is not None:
            lo, hi = (float(getattr(units, conv)(x)) for x in co.ci95)
            ci.append(f"{field_name} 95 % interval [{lo:.6g}, {hi:.6g}]" + ("" if co.identifiable else
                                                                             " (not identifiable)"))
    f["notes"] = "; ".join(ci)
    return f


def _toml_value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    return json.dumps(str(v))  # a TOML basic string: JSON's escapes are TOML's


def write_part_toml(path: Path, fields: dict[str, object], what: str) -> None:
    """Write ``fields`` as a part file (top-level keys) with gyrobench's first-line marker, atomically."""
    from gyrobench.base.atomic import atomic_path
    from gyrobench.base.safety import comment_marker

    text = comment_marker(what) + "\n" + "".join(f"{k} = {_toml_value(v)}\n" for k, v in fields.items())
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")


def _check_twin_outputs(args, path: Path) -> None:
    """-o and --plot through the output rule (gyrobench.base.safety): never the record or the --part file."""
    from gyrobench.base.safety import Output

    part = args.part if args.part is not None and args.part.lower().endswith(".toml") else None
    if args.part is not None:  # read once here: a missing, foreign or too deeply nested part fails before the fit
        from gyrobench.scenarios.cli.simulate import load_part

        load_part(args.part, "--part")
    outs = [Output(Path(args.output), "-o", suffixes=(".h5", ".hdf5", ".csv"), create_parents=False)]
    if args.plot:
        outs.append(Output(Path(args.plot), "--plot", suffixes=(".png",), create_parents=False))
    if args.save_part:
        outs.append(Output(Path(args.save_part), "--save-part", suffixes=(".toml",), create_parents=False))
    check_outputs(args, outs, [("FILE", path), ("--part", part)])


def _cmd_twin(args) -> int:
    import numpy as np

    from gyrobench.io.recording import save_hdf5
    from gyrobench.scenarios.cli.allan import _check_allan_input, _read_hdf5

    path = input_file(args.file, "recording file")  # not found, a folder, a FIFO, a device: one line
    if args.part is not None and args.nearest is not None:
        raise BadInput("give --part NAME or --nearest TECHNOLOGY, not both")
    if args.save_part is not None and (args.part is not None or args.nearest is not None):
        raise BadInput("--save-part saves the fitted model; with --part or --nearest the twin is a built-in part's")
    if args.technology is not None and args.save_part is None:
        raise BadInput("--technology names the technology of the --save-part file; give --save-part FILE.toml")
    if Path(args.output).suffix.lower() not in (".h5", ".hdf5", ".csv"):
        raise BadInput(f"-o must end in .h5, .hdf5 or .csv; got {args.output!r}")
    _check_twin_outputs(args, path)  # before any work
    columns = [args.column] if args.column is not None else None
    if path.suffix.lower() in (".h5", ".hdf5"):
        if args.fs is not None or args.units is not None:
            raise BadInput("--fs and --units apply to CSV input; an HDF5 recording carries its own")
        log = _read_hdf5(path, None, columns)
    else:
        from gyrobench.io.logs import read_csv_log

        log = read_csv_log(path, columns, args.fs, args.units)
    # without --column, a triad's first gyro (its outputs come in name order, accelerometers first)
    ch = log.channels[0] if columns else next((c for c in log.channels if c.quantity == "rate"), log.channels[0])
    if ch.quantity != "rate":
        raise BadInput(f"--column must name a rate column; {ch.label!r} is {ch.quantity}")
    rate = np.asarray(ch.data, dtype=float)
    if not np.all(np.isfinite(rate)):
        raise BadInput(f"{ch.label!r} holds non-finite samples; the twin needs a complete record")
    _check_allan_input(rate, log.fs, ch.label, "overlapping")
    from gyrobench.scenarios.cli import exits

    try:
        res = make_twin(rate, log.fs, rng=np.random.default_rng(args.seed), source=f"{path.name}:{ch.label}",
                        part=args.part, nearest=args.nearest, family_alpha=args.alpha)
    except NonStationaryRecord as exc:
        print(f"NONSTATIONARY {path.name}:{ch.label}: {exc}")
        return exits.NONSTATIONARY
    if Path(args.output).suffix.lower() == ".csv":
        from gyrobench.io.recording import to_csv

        to_csv(Path(args.output), res.recording, overwrite=args.force)
    else:
        save_hdf5(Path(args.output), res.recording, overwrite=args.force)
    label = f"{path.name}:{ch.label}"
    if args.save_part:
        import re

        stem = re.sub(r"[^a-z0-9_.-]+", "-", Path(args.save_part).stem.lower()).strip("-") or "twin"
        fields = part_fields(res, log.fs, source=label, technology=args.technology or "MEMS", name=stem)
        from gyrobench.sim.parts import Datasheet

        Datasheet(**fields)  # type: ignore[arg-type]  # the part file simulate device reads back, checked first
        write_part_toml(Path(args.save_part), fields, f"twin {label}: a part fitted to the record")
    if args.plot:
        _plot(res, label, Path(args.plot))
    if args.json:
        print(json.dumps(_json(res, label)))
    else:
        lines = _table(res, label)
        if res.analysis is not None and res.analysis.nonstationary:
            lines.insert(0, f"NONSTATIONARY {label}: motion or steps in the record; the twin is of its quiet "
                            "stretches, as gyrobench allan analyses them")
        print("\n".join(lines))
        print(f"wrote {args.output}" + (f" and {args.plot}" if args.plot else "")
              + (f" and the part file {args.save_part} (simulate device {args.save_part})" if args.save_part else ""))
    if res.analysis is not None and res.analysis.nonstationary and not args.accept_nonstationary:
        return exits.NONSTATIONARY
    return 0 if res.passed else 1


def _alpha_arg(text: str) -> float:
    import argparse

    v = positive_float("--alpha")(text)
    if not v < 1:
        raise argparse.ArgumentTypeError(f"--alpha must be in (0, 1); got {text!r}")
    return v


def add_parser(sub) -> None:
    """Add ``twin`` to the subparsers ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``gyrobench`` command's subparsers.
    """
    s = sub.add_parser("twin", help="digital twin of a real static record: fit, simulate, compare Allan deviations",
                       epilog="exit status: 0 the twin matches; 1 it does not (some octave tau outside the band, "
                              "or the sample spread); 2 bad input; 5 the record is not stationary (the twin is of "
                              "its quiet stretches, or none is built; --accept-nonstationary exits 0/1)")
    s.add_argument("file", help="real static record: CSV (.csv, .csv.gz) or gyrobench HDF5")
    s.add_argument("--column", help="the rate column (CSV name or index; HDF5 channel, default 'rate')")
    s.add_argument("--fs", type=positive_float("--fs", MAX_FLAG_VALUE),
                   help="CSV without a time column: sample rate [Hz]")
    s.add_argument("--units", help="CSV: unit of the column, e.g. deg/s, deg/h, rad/s (default: from the header)")
    s.add_argument("-o", "--output", required=True, help="write the twin recording here (.h5 HDF5 or .csv, with its "
                                                      "truth columns)")
    s.add_argument("--seed", type=seed, default=0, help="seed of the twin's noise (default 0)")
    s.add_argument("--part", help="use this built-in part's (or .toml part's) datasheet model instead of the fit")
    s.add_argument("--nearest", choices=("MEMS", "FOG", "RLG"),
                   help="use the built-in part of this technology nearest the fit in (N, B)")
    s.add_argument("--alpha", type=_alpha_arg, default=0.05,
                   help="family-wise false-alarm rate of the pass rule: a perfect twin fails at most this often "
                        "(default 0.05)")
    s.add_argument("--accept-nonstationary", action="store_true",
                   help="exit 0/1 by the match also when the record has motion or steps (the twin is then of its "
                        "quiet stretches; default: exit status 5, as allan)")
    s.add_argument("--save-part", help="also write the fitted model as a part file (.toml) that 'simulate device' "
                                       "reads (its budget: the fitted Q, N, B, K, R, Gauss-Markov, sine and filter "
                                       "terms)")
    s.add_argument("--technology", choices=("MEMS", "FOG", "RLG"),
                   help="the technology the --save-part file names (default MEMS; the saved part runs on its "
                        "budget unless simulate device --model physics)")
    s.add_argument("--json", action="store_true", help="print the per-tau comparison as JSON")
    s.add_argument("--plot", help="write the overlaid ADEV figure (PNG)")
    add_force(s)
    s.set_defaults(func=_cmd_twin)
