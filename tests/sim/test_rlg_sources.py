"""Each cavity-RLG mechanism coefficient pinned to the value its source prints, in the source's units.

Sources (printed values, not derived):

* Aronowitz & Lim, Opt. Eng. 18(4) 376 (1979), abstract: Langmuir-flow null shift "0.0066
  deg/hr/mamp of unbalance" of the two discharge legs' currents, and "4.4 deg/hr/cm/sec of
  velocity unbalance".
* SCHOTT, "Technical Details of ZERODUR": expansion class 2, |alpha(0..50 degC)| <= 0.10e-6 /K.

No primary source with a printed number was found (searched: backscatter null shift per unit
lock-in, gas-temperature and block-gradient null shift, discharge-current regulation against
temperature) for the backscatter null-shift ratio eta, the gas temperature rise, the sense-resistor
TCR mismatch, the mount asymmetry or the leg imbalance at turn-on: those are family parameters
with stated ranges (:data:`gyrobench.sim.rlg_cavity.CAVITY_RLG_FAMILY`; eta identified for paper
004 in :mod:`gyrobench.scenarios.papers.p004_rlg_thermal.identify`).
"""

import pytest

from gyrobench.base import units
from gyrobench.sim import rlg_cavity as rc

#: 1 deg/h in rad/s, from the definition (pi/180 rad per 3600 s), not from gyrobench.sim.units
_DEG_H = 3.141592653589793 / 180.0 / 3600.0


def test_langmuir_coefficient_is_aronowitz_lim_per_milliampere():
    per_ma = rc.LANGMUIR_COEFFICIENT_PRINTED * 1e-3 / _DEG_H  # rad/s per A -> deg/h per mA
    assert per_ma == pytest.approx(0.0066, rel=1e-12)


def test_langmuir_velocity_sensitivity_is_aronowitz_lim_per_cm_s():
    per_cm_s = rc.LANGMUIR_VELOCITY_SENSITIVITY * 1e-2 / _DEG_H  # rad/s per (m/s) -> deg/h per (cm/s)
    assert per_cm_s == pytest.approx(4.4, rel=1e-12)


def test_zerodur_class_2_bound_is_schott_value():
    assert rc.ZERODUR_CTE_CLASS_2 == pytest.approx(0.10e-6, rel=1e-12)  # 1/K


def test_units_deg_per_h_agrees_with_the_definition():
    assert units.deg_per_h(1.0) == pytest.approx(_DEG_H, rel=1e-12)


def test_cavity_default_langmuir_coefficient_is_the_printed_value_in_deg_h_per_ma():
    """The model's default k_LF (Discharge, CavityRLGSpec) is 0.0066 deg/h per mA of leg imbalance."""
    for k in (rc.LANGMUIR_COEFFICIENT, rc.Discharge().coefficient, rc.CavityRLGSpec().discharge.coefficient):
        assert k * 1e-3 / _DEG_H == pytest.approx(0.0066, rel=1e-12)  # rad/s per A -> deg/h per mA


def test_unsourced_cavity_sizes_are_family_ranges_and_the_default_leaves_the_null_shift_off():
    fam = rc.CAVITY_RLG_FAMILY
    spec = rc.CavityRLGSpec()
    assert spec.dissipative == 0.0
    assert fam.dissipative.contains(1.26e-3)  # paper 004's identified eta lies in the family
    for name in ("mount_asymmetry", "tcr_mismatch_std", "imbalance_repeatability", "walk_phase_std"):
        assert getattr(fam, name).contains(getattr(spec, name)), name
    assert fam.gas_rise.contains(spec.discharge.gas_rise)
