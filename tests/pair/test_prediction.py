"""Δf_est from CW11 eqs. 14-18 beside Δf_mea (issue 12 item 5, the part without a CMM).

Before, given a measurement, the reported Δf_est was the measurement itself (eq. 19 put
back into eq. 18). Now the forward prediction from the known errors of both cams (the
master errors of the ``[inspection]`` table) is reported beside Δf_mea, with the rms of
the difference: the comparison the paper makes (2.75 µm, THEORY §8.4).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.inspection import ErrorFunction
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.variation import conjugate_factors, conjugate_variation


def test_prediction_is_the_forward_variation_of_the_known_errors() -> None:
    d = load_example("cw11-conjugate")
    spec = d.inspection
    assert spec is not None and spec.df_mea is not None
    res = inspect_conjugate(d, step_deg=1.0)
    assert res.predicted is not None and res.estimate is not None
    fac = conjugate_factors(d, res.theta_rad)
    forward = conjugate_variation(fac, spec.master_a, spec.master_b, spec.errors)
    np.testing.assert_allclose(res.predicted.df_est_um, forward.df_est_um, atol=1e-12)
    # the measured side is unchanged: Δf_est of `variation` is still Δf_mea (eq. 19 → 18)
    np.testing.assert_allclose(res.variation.df_est_um, 22.0, atol=1e-12)
    diff = res.df_est_minus_mea_um
    assert diff is not None
    np.testing.assert_allclose(diff, forward.df_est_um - 22.0, atol=1e-12)
    assert "df_est_pred" in res.extremes


def test_a_measurement_equal_to_the_prediction_gives_zero_difference() -> None:
    d = load_example("cw11-conjugate")
    spec = d.inspection
    assert spec is not None
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    forward = conjugate_variation(
        conjugate_factors(d, theta), spec.master_a, spec.master_b, spec.errors
    )
    mea = ErrorFunction.table(np.degrees(theta), forward.df_est_um, name="perfect record")
    res = inspect_conjugate(d, dataclasses.replace(spec, df_mea=mea), step_deg=0.5)
    diff = res.df_est_minus_mea_um
    assert diff is not None
    assert np.max(np.abs(diff)) <= 1e-9  # the same numbers at the same grid points


def test_no_measurement_no_prediction(capsys: pytest.CaptureFixture[str]) -> None:
    d = load_example("cw11-conjugate")
    assert d.inspection is not None
    res = inspect_conjugate(d, dataclasses.replace(d.inspection, df_mea=None), step_deg=1.0)
    assert res.predicted is None and res.df_est_minus_mea_um is None
    assert "df_est_pred" not in res.extremes


def test_cli_reports_the_prediction(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["conjugate", "-e", "cw11-conjugate", "--step", "1", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    res = inspect_conjugate(load_example("cw11-conjugate"), step_deg=1.0)
    diff = res.df_est_minus_mea_um
    assert diff is not None
    pred = data["prediction"]
    assert pred["df_est_minus_mea_rms_um"] == pytest.approx(float(np.sqrt(np.mean(diff**2))))
    assert pred["df_est_minus_mea_max_abs_um"] == pytest.approx(float(np.abs(diff).max()))
    assert "df_est_pred_um" in data["extremes"]
    main(["conjugate", "-e", "cw11-conjugate", "--step", "1"])
    out = " ".join(capsys.readouterr().out.split())
    assert "Δf_est from the known errors of both cams" in out


def test_the_variation_panel_draws_the_prediction() -> None:
    pytest.importorskip("matplotlib")
    from camtol.report.plots import conjugate_variation_plot

    res = inspect_conjugate(load_example("cw11-conjugate"), step_deg=1.0)
    assert res.predicted is not None
    arts = conjugate_variation_plot(res)
    pred = next(a for a in arts if a.get_label().startswith("Δf_est from the known errors"))
    np.testing.assert_allclose(pred.get_ydata(), res.predicted.df_est_um)
