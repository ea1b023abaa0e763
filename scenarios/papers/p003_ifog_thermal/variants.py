"""Paper 003's config variants: the control population and one variant per listed deviation.

:func:`control_config` switches the paper's effect off (no thermal program: the chamber holds
``start_degC`` for every run's duration), so each claim can also be judged where there is
nothing to find (:func:`gyrobench.scenarios.claims.evaluate`). :func:`variant_config` turns a
``Deviation.variant`` name into the config that runs that alternative
(``gyrobench reproduce ifog_thermal --deviations`` measures every claim under it).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from types import MappingProxyType

from .config import Config

__all__ = ["VARIANTS", "control_config", "variant_config"]


def control_config(config: Config) -> Config:
    """The control: ``config`` without its thermal program (constant chamber temperature).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    Config
        ``config`` with ``thermal_program = False``.
    """
    return replace(config, thermal_program=False)


#: variant name -> the change of Config it makes (each is one ``Deviation.variant``)
VARIANTS: Mapping[str, Callable[[Config], Config]] = MappingProxyType(
    {
        # the paper's words: the axis points north (the loop senses the horizontal Earth rate)
        "north_axis": lambda c: replace(c, sense_azimuth_deg=0.0),
        # validation 2 without an input rate (no scale-factor error at the reference)
        "val2_zero_rate": lambda c: replace(c, validation2_true_rate_deg_h=0.0),
        # the net diameter tempco of the earlier FOG2D product form instead of the coil's own
        "sf_tempco_low": lambda c: replace(c, diameter_tempco_ppm_per_K=2.76),
        # the identification record also holds the cool-down from start_degC
        "record_cooldown": lambda c: replace(c, record_cooldown=True),
        # step 5 read as heating and cooling averaged as curves against temperature
        "temperature_curves": lambda c: replace(c, identification_average="temperature_curves"),
        # eq. (19) on the logged samples: no block averaging before training and scoring
        "err_logged_rate": lambda c: replace(c, analysis_block_s=1.0 / c.fs_hz),
        # dT/dt as the central difference of the analysis-rate samples
        "dTdt_central_difference": lambda c: replace(c, derivative_estimator="central_difference"),
    }
)


def variant_config(config: Config, name: str) -> Config:
    """``config`` with the alternative protocol of the deviation whose ``variant`` is ``name``.

    Parameters
    ----------
    config : Config
        The configuration.
    name : str
        A deviation's ``variant``.

    Returns
    -------
    Config
        The variant's configuration.
    """
    if not isinstance(name, str) or name not in VARIANTS:
        raise ValueError(f"variant_config name must be one of {tuple(VARIANTS)}; got {name!r}")
    return VARIANTS[name](config)
