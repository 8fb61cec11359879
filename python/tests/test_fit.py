"""predvs.fit_noise on numpy arrays against `predvs fit-noise` (fit.json, params.yaml) on one track."""
import json
import math
import subprocess

import numpy as np
import pytest

import predvs
from conftest import read_track

RELATIVE = 1e-12  # the bound (same code on the same doubles: 0 expected)


def close(a, b):
    if a is None or b is None:  # the command line writes a non-finite number (an open CI bound) as null
        other = b if a is None else a
        return other is None or (isinstance(other, float) and not math.isfinite(other))
    if isinstance(a, str) or isinstance(b, str):  # a word (model: ca, mean: zero)
        return a == b
    return abs(a - b) <= RELATIVE * max(abs(a), abs(b), 1e-300)


@pytest.mark.parametrize("name,objective", [("kf-cv", "likelihood"), ("fakf", "likelihood"),
                                            ("kf-cv", "prediction")])
def test_fit_noise_matches_the_command_line(name, objective, cli, track_csv, tmp_path):
    # GIVEN the command line's fit of `name` on the generated track
    out = tmp_path / "fit"
    subprocess.run([cli, "fit-noise", "--input", str(track_csv), "--predictor", name, "--objective", objective,
                    "--out", str(out)], check=True, capture_output=True)
    cpp = json.loads((out / "fit.json").read_text())
    # WHEN the module fits the same predictor on the same numbers (the command's horizon, 2 frames)
    t, z = read_track(track_csv)
    fit = predvs.fit_noise(name, t, z, objective=objective, horizon_s=cpp.get("horizon_s", 0.0))
    # THEN every figure is the same
    assert fit.predictor == name and fit.objective == objective
    assert close(fit.rmse_before_px, cpp["rmse_before_px"]) and close(fit.rmse_after_px, cpp["rmse_after_px"])
    if objective == "prediction":
        assert fit.residuals == cpp["residuals"] and fit.rmse_after_px <= fit.rmse_before_px
    assert fit.innovations == cpp["innovations"] and fit.iterations == cpp["iterations"]
    assert fit.termination == cpp["termination"] and fit.covariance_ok == cpp["covariance_ok"]
    assert close(fit.loglik_before, cpp["loglik_before"]) and close(fit.loglik_after, cpp["loglik_after"])
    assert [v.key for v in fit.values] == [f["key"] for f in cpp["fitted"]]
    for v, f in zip(fit.values, cpp["fitted"]):
        assert close(v.initial, f["start"]) and close(v.value, f["value"]), (v, f)
        std = None if math.isnan(v.std_log) else v.std_log
        assert close(std, f["std_log"]), (v, f)
        if f["ci95"] is not None:
            assert close(v.lo95, f["ci95"][0]) and close(v.hi95, f["ci95"][1])
        assert v.at_bound == f["at_bound"] and v.held == f.get("held", False)
    assert fit.variant == cpp["variant"]
    assert [v[0] for v in fit.variants] == [v["variant"] for v in cpp["variants"]]
    assert all(close(a[2], b["objective_after"]) for a, b in zip(fit.variants, cpp["variants"]))
    assert fit.forecast_variant == cpp["forecast_variant"]
    assert [(v, close(r, c["rmse_px"])) for (v, r), c in zip(fit.forecast_variants, cpp["forecast_variants"])] == \
        [(c["variant"], True) for c in cpp["forecast_variants"]]
    own = None if math.isnan(fit.rmse_own_forecast_px) else fit.rmse_own_forecast_px
    assert close(own, cpp["rmse_own_forecast_px"])
    if objective == "prediction":  # kf-cv's blend runs on two horizons: the one-horizon blend was compared
        assert [v[0] for v in fit.forecast_variants] == ["hold_blend_frames=1"]
    assert fit.params.keys() == cpp["params"].keys()
    assert all(close(fit.params[k], cpp["params"][k]) for k in fit.params)
    # and the parameter file it wrote reads back as the module's params (12 significant digits)
    (entry,) = predvs.read_params(str(out / "params.yaml"))
    assert entry["name"] == name
    assert all(entry["params"][k] == fit.params[k] if isinstance(fit.params[k], str)
               else abs(entry["params"][k] - fit.params[k]) <= 1e-11 * abs(fit.params[k]) for k in fit.params)
    # and the likelihood it reports is log_likelihood's, improved by a likelihood fit
    ll_after, n = predvs.log_likelihood(name, t, z, fit.params)
    assert n == fit.innovations and close(ll_after, fit.loglik_after)
    if objective == "likelihood":  # (the prediction objective may lower the likelihood)
        assert fit.loglik_after >= fit.loglik_before


def test_fit_noise_errors(track_csv):
    t, z = read_track(track_csv)
    with pytest.raises(ValueError, match="'hold' has no parameters to fit"):
        predvs.fit_noise("hold", t, z)
    with pytest.raises(ValueError, match="unknown predictor 'nope'"):
        predvs.fit_noise("nope", t, z)
    with pytest.raises(ValueError, match="z: 3 rows, expected one per time"):
        predvs.fit_noise("kf-cv", t, z[:3])
    with pytest.raises(ValueError, match="t: row 1: times must be strictly increasing"):
        predvs.fit_noise("kf-cv", np.zeros(len(t)), z)
    with pytest.raises(ValueError, match="unknown parameter 'qq'"):
        predvs.fit_noise("kf-cv", t, z, params={"qq": 1.0})
    with pytest.raises(ValueError, match="unknown fit objective 'mse'"):
        predvs.fit_noise("kf-cv", t, z, objective="mse")
    with pytest.raises(ValueError, match="measured rows"):
        predvs.fit_noise("kf-cv", t[:20], z[:20])
