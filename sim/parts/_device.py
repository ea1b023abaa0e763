"""A part on its technology's physics model: the sheet's environmental figures mapped onto the model's parameters.

:func:`physics_spec` starts from the noise mapping of :mod:`gyrobench.sim.parts._physics`
(:func:`~gyrobench.sim.parts.fog_spec`, :func:`~gyrobench.sim.parts.mems_spec`,
:func:`~gyrobench.sim.parts.rlg_spec`: the sheet's ARW and bias instability) and maps the
sheet's temperature and acceleration figures onto the physical parameters that produce them;
:func:`simulate_part` runs one record on that model (``model="physics"``) or on the datasheet
budget of :class:`~gyrobench.sim.parts.Part` (``model="budget"``), and says which ran in the
record's metadata (``model_kind``).

The mapping, per technology (SI inside; every coefficient taken positive, as the budget does:
the sheets print +- magnitudes)
---------------------------------------------------------------------------------------------
MEMS (:class:`gyrobench.sim.mems_resonator.MemsResonator`)
    The default resonator is ideal (no quadrature, anisodamping or phase error): it has no bias,
    no g-sensitivity and no bias tempco until the sheet's figures give it the imperfections
    that produce them (docs/physics.md 5.1). The g-sensitivity is the quadrature force of a
    specific force leaking through the rebalance phase error, g_s = SF tan(theta0) (dk_yx/df) /
    (2 m w) (:func:`~gyrobench.sim.mems_resonator.g_sensitivity`, the default plates' area
    gradient): the sheet's g_s sets ``phase_error`` theta0 (|theta0| < 0.5 rad). The bias tempco is
    the anisodamping bias Omega_b = eps_c c_y / (2 m) following the damping's 1/Q (``q_tc``, the
    default 2e-3/K): the sheet's c_T sets ``damping_coupling`` eps_c so that
    d zero_rate_output / dT = c_T at the reference temperature (its bias there is the factory
    trim's). The scale factor SF(T) ~ (w/w0)(G0/G) cos theta follows the frequency and
    rebalance-gain tempcos: the sheet's k_T sets ``gain_tc`` so that d ln SF / dT = k_T. The
    two tempcos (the scale factor's first: the bias is SF x Omega_b, so the bias solve comes
    last) by a secant solve on the noise-free closed forms
    :func:`~gyrobench.sim.mems_resonator.zero_rate_output` and
    :func:`~gyrobench.sim.mems_resonator.low_rate_scale_factor` (central differences over
    +-1 K, to 1e-3 relative). A figure the sheet does not print leaves the default design's
    value. The record's terms: the resonator's temperature bias zero_rate_output(T) -
    zero_rate_output(T0) as ``bias_temperature`` and its scale-factor change
    (SF(T)/SF(T0) - 1) x true rate as ``scale_factor_temperature`` (both from the closed forms,
    interpolated over 33 temperatures of the record's span), the rest of the slow flow's error
    as ``resonator``.
FOG (:class:`gyrobench.sim.fog2d.FOG2DUnit`)
    The chamber drives the (r, z) heat flow of the coil: the Shupe and T x dT drift and the
    scale factor's (1 + alpha_D dT)^2 / (1 + alpha_lambda dT) law come from the coil's
    materials and winding, not from a sheet figure (a bias tempco is not a FOG's law: the
    Shupe drift follows dT/dt). The sheet's scale-factor tempco, where printed, sets the
    source's wavelength tempco alpha_lambda = 2 alpha_D - k_T. A shaker run (the
    environment's ``vibration``) drives the coil's own modes through the loop
    (:mod:`gyrobench.sim.coil_vibration`: the spool's inertial strain weighted on the unit's
    winding map, the pigtail, the fixture; docs/physics.md 4.3): the terms
    ``strain_nonreciprocity``, ``rectification`` and ``loop_error``. The model has no static
    g-sensitive term (the strain term follows the acceleration's rate): the sheet's
    g-sensitivity (where printed) is added as the term ``g_sensitivity`` = g_s f, a sheet term
    on the physics record, named in the metadata.
RLG (:class:`gyrobench.sim.rlg.RLGUnit`)
    The chamber drives the two-node (housing, cavity) thermal model. The sheet's bias tempco,
    where printed, is the cavity coefficient k_c of :class:`~gyrobench.sim.rlg.ThermalBias`
    (the bias k_c (T2 - T_ref) once the cavity has followed the chamber), the other
    mechanisms 0, T_ref the cavity's steady state in a 25 degC chamber (25 degC + H_1 + H_2, the
    housing and discharge heating of :class:`~gyrobench.sim.rlg.TwoNodeThermal`): the sheet's
    coefficient is per kelvin of the ambient. No RLG sheet read prints one; the part then carries the one sized set of
    RLG thermal mechanisms in the project, :data:`~gyrobench.sim.rlg.THERMAL_BIAS_CALIBRATED`
    (CALIBRATED to paper 004's device, an ASSUMED design as the FOG's default coil is). A
    shaker run twists the block on its dither flexure (:mod:`gyrobench.sim.rlg_vibration`,
    the default ASSUMED :class:`~gyrobench.sim.rlg_vibration.DitherMount`; docs/physics.md
    6.7): the unstripped part is the term ``dither_mount_vibration``. The sheet's
    g-sensitivity is added as for the FOG.

After the device model, the sheet's output stage: its output filter at the output rate (the
model's record runs at ``fs``; a bandwidth at or above 0.45 fs is not applied and the metadata
says so), saturation at its range and rounding to its resolution, each a truth term, so the
record's terms still sum to ``output - true_rate`` (``output_quantization`` where the model has
its own ``quantization``, the RLG's count quantization). The MEMS slow flow does not split its
output into terms: its thermal terms come from the closed forms (above) and the rest of its error
is the one term ``resonator``. Every rad/s truth channel is one of the terms (the models' sub-terms
and intermediate rates are not kept); the models' inputs and states (temperatures, specific
force) stay in the truth, their logged channels beside ``output``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.io.recording import Channel, Recording
from gyrobench.sim.coil2d import Coil2D
from gyrobench.sim.fog2d import FOG2DSpec, coil_diameter_tempco
from gyrobench.sim.mems_population import MemsResonatorSpec
from gyrobench.sim.mems_resonator import MemsResonator, g_sensitivity, low_rate_scale_factor, zero_rate_output
from gyrobench.sim.parts._part import Datasheet, Part, PartUnit, filter_metadata, output_filter, settled_filter
from gyrobench.sim.parts._physics import fog_spec, mems_spec, physics_summary, rlg_spec
from gyrobench.sim.rlg import THERMAL_BIAS_CALIBRATED, RLGSpec, ThermalBias
from gyrobench.sim.sensor import Environment

__all__ = ["MODELS", "draw_unit", "physics_spec", "simulate_part", "simulate_unit"]

MODELS = ("physics", "budget")
"""The models a part runs on: its technology's physics model (default) or the datasheet budget."""

_DT = 1.0  # K, half-step of the central differences of the MEMS tempco solve


def _central(f, t0: float) -> float:
    return (f(t0 + _DT) - f(t0 - _DT)) / (2.0 * _DT)


def _secant(g, x0: float, x1: float, target: float) -> float:
    """x with g(x) = target (g linear or nearly so in x), a few secant steps to 1e-3 relative."""
    g0, g1 = g(x0) - target, g(x1) - target
    for _ in range(8):
        if g1 == g0:
            break
        x0, x1 = x1, x1 - g1 * (x1 - x0) / (g1 - g0)
        g0, g1 = g1, g(x1) - target
        if abs(g1) <= 1e-3 * abs(target):
            return x1
    if abs(g1) > 1e-3 * abs(target):
        raise ValueError(f"the tempco solve did not reach its target {target!r} (residual {g1!r})")
    return x1


def _mems_mapped(datasheet: Datasheet) -> MemsResonatorSpec:
    spec = mems_spec(datasheet)
    unit: MemsResonator = spec.nominal
    t0 = unit.reference_temperature
    if datasheet.g_sensitivity:
        # g_s = SF tan(theta) (dk_yx/df)/(2 m w): linear in tan(theta) at the default plates
        target_g = units.deg_per_h(datasheet.g_sensitivity) / units.G0
        probe = 0.01
        g1 = g_sensitivity(replace(unit, phase_error=probe))  # signed: theta0 takes the sign giving +g_s
        if not abs(g1) > 0.0:
            raise ValueError(f"{datasheet.name!r}: the resonator has no g-sensitive term to map the sheet's onto")
        theta = math.atan(math.tan(probe) * target_g / g1)
        if not abs(theta) < 0.5:
            raise ValueError(f"{datasheet.name!r}: g-sensitivity {datasheet.g_sensitivity!r} deg/h/g needs a phase "
                             f"error {theta!r} rad, beyond 0.5 rad")
        unit = replace(unit, phase_error=theta)
    if datasheet.scale_factor_tempco:
        target_sf = datasheet.scale_factor_tempco * 1e-6
        sf0 = low_rate_scale_factor(unit, t0)

        def sf_slope(a_g: float) -> float:
            u = replace(unit, gain_tc=a_g)
            return _central(lambda t: low_rate_scale_factor(u, t), t0) / sf0

        unit = replace(unit, gain_tc=_secant(sf_slope, unit.gain_tc, unit.gain_tc - 1e-4, target_sf))
    if datasheet.bias_tempco:
        target = units.deg_per_h(datasheet.bias_tempco)

        def bias_slope(eps_c: float) -> float:
            u = replace(unit, damping_coupling=eps_c)
            return _central(lambda t: zero_rate_output(u, t), t0)

        unit = replace(unit, damping_coupling=_secant(bias_slope, 1e-4, 2e-4, target))
    return replace(spec, nominal=unit)


def _mems_thermal(unit: MemsResonator, temp: NDArray[np.float64],
                  omega: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """The resonator's bias and scale-factor change from T0 along the record's temperature (module docstring)."""
    t0 = unit.reference_temperature
    lo, hi = float(np.min(temp)), float(np.max(temp))
    if hi - lo < 1e-9 and abs(lo - t0) < 1e-9:
        return {"bias_temperature": np.zeros_like(omega), "scale_factor_temperature": np.zeros_like(omega)}
    grid = np.linspace(lo, hi, 33) if hi > lo else np.array([lo])
    b0, sf0 = zero_rate_output(unit, t0), low_rate_scale_factor(unit, t0)
    bias = np.array([zero_rate_output(unit, t) - b0 for t in grid])
    sf = np.array([low_rate_scale_factor(unit, t) / sf0 - 1.0 for t in grid])
    if len(grid) == 1:
        return {"bias_temperature": np.full_like(omega, bias[0]), "scale_factor_temperature": sf[0] * omega}
    return {"bias_temperature": np.interp(temp, grid, bias),
            "scale_factor_temperature": np.interp(temp, grid, sf) * omega}


def physics_spec(datasheet: Datasheet) -> FOG2DSpec | MemsResonatorSpec | RLGSpec:
    """The part's physics model with the sheet's noise, temperature and acceleration figures mapped (module docstring).

    Parameters
    ----------
    datasheet : Datasheet
        The part's datasheet.

    Returns
    -------
    FOG2DSpec, MemsResonatorSpec or RLGSpec
        The technology's model.

    Raises
    ------
    ValueError
        The sheet cannot be mapped (its ARW beyond the model's physical ranges, or a tempco the
        model's parameter cannot reach).
    """
    if not isinstance(datasheet, Datasheet):
        raise TypeError(f"datasheet must be a Datasheet; got {type(datasheet).__name__}")
    if datasheet.technology == "MEMS":
        return _mems_mapped(datasheet)
    if datasheet.technology == "FOG":
        fog = fog_spec(datasheet)
        if datasheet.scale_factor_tempco:
            alpha_d = coil_diameter_tempco(Coil2D(spec=fog.coil))
            fog = replace(fog, wavelength_tempco=2.0 * alpha_d - datasheet.scale_factor_tempco * 1e-6)
        return fog
    rlg = rlg_spec(datasheet)
    if datasheet.bias_tempco:
        # referred to the cavity's steady state in a 25 degC chamber (the housing and discharge heating
        # H_1 + H_2 above it): a powered unit at 25 degC has no thermal bias, and k_c dT once settled
        th = rlg.thermal
        thermal = ThermalBias(cavity=units.deg_per_h(datasheet.bias_tempco),
                              reference_temperature=units.celsius(25.0) + th.heating_housing + th.heating_cavity)
    else:
        thermal = THERMAL_BIAS_CALIBRATED
    return replace(rlg, thermal_bias=thermal, mechanism_spread=0.0)


def _mapping_note(datasheet: Datasheet) -> str:
    if datasheet.technology == "RLG" and not datasheet.bias_tempco:
        return "thermal mechanisms: THERMAL_BIAS_CALIBRATED (no bias tempco on the sheet; an ASSUMED design)"
    if datasheet.technology == "FOG":
        return "thermal drift and scale factor from the coil's (r, z) heat flow and materials"
    mapped = [k for k in ("bias_tempco", "scale_factor_tempco", "g_sensitivity") if getattr(datasheet, k)]
    return "mapped onto the model: " + (", ".join(mapped) if mapped else "none (the default design's tempcos)")


def simulate_part(part: Part, environment: Environment, *, fs: float, rng: np.random.Generator,
                  model: str = "physics") -> Recording:
    """One record of ``part`` in ``environment`` at ``fs`` [Hz] on its physics model or its datasheet budget.

    Parameters
    ----------
    part : Part
    environment : Environment
    fs : float
        Output rate [Hz].
    rng : numpy.random.Generator
        The unit's draw and the record's streams.
    model : {"physics", "budget"}
        "physics" (default): :func:`physics_spec` realised and simulated, then the sheet's output
        stage (module docstring); "budget": :meth:`Part.simulate`.

    Returns
    -------
    Recording
        Channel ``output`` [rad/s] (and the model's logged channels), truth ``true_rate`` and the
        terms named in the metadata's ``error_components``; metadata ``model_kind`` says which
        model ran.
    """
    if not isinstance(part, Part):
        raise TypeError(f"part must be a Part; got {type(part).__name__}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    if model == "budget":
        return part.simulate(environment, fs=fs, rng=rng)
    ds = part.datasheet
    spec = physics_spec(ds)
    r_unit, r_rec = rng.spawn(2)
    unit = spec.realize(rng=r_unit)
    rec = unit.simulate(environment, fs=fs, rng=r_rec)
    return _device_record(part, rec, environment, fs, unit)


def _device_record(part: Part, rec: Recording, environment: Environment, fs: float, unit: object) -> Recording:
    """The physics record as a device record: the sheet's terms and output stage added, the terms closing."""
    ds = part.datasheet
    n = rec.n_samples
    out = np.asarray(rec["output"], dtype=float)
    omega = np.asarray(rec["truth/true_rate"], dtype=float)
    names = list(rec.metadata.get("error_components") or [])
    comps: dict[str, NDArray[np.float64]] = {k: np.asarray(rec.truth[k].data, dtype=float) for k in names}
    descr = {k: rec.truth[k].description for k in names}
    ignored = list(rec.metadata.get("ignored_inputs") or [])
    sheet_terms: list[str] = []
    if ds.technology != "MEMS" and ds.g_sensitivity:
        force = environment.sampled("specific_force", fs)[:n]
        comps["g_sensitivity"] = units.deg_per_h(ds.g_sensitivity) / units.G0 * force
        descr["g_sensitivity"] = "the sheet's g-sensitivity x specific force (the model has no g term)"
        sheet_terms.append("g_sensitivity")
        ignored = [k for k in ignored if k != "specific_force"]
        out = out + comps["g_sensitivity"]
    if isinstance(unit, MemsResonator) and "deterministic_error" in comps:  # its thermal terms, closed forms
        temp = np.asarray(rec["inputs/temperature"], dtype=float)
        thermal = _mems_thermal(unit, temp, omega)
        det = comps.pop("deterministic_error")
        comps = {**thermal, "resonator": det - sum(thermal.values(), np.zeros(n)), **comps}
        descr.update(bias_temperature="the resonator's bias change from T0 (noise-free closed form)",
                     scale_factor_temperature="the resonator's scale-factor change from T0 x true rate",
                     resonator="the rest of the resonator's noise-free error (trim residue, nonlinearity, "
                               "dynamics, ADC)")
    stage: dict[str, Any] = filter_metadata(ds, fs)
    if ds.bandwidth is not None and ds.bandwidth < 0.45 * fs:
        sos = output_filter(ds, fs)
        comps = {k: settled_filter(sos, v) for k, v in comps.items()}
        comps["bandwidth"] = settled_filter(sos, omega) - omega
        stage.update(internal_rate_hz=fs, oversampling=1)
    else:
        comps["bandwidth"] = np.zeros(n)
        if ds.bandwidth is not None:
            stage = {"applied": False, "why": f"the sheet's bandwidth {ds.bandwidth:g} Hz is not below 0.45 fs "
                                              f"({0.45 * fs:g} Hz): the model's own dynamics only"}
    descr["bandwidth"] = "the output filter's effect on the true rate (filtered - true)"
    raw = omega + sum(comps.values(), np.zeros(n))
    clipped = raw if ds.range_dps is None else np.clip(raw, -math.radians(ds.range_dps), math.radians(ds.range_dps))
    q = math.radians(ds.resolution) if ds.resolution else 0.0
    final = np.round(clipped / q) * q if q else clipped
    for key, term, what in (("saturation", clipped - raw, "clipping at the sheet's +-range"),
                            ("quantization", final - clipped, "rounding to the sheet's resolution")):
        key = key if key not in comps else f"output_{key}"  # the RLG's own count quantization keeps its name
        comps[key], descr[key] = term, what
    channels = {"output": Channel(final, "rad/s", f"{ds.manufacturer} {ds.model} output ({rec.metadata['model']})")}
    channels.update({k: c for k, c in rec.channels.items() if k not in ("output", "rate")})
    truth = {"true_rate": Channel(omega, "rad/s", "input rate about the sense axis (with the Earth's, as the "
                                                   "model adds it)")}
    truth.update({k: Channel(v, "rad/s", descr[k]) for k, v in comps.items()})
    # the model's inputs and states (K, m/s^2, counts) stay under inputs/; its rad/s sub-terms and
    # intermediate rates (the FOG's shupe and txdt_product inside nonreciprocal, the table and Earth
    # rates inside true_rate) do not: every rad/s truth channel is one of the terms that close the record
    inputs = dict(rec.inputs)
    meta = {
        **rec.metadata,
        "model_kind": "physics",
        "device_model": rec.metadata.get("model"),
        "model": f"gyrobench.sim.parts.simulate_part (physics: {rec.metadata.get('model')})",
        "part": ds.name,
        "datasheet": ds.figures(),
        "physics_mapping": f"{physics_summary(ds)}; {_mapping_note(ds)}",
        "sheet_terms": sheet_terms,
        "output_filter": stage,
        "error_components": list(comps),
        "ignored_inputs": ignored,
    }
    return Recording(fs=rec.fs, channels=channels, truth=truth, inputs=inputs, t0=rec.t0, metadata=meta,
                     name=ds.name.replace("/", "_"))


def draw_unit(part: Part, *, rng: np.random.Generator, model: str = "physics") -> object:
    """One unit of ``part`` on ``model``, drawn once so several records share it (a calibration and a test).

    Parameters
    ----------
    part : Part
    rng : numpy.random.Generator
        The unit's draw (its turn-on bias, scale-factor error, the physics model's build spread).
    model : {"physics", "budget"}
        As in :func:`simulate_part`.

    Returns
    -------
    object
        A :class:`~gyrobench.sim.parts.PartUnit` (budget) or the physics model's unit; pass it to
        :func:`simulate_unit`.
    """
    if not isinstance(part, Part):
        raise TypeError(f"part must be a Part; got {type(part).__name__}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}; got {model!r}")
    return part.realize(rng=rng) if model == "budget" else physics_spec(part.datasheet).realize(rng=rng)


def simulate_unit(part: Part, unit: object, environment: Environment, *, fs: float,
                  rng: np.random.Generator) -> Recording:
    """One record of a unit :func:`draw_unit` drew, in ``environment`` at ``fs`` [Hz].

    The same record :func:`simulate_part` writes for that unit (the sheet's output stage on the
    physics model, the terms closing), with ``rng`` the record's own streams.

    Parameters
    ----------
    part : Part
        The part the unit was drawn from.
    unit : object
        From :func:`draw_unit`.
    environment : Environment
    fs : float
        Output rate [Hz].
    rng : numpy.random.Generator
        The record's noise streams.

    Returns
    -------
    Recording
        As :func:`simulate_part`'s.
    """
    if isinstance(unit, PartUnit):
        return unit.simulate(environment, fs=fs, rng=rng)
    simulate = getattr(unit, "simulate", None)
    if not callable(simulate):
        raise TypeError(f"unit must come from draw_unit; got {type(unit).__name__}")
    return _device_record(part, simulate(environment, fs=fs, rng=rng), environment, fs, unit)
