"""The limits a Monte Carlo yield is judged against travel with the result and its figures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.report.tolerancing_display import display_montecarlo
from camtol.tolerancing import monte_carlo
from camtol.tolerancing.montecarlo import prepare

CW06 = load_example("cw06-translating")
STEP = 1.0


@pytest.mark.parametrize("mode, samples", [("linear", 2000), ("exact", 8)])
def test_spec_limits_are_plus_minus_spec_in_the_display_unit(mode: str, samples: int) -> None:
    r = monte_carlo(CW06, samples, mode=mode, spec=0.012, step_deg=STEP)  # type: ignore[arg-type]
    assert r.limits is not None
    lower, upper = r.limits
    assert lower.shape == upper.shape == r.theta_deg.shape
    np.testing.assert_array_equal(upper, 0.012)  # internal unit: mm
    np.testing.assert_array_equal(lower, -0.012)
    shown = display_montecarlo(r, CW06).limits
    assert shown is not None
    np.testing.assert_array_equal(shown[1], 12.0)  # µm: 0.012 mm shown in the display unit
    np.testing.assert_array_equal(shown[0], -12.0)


def test_band_limits_follow_the_band_and_none_without_a_spec() -> None:
    n = prepare(CW06, step_deg=STEP).theta_rad.size
    theta = np.linspace(0.0, 2.0 * np.pi, n)
    band = (-0.01 - 0.002 * np.cos(theta), 0.015 + 0.003 * np.sin(theta))
    r = monte_carlo(CW06, 2000, band=band, step_deg=STEP)
    shown = display_montecarlo(r, CW06).limits
    assert r.limits is not None and shown is not None
    np.testing.assert_array_equal(r.limits[0], band[0])  # internal unit: mm
    np.testing.assert_allclose(shown[0], band[0] * 1e3, rtol=1e-15)  # µm
    np.testing.assert_allclose(shown[1], band[1] * 1e3, rtol=1e-15)
    assert monte_carlo(CW06, 100, step_deg=STEP).limits is None


def test_plot_and_report_draw_the_limits(tmp_path: Path) -> None:
    """The CLI figure and the HTML report section show the spec lines (legend entry)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from camtol.report.tolerancing import draw_limits, montecarlo_section

    r = monte_carlo(CW06, 2000, spec=0.012, step_deg=STEP)
    fig = Figure()
    ax = fig.add_subplot()
    draw_limits(ax, display_montecarlo(r, CW06))
    labels = [line.get_label() for line in ax.get_lines()]
    assert "spec limits" in labels
    assert any(np.allclose(line.get_ydata(), 12.0) for line in ax.get_lines())
    assert "spec limits" in montecarlo_section(r, CW06)  # the SVG keeps legend text
    png = tmp_path / "mc.png"
    argv = ["montecarlo", "-e", "cw06-translating", "--samples", "2000", "--step", "1"]
    assert main([*argv, "--spec-um", "12", "--plot", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
