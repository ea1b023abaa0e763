"""Optical noise budget of an interferometric FOG: shot, excess RIN, detector/preamp thermal noise.

All parameters in SI. Currents [A], one-sided current PSDs [A^2/Hz], phase PSDs [rad^2/Hz].

Detector current at phase difference phi: i(phi) = (i0/2)(1 + cos phi), i0 = R P_det,
P_det = P_source 10^(-loss_dB/10). With square-wave bias modulation of depth phi_b the
detector sits at i_b = i0 (1 + cos phi_b)/2 = i0 cos^2(phi_b/2) and the demodulated slope is
(i0/2) sin(phi_b). One-sided current noise PSDs at the bias point:

    shot          S_shot = 2 q i_b                                                 [A^2/Hz]
    excess RIN    S_rin  = 2 i_b^2 / dnu_eff, dnu_eff = k_w c dlambda / lambda^2      [A^2/Hz]
                  (x 1/2 for unpolarised light at the detector)
    thermal       S_th   = 4 k_B T / R_f + i_n^2                                    [A^2/Hz]

Divided by the squared slope they give the equivalent phase-noise PSD

    S_phi = 2q/(i0 sin^2(phi_b/2)) + 2 cot^2(phi_b/2)/dnu_eff + S_th/((i0/2)^2 sin^2 phi_b)

and the angle random walk of the closed-loop output (rate = phase / SF; docs/physics.md 1:
N = sqrt(S1/2) for a one-sided rate PSD S1)

    N = sqrt(S_phi / 2) / SF                                                        [rad/sqrt(s)]

RIN of a broadband (thermal-like) source, one-sided: 2/dnu_eff for polarised light, 1/dnu_eff
depolarised (two independent polarisation modes). Derivation: for polarised thermal light the
photocount variance over a time T is <K> + <K>^2 tau_c/T with the coherence time tau_c =
int |gamma(tau)|^2 dtau = 1/dnu_eff (Goodman, Statistical Optics, Wiley 1985, sec. 9.2-9.3,
Mandel's formula; unpolarised light halves the excess term); the variance of the mean current
over T is then q<i>/T + <i>^2/(dnu_eff T), and a white one-sided PSD S1 gives S1/(2T): S_shot =
2 q <i> (Schottky) and S_rin = 2 <i>^2 / dnu_eff. The "RIN = 1/dnu" often quoted for FOGs
(Lefevre, The Fiber-Optic Gyroscope, sec. 5.3.3; Burns, Moeller, Chen, J. Lightwave Technol.
1(1) 98 (1983)) is this with depolarised light or a two-sided PSD; this module used it for
polarised light until issue 26 (ARW x sqrt((2 r + 1)/(r + 1)) = 1.40 at the default RIN/shot
r = 37.5). tests/sim/test_fog_optics_rin.py checks 2/dnu_eff on simulated thermal light.
k_w (``width_factor``) converts
the FWHM to the effective width (int S)^2 / int S^2: 1 for a rectangular spectrum, 1.505 for a
Gaussian (derived: sqrt(pi/(2 ln 2)) * ... = 1.5054). Shot noise: Schottky formula. Thermal:
Johnson noise of the transimpedance feedback resistor plus the amplifier's input current noise.

Constants: elementary charge q and Boltzmann k_B are exact in the 2019 SI (CODATA 2018).
Defaults (the worked example of docs/physics.md 3.8), each with where it comes from:

- Er ASE source 10 mW, 30 nm (rectangular-equivalent): an Er-doped superfluorescent source
  for FOGs gave up to 15 mW from 70 mW of 980 nm pump with RIN < -125 dB/Hz ("Broadband erbium
  source for fiber optic sensor applications"); 30 nm gives lambda^2/(c dlambda) = -125.7 dB/Hz,
  consistent with it.
- 20 dB source-to-detector loss: an ASSUMED budget of a depolarised-source IFOG (source
  coupler twice 6 dB, polariser 3 dB, Y-junction/IOC insertion 4 dB and its 3 dB split, 1 km
  of fibre at 0.5-1 dB, splices and excess ~3 dB); not measured on a unit.
- R = 0.9 A/W: R = eta q lambda/(h c) = 1.25 eta A/W at 1550 nm, i.e. a quantum efficiency of
  0.72; InGaAs PIN diodes reach eta > 0.83 at 1.55 um (Lee et al., Electron. Lett. 20, 196
  (1984)), so this is a conservative front end.
- R_f = 100 kOhm, i_n = 1 pA/sqrt(Hz), 300 K: ASSUMED transimpedance design values; the
  thermal current PSD is 0.2 % of the RIN term at phi_b = pi/2 (docs/physics.md 3.8).

N = 1.32e-3 deg/sqrt(h) at phi_b = pi/2 (RIN dominated; 9.4e-4 with the former 1/dnu_eff).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from numbers import Real
from typing import ClassVar

from gyrobench.base.ranges import FieldRange, validate
from gyrobench.base.units import BOLTZMANN, ELEMENTARY_CHARGE, SPEED_OF_LIGHT  # exact SI, re-exported

__all__ = [
    "ELEMENTARY_CHARGE",
    "BOLTZMANN",
    "SPEED_OF_LIGHT",
    "OpticalBudget",
    "arw_from_phase_psd",
]



def _pos(owner: str, name: str, v: object, unit: str, *, allow_zero: bool = False) -> None:
    if isinstance(v, bool) or not isinstance(v, Real):
        raise TypeError(f"{owner}.{name} must be a real number [{unit}]; got {v!r}")
    x = float(v)
    ok = math.isfinite(x) and (x >= 0 if allow_zero else x > 0)
    if not ok:
        raise ValueError(
            f"{owner}.{name} must be finite and {'>=' if allow_zero else '>'} 0 {unit}; got {v!r}"
        )


def arw_from_phase_psd(phase_psd: float, scale_factor: float) -> float:
    """N = sqrt(S_phi/2)/SF [rad/sqrt(s)] from a one-sided phase PSD [rad^2/Hz] and SF [s]."""
    return math.sqrt(phase_psd / 2.0) / scale_factor


@dataclass(frozen=True, slots=True, kw_only=True)
class OpticalBudget:
    """Source, losses and detector of an IFOG (SI).

    Parameters
    ----------
    source_power : float
        Source output power [W].
    spectral_width : float
        Source spectral FWHM dlambda [m].
    width_factor : float
        k_w: effective (noise) width / FWHM [-]; 1 rectangular, 1.505 Gaussian.
    polarized : bool
        Light at the detector is polarised (after the IFOG's polariser): full RIN;
        False halves the RIN PSD.
    loss_db : float
        Source-to-detector loss [dB] (at zero phase difference).
    responsivity : float
        Detector responsivity R [A/W].
    feedback_resistance : float
        Transimpedance feedback resistor R_f [Ohm].
    amplifier_current_noise : float
        Preamplifier input current noise i_n [A/sqrt(Hz)].
    temperature : float
        Preamplifier temperature [K].
    """

    source_power: float = 10e-3
    spectral_width: float = 30e-9
    width_factor: float = 1.0
    polarized: bool = True
    loss_db: float = 20.0
    responsivity: float = 0.9
    feedback_resistance: float = 1e5
    amplifier_current_noise: float = 1e-12
    temperature: float = 300.0

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "source_power": FieldRange(0, 1e3, "W", "sources are mW; 1 kW admits stress budgets", low_open=True),
        "spectral_width": FieldRange(0, 1e-6, "m", "FWHM of a broadband source: < 1 um", low_open=True),
        "width_factor": FieldRange(0, 10, "1", "noise/FWHM width ratio: 1 rectangular, 1.505 Gaussian", low_open=True),
        "loss_db": FieldRange(0, 100, "dB", "source-to-detector loss; > 100 dB leaves no light"),
        "responsivity": FieldRange(0, 2, "A/W", "photodiode; quantum limit 1.25 A/W at 1550 nm", low_open=True),
        "feedback_resistance": FieldRange(0, 1e12, "Ohm", "transimpedance resistor", low_open=True),
        "amplifier_current_noise": FieldRange(0, 1e-6, "A/sqrt(Hz)", "preamplifier input current noise, >= 0"),
        "temperature": FieldRange(0, 1000, "K", "preamplifier temperature", low_open=True),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above

    @property
    def peak_current(self) -> float:
        """i0 = R P_source 10^(-loss/10): detector current at zero phase difference [A]."""
        return self.responsivity * self.source_power * 10.0 ** (-self.loss_db / 10.0)

    def effective_bandwidth(self, wavelength: float) -> float:
        """dnu_eff = k_w c dlambda / lambda^2 [Hz] at mean wavelength ``wavelength`` [m]."""
        _pos("OpticalBudget", "wavelength", wavelength, "m")
        return self.width_factor * SPEED_OF_LIGHT * self.spectral_width / wavelength**2

    def bias_current(self, bias_phase: float) -> float:
        """i_b = i0 (1 + cos phi_b)/2 [A]."""
        return self.peak_current * (1.0 + math.cos(bias_phase)) / 2.0

    def slope(self, bias_phase: float) -> float:
        """Demodulated slope (i0/2) sin(phi_b) [A/rad]."""
        return self.peak_current / 2.0 * math.sin(bias_phase)

    def current_psd(self, bias_phase: float, wavelength: float) -> dict[str, float]:
        """One-sided current-noise PSDs at the bias point [A^2/Hz]: shot, rin, thermal."""
        _check_bias(bias_phase)
        ib = self.bias_current(bias_phase)
        rin = 2.0 / self.effective_bandwidth(wavelength) * (1.0 if self.polarized else 0.5)
        return {
            "shot": 2.0 * ELEMENTARY_CHARGE * ib,
            "rin": ib**2 * rin,
            "thermal": 4.0 * BOLTZMANN * self.temperature / self.feedback_resistance
            + self.amplifier_current_noise**2,
        }

    def phase_psd(self, bias_phase: float, wavelength: float) -> dict[str, float]:
        """One-sided equivalent phase-noise PSDs [rad^2/Hz] (current PSD / slope^2) and total."""
        s = self.slope(bias_phase) ** 2
        out = {k: v / s for k, v in self.current_psd(bias_phase, wavelength).items()}
        out["total"] = out["shot"] + out["rin"] + out["thermal"]
        return out


def _check_bias(bias_phase: float) -> None:
    if (
        isinstance(bias_phase, bool)
        or not isinstance(bias_phase, Real)
        or not (0.0 < float(bias_phase) < math.pi)
    ):
        raise ValueError(f"bias_phase must be in (0, pi) rad; got {bias_phase!r}")
