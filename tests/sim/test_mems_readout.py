"""sim/mems_readout.py: the open-loop sense chain's pieces, its population and its place in the resonator."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gyrobench.sim import mems_full, mems_population, mems_slow_flow
from gyrobench.sim import mems_resonator as mr
from gyrobench.sim.mems_readout import EPSILON_0, SenseChain, SenseChainSpec, _harmonic


def test_clip_displacement_is_where_the_front_end_reaches_its_rail():
    ch = SenseChain()
    yc = ch.clip_displacement
    assert float(ch.frontend_output(yc)) == pytest.approx(ch.rail, rel=1e-12)
    assert float(ch.frontend_output(0.999 * yc)) < ch.rail
    assert float(ch.frontend_output(1.5 * yc)) == ch.rail


def test_describing_gain_is_one_at_small_amplitude_and_falls_past_the_rail():
    ch = SenseChain()
    yc = ch.clip_displacement
    a = np.linspace(1e-12, 0.9 * ch.gap, 400)
    g = ch.describing_gain(a)
    assert g[0] == pytest.approx(1.0, abs=1e-9)
    past = a > 1.05 * yc
    assert np.all(np.diff(g[past]) < 0)  # compression beyond the rail
    v1 = g * a  # the fundamental (per K_0) grows with the amplitude: the output stays monotone
    assert np.all(np.diff(v1) > 0)


def test_describing_gain_is_the_generic_quadrature_bit_for_bit():
    """The in-place quadrature of the describing gain is the generic Gauss-Legendre harmonic
    (:func:`_harmonic` of ``frontend_output``) value for value, clipped and unclipped amplitudes
    and a drawn unit's chain alike."""
    rng = np.random.default_rng(3)
    for ch in (SenseChain(), SenseChainSpec(k3_spread=0.1).realize(rng=rng)):
        yc = ch.clip_displacement
        a = np.concatenate([[0.0, yc], rng.uniform(0.0, 1.8 * yc, 3000)])
        safe = np.maximum(a, 1e-300)
        tc = np.arccos(np.clip(yc / safe, 0.0, 1.0))
        v1 = ch.rail * (4.0 / math.pi) * np.sin(tc) + _harmonic(ch.frontend_output, safe, tc)
        generic = np.where(a > 0, v1 / (ch.small_signal_gain * safe), 1.0)
        assert ch.describing_gain(a).tobytes() == generic.tobytes()


def test_far_past_the_rail_the_fundamental_tends_to_the_hard_limiters():
    """a >> y_c: V_1 -> (4/pi) V_rail (the square wave's fundamental; Gelb & Vander Velde ch. 2),
    within the share of the cycle spent below the rail, O(y_c/a)."""
    ch = SenseChain()
    a = 0.9 * ch.gap
    v1 = float(ch.describing_gain(a)) * ch.small_signal_gain * a
    assert v1 == pytest.approx(4.0 / math.pi * ch.rail, rel=2.0 * ch.clip_displacement / a)


def test_electrode_softening_matches_its_series_at_small_amplitude():
    """F_e - k_e y = k_e y (2 (y/g)^2 + ...): fundamental 3/4 of the cubic, dk = -(3/2) k_e (a/g)^2."""
    ch = SenseChain()
    a = 0.01 * ch.gap
    assert float(ch.stiffness_change(a)) == pytest.approx(-1.5 * ch.electrostatic_stiffness * (a / ch.gap) ** 2,
                                                          rel=5e-4)
    assert ch.electrostatic_stiffness == pytest.approx(2 * EPSILON_0 * ch.sense_area * ch.sense_bias**2 / ch.gap**3)


def test_out_of_range_and_bad_values_are_refused_in_one_line():
    with pytest.raises(ValueError, match=r"SenseChain.feedback_capacitance must be"):
        SenseChain(feedback_capacitance=1e-18)
    with pytest.raises(ValueError, match=r"sense amplitude must stay below the gap"):
        SenseChain().describing_gain(3e-6)
    with pytest.raises(TypeError, match=r"SenseChainSpec.nominal must be a SenseChain"):
        SenseChainSpec(nominal=1.0)  # type: ignore[arg-type]


def test_pull_in_is_refused():
    ch = SenseChain(sense_bias=30.0, gap=0.5e-6)  # k_e far above the tuned split's stiffness
    op = mr.operating_point(replace(mr.MemsResonator(), readout="open_loop"))
    with pytest.raises(ValueError, match="SenseChain: the sense amplitude"):
        ch.stiffened_envelope(np.array([0.4e-6 + 0j]), op.receptance)


def test_population_draws_are_reproducible_and_spread():
    spec = SenseChainSpec()
    a = spec.realize(rng=np.random.default_rng(1))
    b = spec.realize(rng=np.random.default_rng(1))
    c = spec.realize(rng=np.random.default_rng(2))
    assert a == b and a != c
    assert a.sense_area == spec.nominal.sense_area and a.carrier == spec.nominal.carrier
    flat = replace(spec, gap_spread=0.0, feedback_capacitance_spread=0.0, rail_spread=0.0,
                   sense_bias_spread=0.0, k3_spread=0.0)
    assert flat.realize(rng=np.random.default_rng(1)) == spec.nominal


def test_the_resonator_takes_a_chain_only_open_loop_and_full_integration_refuses_it():
    with pytest.raises(ValueError, match="sense_chain needs readout 'open_loop'"):
        mr.MemsResonator(sense_chain=SenseChain())
    unit = mr.MemsResonator(readout="open_loop", sense_chain=SenseChain())
    with pytest.raises(ValueError, match="simulate_full integrates the linear sense mode"):
        mems_full.simulate_full(unit, 0.0, duration=1e-3, fs=1e3, rng=np.random.default_rng(0))


def test_open_loop_output_goes_through_the_chain():
    """The slow flow's noise-free output equals the static channel through the chain at 3000 deg/s."""
    chain = SenseChain(feedback_capacitance=2e-15)
    unit = mems_population.factory_trim(mr.MemsResonator(readout="open_loop", sense_chain=chain))
    op = mr.operating_point(unit)
    w = math.radians(3000.0)
    res = mems_slow_flow.slow_flow(unit, np.full(50, w), fs=200.0, rng=np.random.default_rng(0), noise=False, adc=False,
                      flicker=False)
    static = mr._output_map(unit, op, mr._static_channels(op, np.array([w]), np.zeros(1)).real)[0]
    assert float(res.output[-1]) == pytest.approx(float(static), rel=1e-9)
    ideal = mems_population.factory_trim(mr.MemsResonator(readout="open_loop"))
    lin = mems_slow_flow.slow_flow(ideal, np.full(50, w), fs=200.0, rng=np.random.default_rng(0), noise=False,
                                   adc=False, flicker=False)
    assert float(res.output[-1]) < 0.95 * float(lin.output[-1])  # the rail bends it


def test_the_softening_closed_form_is_the_first_harmonic_of_the_electrode_force():
    """dk(a) = -(F_e1(a)/a - k_e) with F_e1 the first harmonic of F_e(a cos t), integrated here
    adaptively (scipy.integrate.quad, rtol 1e-13) at 10-99 % of the gap: equal to the
    integration's accuracy (the a -> 0 end, where the quadrature itself cancels, is left out)."""
    from scipy.integrate import quad

    c = SenseChain(k3=0.0)
    for frac in (0.1, 0.5, 0.9, 0.99):
        a = frac * c.gap
        fe1 = 4.0 / math.pi * quad(lambda t, a=a: float(c.electrode_force(a * math.cos(t))) * math.cos(t),
                                   0.0, 0.5 * math.pi, epsabs=0.0, epsrel=1e-13, limit=200)[0]
        assert -float(c.stiffness_change(a)) == pytest.approx(fe1 / a - c.electrostatic_stiffness, rel=1e-11)
