"""Re-measure the effects quoted in paper 001's :data:`~.claims.DEVIATIONS` (slow; not run by the report)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from gyrobench.scenarios.claims import finite_median

from .config import METHOD_LABELS, Config
from .experiment import experiment
from .results import UnitResult

__all__ = ["control_config", "deviation_effects", "variant_config", "variants"]


def variants(config: Config) -> dict[str, Config]:
    """The configurations :func:`deviation_effects` compares (name -> Config).

    Parameters
    ----------
    config : Config
        The base configuration.

    Returns
    -------
    dict of str to Config
        Name -> configuration.
    """
    nom = config.gyro.nominal
    return {
        "default": config,
        "design": replace(config, variant="design"),
        "calibrated": replace(config, variant="calibrated"),
        "fit_runs_5": replace(config, n_fit_runs=5),
        "sf_repeatability_0": replace(
            config,
            gyro=replace(config.gyro, nominal=replace(nom, scale_factor_repeatability=0.0)),
        ),
        "piecewise_alpha_0": replace(config, piecewise_alpha=0.0),
        "join_centred_0.05": replace(config, join="centred", join_width=0.05),
        "join_centred_0.02": replace(config, join="centred", join_width=0.02),
        "mlp_epochs_200": replace(config, mlp_epochs=200),
        "average_120s": replace(config, average_s=120.0),
    }


def variant_config(config: Config, name: str) -> Config:
    """The config variant ``name`` of :func:`variants` (a ``Deviation.variant``: the paper's protocol).

    Parameters
    ----------
    config : Config
        The configuration.
    name : str
        A key of :func:`variants`.

    Returns
    -------
    Config
        The variant's configuration.
    """
    table = variants(config)
    if name not in table:
        raise ValueError(f"variant_config name must be one of {sorted(table)}; got {name!r}")
    return table[name]


def control_config(config: Config) -> Config:
    """The control population: the same units with a linear scale factor.

    The control population: the same units with a linear scale factor (no read-out
    compression, the resonator design's force rebalance, linear through the table).

    Parameters
    ----------
    config : Config
        The configuration.

    Returns
    -------
    Config
        No read-out compression, the design's force rebalance, linear through the table.
    """
    return replace(config, variant="design")


def _effect_row(us: Sequence[UnitResult]) -> dict[str, float]:
    """Medians over units of the numbers the DEVIATIONS quote."""

    def med(f: Callable[[UnitResult], float]) -> float:
        return finite_median(f(u) for u in us)

    row: dict[str, float] = {}
    for k in METHOD_LABELS:
        for what in ("kn_fit_pct", "kn_heldout_pct", "kn_dense_pct"):
            row[f"{what}.{k}"] = finite_median(getattr(u.methods[k], what) for u in us)
    for k in METHOD_LABELS:
        row[f"eval_ms.{k}"] = finite_median(u.timing_ms[k] for u in us)
    row["raw_kn_pct"] = med(lambda u: u.raw.raw_kn_pct)
    row["floor_pct"] = med(lambda u: u.floor_pct)
    row["units_in_paper_order"] = float(sum(u.quantities["order_as_paper"] or 0.0 for u in us))
    row["units_with_a_breakpoint"] = float(sum(bool(u.raw.breakpoints_dps) for u in us))
    row["units_split_at_1800"] = float(sum(u.quantities["breakpoints_at_1800"] or 0.0 for u in us))
    return row


def deviation_effects(
    config: Config | None = None,
    seeds: Sequence[int] = tuple(range(20)),
    names: Sequence[str] | None = None,
) -> dict[str, dict[str, float]]:
    """Re-measure the effects quoted in ``DEVIATIONS`` (slow: one experiment per variant/seed).

    For each configuration of :func:`variants` (or those in ``names``): the median over
    ``seeds`` of each method's in-sample, held-out and dense-sweep K_n [%], the raw K_n, the
    repeatability floor [%], the evaluation times [ms], and counts of units in the paper's
    order, with any breakpoint, split at +-1800. The quoted numbers were measured with
    ``deviation_effects()`` (seeds 0-19).

    Parameters
    ----------
    config : Config or None
        The base configuration (None: the default).
    seeds : sequence of int
        The units.
    names : sequence of str or None
        The variants measured (None: all of :func:`variants`).

    Returns
    -------
    dict of str to dict of str to float
        Variant -> measured figure -> median.
    """
    base = Config() if config is None else config
    configs = variants(base)
    keep = list(configs) if names is None else list(names)
    return {n: _effect_row([experiment(configs[n], s) for s in seeds]) for n in keep}
