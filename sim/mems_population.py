"""The production population of a MEMS gyro design: spreads, the draw of one unit, the factory trim, datasheet mapping.

Equations, units and references: :mod:`gyrobench.sim.mems_resonator` and docs/physics.md 5.1.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from gyrobench.base import units
from gyrobench.base.ranges import FieldRange, validate
from gyrobench.base.validate import check_rng as _check_rng
from gyrobench.base.validate import real_field
from gyrobench.sim.mems_resonator import (
    LIMIT_SIGMAS,
    MemsResonator,
    brownian_arw,
    low_rate_scale_factor,
    operating_point,
    zero_rate_output,
)

__all__ = [
    "MemsResonatorSpec",
    "factory_trim",
]


@dataclass(frozen=True, slots=True, kw_only=True)
class MemsResonatorSpec:
    """A production population: nominal unit plus unit-to-unit spreads (1 sigma).

    Parameters
    ----------
    nominal : MemsResonator
        Nominal design (its own quadrature/damping coupling and phase error are the means).
    mass_spread, frequency_spread, q_spread, gap_spread : float
        Relative 1-sigma spreads [-] of m, f_x, Q (both modes, lognormal) and the rebalance gap
        g (G and F_max go as 1/g^2). Defaults 1 %, 2 %, 10 %, 2 % (assumed production spreads).
    split_spread : float
        1-sigma of the mode split [Hz] (default 30 Hz, assumed).
    quadrature_spread : float
        1-sigma of kappa = k_yx/k_x [-] (default 2e-4: Omega_q ~ 9 rad/s ~ 540 deg/s;
        assumed: an untrimmed quadrature of hundreds of deg/s).
    damping_coupling_spread : float
        1-sigma of eps_c [-] (default 1e-3: Omega_b ~ 1.3 deg/s before trim, assumed).
    phase_error_spread : float
        1-sigma of theta_e [rad] (default 5 mrad, assumed).
    phase_tc_spread : float
        1-sigma of the phase tempco [rad/K] around the nominal (default 1e-5).
    factory_trim : bool
        Trim each drawn unit's scale factor to 1 and bias to 0 at T0 (factory calibration).
    """

    nominal: MemsResonator = field(default_factory=MemsResonator)
    mass_spread: float = 0.01
    frequency_spread: float = 0.02
    split_spread: float = 30.0
    q_spread: float = 0.10
    gap_spread: float = 0.02
    quadrature_spread: float = 2e-4
    damping_coupling_spread: float = 1e-3
    phase_error_spread: float = 5e-3
    phase_tc_spread: float = 1e-5
    factory_trim: bool = True

    RANGES: ClassVar[Mapping[str, FieldRange]] = {
        "mass_spread": FieldRange(0, 0.5, "1", "relative 1-sigma; m (1 + s z) stays > 0 to 2 sigma"),
        "frequency_spread": FieldRange(0, 0.5, "1", "relative 1-sigma; f_x (1 + s z) stays > 0 to 2 sigma"),
        "split_spread": FieldRange(0, 1e4, "Hz", "1-sigma of the mode split"),
        "q_spread": FieldRange(0, 3, "1", "1-sigma of ln Q (lognormal)"),
        "gap_spread": FieldRange(0, 0.5, "1", "relative 1-sigma; g (1 + s z) stays > 0 to 2 sigma"),
        "quadrature_spread": FieldRange(0, 0.1, "1", "1-sigma of k_yx/k_x"),
        "damping_coupling_spread": FieldRange(0, 0.1, "1", "1-sigma of c_yx/c_y"),
        "phase_error_spread": FieldRange(0, 1, "rad", "1-sigma of theta_e (the draw is clipped to +-1.5 rad)"),
        "phase_tc_spread": FieldRange(0, 0.1, "rad/K", "1-sigma of the phase tempco"),
    }

    def __post_init__(self) -> None:
        validate(self)  # the declared specs above; nominal must be a MemsResonator

    def realize(self, *, rng: np.random.Generator) -> MemsResonator:
        """Draw one unit of the population (physical parameters, then the factory trim).

        Nine standard normals are drawn in a fixed order (mass, frequency, split, Q, gap,
        kappa, eps_c, theta, phase tempco), so a spread set to 0 changes no other draw.
        """
        _check_rng(rng)
        z = rng.standard_normal(9)
        n = self.nominal
        theta = n.phase_error + self.phase_error_spread * z[7]
        theta = float(np.clip(theta, -1.5, 1.5))
        q = math.exp(self.q_spread * z[3])
        unit = replace(
            n,
            mass=n.mass * (1.0 + self.mass_spread * z[0]),
            drive_frequency=n.drive_frequency * (1.0 + self.frequency_spread * z[1]),
            mode_split=n.mode_split + self.split_spread * z[2],
            drive_q=n.drive_q * q,
            sense_q=n.sense_q * q,
            electrode_gap=n.electrode_gap * (1.0 + self.gap_spread * z[4]),
            quadrature_coupling=n.quadrature_coupling + self.quadrature_spread * z[5],
            damping_coupling=n.damping_coupling + self.damping_coupling_spread * z[6],
            phase_error=theta,
            phase_tc=n.phase_tc + self.phase_tc_spread * z[8],
        )
        if self.factory_trim:
            unit = factory_trim(unit)
        return unit

    @classmethod
    def from_datasheet(
        cls,
        *,
        range_dps: float = 3600.0,
        range_margin: float = 1.3,
        noise_density_dps_rthz: float = 0.01,
        noise_density_convention: str,
        bias_instability_dph: float = 0.0,
        rate_random_walk_dph_rth: float = 0.0,
        nonlinearity_pct_fs: float = 0.0,
        bias_repeatability_dps: float = 0.0,
        scale_factor_repeatability_ppm: float = 0.0,
        repeatability_convention: str = "1-sigma",
        output_bits: int | None = 20,
        nominal: MemsResonator | None = None,
    ) -> MemsResonatorSpec:
        """A population from datasheet figures (field units); the resonator stays ``nominal``.

        Parameters
        ----------
        range_dps : float
            Measurement range [deg/s]; the output full scale is ``range_dps`` x 10/9
            (headroom) and the DAC limit v_max (open-loop ``nominal``: the pick-off full
            scale Y_fs) is set so the nominal authority is ``range_margin`` x range.
        noise_density_dps_rthz : float
            Rate noise density [deg/s/sqrt(Hz)].
        noise_density_convention : {"one-sided", "two-sided"}
            "two-sided": the IEEE/ADEV-at-1-s value N (white-noise PSD N^2 two-sided);
            "one-sided": sqrt of the one-sided PSD, N = d / sqrt(2). Required (no default:
            datasheets differ). The pick-off noise is set so that sqrt(N_B^2 + N_e^2) = N;
            ValueError if the Brownian floor N_B already exceeds it.
        bias_instability_dph : float
            IEEE 952 bias instability B [deg/h] (electronic 1/f term; a datasheet's ADEV
            minimum is 0.6643 B, :data:`ADEV_MIN_PER_B`).
        rate_random_walk_dph_rth : float
            IEEE 952 rate random walk K [deg/h/sqrt(h)].
        nonlinearity_pct_fs : float
            Scale-factor nonlinearity [% FS] below the knee: sets the output cubic a3 so the
            IEEE K_n of a noise-free 21-point +-range table is this value.
        bias_repeatability_dps, scale_factor_repeatability_ppm : float
            Turn-on bias [deg/s] and scale-factor repeatability [ppm].
        repeatability_convention : {"1-sigma", "limit"}
            "1-sigma": the two figures are standard deviations (a "typical" entry);
            "limit": they are +- / max limits, read as :data:`LIMIT_SIGMAS` sigma.
        output_bits : int or None
            Output word length (default 20, as :class:`MemsResonator`).
        nominal : MemsResonator, optional
            The resonator design (default the module's default design).
        """
        if repeatability_convention not in ("1-sigma", "limit"):
            raise ValueError(
                "repeatability_convention must be '1-sigma' or 'limit'; "
                f"got {repeatability_convention!r}"
            )
        rep_div = LIMIT_SIGMAS if repeatability_convention == "limit" else 1.0
        if noise_density_convention not in ("one-sided", "two-sided"):
            raise ValueError(
                "noise_density_convention must be 'one-sided' or 'two-sided'; "
                f"got {noise_density_convention!r}"
            )
        base = MemsResonator() if nominal is None else nominal
        rng_ = real_field("from_datasheet", "range_dps", range_dps)
        if not rng_ > 0 or not range_margin > 0:
            raise ValueError(
                f"range_dps and range_margin must be > 0; got {range_dps!r}, {range_margin!r}"
            )
        n_tot = units.deg_per_s(noise_density_dps_rthz)
        if noise_density_convention == "one-sided":
            n_tot /= math.sqrt(2.0)
        n_b = brownian_arw(base)
        if not n_tot > n_b:
            raise ValueError(
                f"noise density {noise_density_dps_rthz!r} deg/s/sqrt(Hz) "
                f"({noise_density_convention}) is below the Brownian floor "
                f"{units.to_deg_per_s(n_b):.3g} deg/s/sqrt(Hz) of the design"
            )
        op = operating_point(base)
        x_n = math.sqrt(n_tot**2 - n_b**2) * abs(op.receptance) * op.coriolis_gain
        w_range = units.deg_per_s(rng_)
        out_range = w_range * 10.0 / 9.0
        # v_max (open loop: Y_fs) so the nominal authority (theta = 0, no quadrature) is
        # margin x range
        v_max = range_margin * w_range * op.coriolis_gain / op.gain
        y_fs = range_margin * w_range * op.coriolis_gain * abs(op.receptance)
        # a3: K_n of Omega + a3 Omega^3/R^2 on the 21-point table is |a3| x c(grid)
        grid = np.linspace(-w_range, w_range, 21)
        cub = grid**3 / out_range**2
        c = _lin_residual_max(grid, cub) / w_range  # K_n per unit a3 (to first order in a3)
        a3 = -nonlinearity_pct_fs / 100.0 / c if nonlinearity_pct_fs else 0.0
        nom = replace(
            base,
            pickoff_noise=x_n,
            output_range=out_range,
            output_bits=output_bits,
            dac_full_scale=v_max,
            pickoff_full_scale=y_fs if op.open_loop else base.pickoff_full_scale,
            output_cubic=a3,
            bias_instability=units.deg_per_h(bias_instability_dph),
            rate_random_walk=units.deg_per_h_per_sqrt_h(rate_random_walk_dph_rth),
            bias_repeatability=units.deg_per_s(bias_repeatability_dps) / rep_div,
            scale_factor_repeatability=units.ppm(scale_factor_repeatability_ppm) / rep_div,
        )
        return cls(nominal=nom)


def _lin_residual_max(w: NDArray, f: NDArray) -> float:
    """max |f - LS line(w)| (for the datasheet nonlinearity map; sim does not import analysis)."""
    k, f0 = np.polyfit(w, f, 1)
    return float(np.max(np.abs(f - (k * w + f0))))


def factory_trim(unit: MemsResonator) -> MemsResonator:
    """Trim the unit's scale factor to 1 and its bias to 0 at T0 (noise-free, before turn-on).

    s_trim = 1 / SF_untrimmed(T0), b_trim = the trimmed zero-rate output at T0.

    Parameters
    ----------
    unit : MemsResonator
        A drawn, untrimmed unit.

    Returns
    -------
    MemsResonator
        The unit with ``scale_factor_trim`` and ``bias_trim`` set at T0.
    """
    base = replace(unit, scale_factor_trim=1.0, bias_trim=0.0, turn_on_bias=0.0,
                   turn_on_scale_factor=0.0)
    s = 1.0 / low_rate_scale_factor(base)
    trimmed = replace(base, scale_factor_trim=s)
    b = zero_rate_output(trimmed)
    return replace(unit, scale_factor_trim=s, bias_trim=b)
