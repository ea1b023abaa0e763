"""allan_figure: the model only over the fitted taus, each asymptote labelled with what it plots (issue 30 item 6)."""

from __future__ import annotations

import re

import numpy as np

from gyrobench.analysis.allan import allan_deviation, fit_noise
from gyrobench.base import units
from gyrobench.scenarios.reports.figures import allan_figure


def _figure():
    rng = np.random.default_rng(49)
    y = 1e-3 * rng.standard_normal(200_000) + np.cumsum(1e-6 * rng.standard_normal(200_000))  # N and K, rad/s
    c = allan_deviation(y, 100.0)
    fit = fit_noise(c, tau_min=0.08, tau_max=200.0)
    return c, fit, allan_figure(c, fit, title="t")


def test_model_is_solid_over_the_fitted_taus_and_dashed_beyond():
    c, fit, fig = _figure()
    ax = fig.axes[0]
    t_lo, t_hi = fit.tau_used[0], fit.tau_used[-1]
    assert t_lo > c.tau[0] and t_hi < c.tau[-1]  # taus left out on both sides
    solid = [ln for ln in ax.get_lines() if ln.get_label().startswith("fitted model")]
    assert len(solid) == 1
    x = solid[0].get_xdata()
    assert x.min() == t_lo and x.max() == t_hi
    dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--" and ln.get_color() == solid[0].get_color()]
    assert len(dashed) == 2
    assert min(ln.get_xdata().min() for ln in dashed) < t_lo and max(ln.get_xdata().max() for ln in dashed) > t_hi
    assert all(ln.get_xdata().max() <= t_lo or ln.get_xdata().min() >= t_hi for ln in dashed)


def test_each_term_line_is_what_its_label_says():
    """A term's label ends with 'line F X tau^h': its line must be F times the coefficient X times
    tau^h (ADEV, in the plot's deg/h), so e.g. the bias-instability line says 0.664 B. The labels'
    3-significant-digit factors against the drawn lines, at every plotted tau: within 0.5 % (the rounding)."""
    _, fit, fig = _figure()
    ax = fig.axes[0]
    k = float(units.to_deg_per_h(1.0))
    seen = set()
    for ln in ax.get_lines():
        m = re.match(r"([QNBKR]) ([=<]) .*; line (?:([0-9.]+) )?[QNBKR](?: tau\^([-0-9.]+))?$", ln.get_label())
        if not m:
            continue
        name, rel, fac, half = m.group(1), m.group(2), float(m.group(3) or 1.0), float(m.group(4) or 0.0)
        coef = fit.coefficients[name]
        x = coef.value if rel == "=" else coef.upper_bound
        tau, y = np.asarray(ln.get_xdata()), np.asarray(ln.get_ydata())
        np.testing.assert_allclose(y / k, fac * x * tau**half, rtol=5e-3)
        seen.add(name)
    assert seen == set(fit.coefficients), seen
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert any(lab.startswith("B ") and lab.endswith("line 0.664 B") for lab in labels), labels
