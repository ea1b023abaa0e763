"""Paper 000's control population and its deviations' config variants.

:func:`control_config` is the same experiment with the paper's effect switched off: the shaker
controller still switches on and off and logs its drive frequency (so every step of the
analysis runs, compensation included), but the table does not move (0 g). A method claim that
holds there about as often as on the vibrated units is a property of the analysis, not a
finding (:attr:`gyrobench.scenarios.claims.ClaimResult.identity`).

:func:`variant_config` builds the configuration a :class:`~gyrobench.scenarios.claims.Deviation`
names in its ``variant``: the paper's protocol (or another reading of it) in place of ours, so
that ``gyrobench reproduce --deviations`` measures each deviation's effect on every claim.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from .config import Config

__all__ = ["VARIANTS", "control_config", "variant_config"]

#: 1e-4 (deg/s)^2 in (deg/h)^2: the RBF goal read in the unit of a deg/s output
_GOAL_DEG_S_IN_DEG_H2 = 1e-4 * 3600.0**2


def control_config(config: Config) -> Config:
    """The same units with no vibration: ``acceleration_g = 0`` (everything else unchanged).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    Config
        ``config`` with ``acceleration_g = 0``.
    """
    return replace(config, acceleration_g=0.0)


#: variant name -> what it changes in the configuration (see :data:`~.claims.DEVIATIONS`)
VARIANTS: dict[str, Callable[[Config], Config]] = {
    "static_200s": lambda c: replace(c, static_before_s=200.0, static_after_s=200.0),
    "rbf_centres_ols": lambda c: replace(c, rbf_centres="ols"),
    "train_a6": lambda c: replace(c, train_level=6),
    "fit_full_tau": lambda c: replace(c, split_fit_range=False),
    "n_full_tau": lambda c: replace(c, n_tone_free=False),
    "guard_1s": lambda c: replace(c, guard_s=1.0, edge_window_s=0.5),
    "azimuth_east": lambda c: replace(c, fog=replace(c.fog, azimuth_deg=90.0)),
    "acceleration_1g": lambda c: replace(c, acceleration_g=1.0),
    "rbf_goal_deg_s": lambda c: replace(c, rbf_goal_deg_h2=_GOAL_DEG_S_IN_DEG_H2),
    "mixed_grade_budget": lambda c: replace(
        c, fog=replace(c.fog, Q_arcsec=0.1, B_deg_h=0.2, K_deg_h_sqrt_h=0.05, R_deg_h2=0.01)
    ),
    "no_mount": lambda c: replace(c, fog=replace(c.fog, mount=None)),
}


def variant_config(config: Config, name: str) -> Config:
    """``config`` with the deviation variant ``name`` applied (one of :data:`VARIANTS`).

    Parameters
    ----------
    config : Config
        The configuration.
    name : str
        A key of :data:`VARIANTS`.

    Returns
    -------
    Config
        The variant's configuration.
    """
    if name not in VARIANTS:
        raise ValueError(f"variant must be one of {sorted(VARIANTS)}; got {name!r}")
    return VARIANTS[name](config)
