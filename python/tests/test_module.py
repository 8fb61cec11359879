"""The predvs module on its own: registry, predictor object, errors, parameter files."""
import math
import os

import numpy as np
import pytest

import predvs


def test_registry_lists_every_predictor_with_a_summary():
    names = [n for n, _ in predvs.predictors()]
    assert "kf-cv" in names and "fakf" in names and "hold" in names
    assert len(names) == len(set(names))
    assert all(s for _, s in predvs.predictors())
    assert all(predvs.is_predictor(n) for n in names)
    assert not predvs.is_predictor("kf-xx")


def test_unknown_predictor_raises_value_error_with_the_cpp_message():
    with pytest.raises(ValueError, match=r"unknown predictor 'kf-xx' \(known: hold, kf-cv"):
        predvs.make("kf-xx", 2)


def test_bad_parameter_raises_value_error_naming_it():
    with pytest.raises(ValueError, match=r"unknown parameter 'qq' for predictor 'kf-cv'"):
        predvs.make("kf-cv", 2, params={"qq": 1.0})
    with pytest.raises(ValueError, match=r"parameter 'q'.*out of range"):
        predvs.make("kf-cv", 2, params={"q": -1.0})
    with pytest.raises(ValueError, match=r"parameter 'q' of kf-cv: expected a number"):
        predvs.make("kf-cv", 2, params={"q": [1.0]})
    with pytest.raises(ValueError, match=r"parameter 'q' expects a number or 'auto', got 'fast'"):
        predvs.make("kf-cv", 2, params={"q": "fast"})
    with pytest.raises(ValueError, match="at least one channel"):
        predvs.make("kf-cv", 0)


def test_update_predict_shapes_and_const_predict():
    # GIVEN a constant-velocity filter on 2 channels fed a straight line at 30 Hz
    p = predvs.make("kf-cv", channels=2, params={"q": 100.0, "r": 1.0})
    assert (p.name, p.channels) == ("kf-cv", 2) and math.isnan(p.time)
    x, P = p.predict(0.0)
    assert x.shape == (2, 2) and P.shape == (2, 2, 2) and np.isnan(x).all()
    for k in range(30):
        t = k / 30
        p.update(t, np.array([100.0 + 60.0 * t, 50.0 - 30.0 * t]))
    # WHEN it predicts 0.1 s ahead
    x, P = p.predict(p.time + 0.1)
    # THEN the positions follow the line, P is symmetric positive, predict changed nothing
    assert x.shape == (2, 2) and P.shape == (2, 2, 2)
    assert np.allclose(x[:, 0], [100.0 + 60.0 * (29 / 30 + 0.1), 50.0 - 30.0 * (29 / 30 + 0.1)], atol=1e-6)
    assert np.allclose(x[:, 1], [60.0, -30.0], atol=1e-6)
    assert np.allclose(P, np.transpose(P, (0, 2, 1))) and (np.linalg.eigvalsh(P) > 0).all()
    x2, P2 = p.predict(p.time + 0.1)
    assert np.array_equal(x, x2) and np.array_equal(P, P2)
    assert np.array_equal(p.predict_positions(p.time + 0.1), x[:, 0])
    assert np.array_equal(p.predict_velocities(p.time + 0.1), x[:, 1])
    assert np.allclose(p.feedforward_velocities(p.time + 0.1), [60.0, -30.0], atol=1e-6)
    xc, Pc = p.predict(p.time + 0.1, channel=1)
    assert np.array_equal(xc, x[1]) and np.array_equal(Pc, P[1])
    assert p.innovation(0).valid and p.innovation(0).S > 0


def test_nan_channel_and_predict_only_steps():
    p = predvs.make("kf-cv", 2, {"q": 100.0, "r": 1.0})
    p.update(0.0, [1.0, 2.0])
    p.update(0.1, [1.5, float("nan")])  # channel 1 not measured
    assert p.innovation(0).valid and not p.innovation(1).valid
    p.update(0.2)  # predict-only
    assert not p.innovation(0).valid and p.time == 0.2
    p.reset()
    assert math.isnan(p.time) and np.isnan(p.predict_positions(1.0)).all()


def test_update_errors():
    p = predvs.make("kf-ca", 3)
    with pytest.raises(ValueError, match="z must hold 3 values"):
        p.update(0.0, [1.0, 2.0])
    p.update(0.0, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="kf-ca"):
        p.update(0.0, [1.0, 2.0, 3.0])  # time not after the last one
    with pytest.raises(IndexError, match="channel 3 out of range"):
        p.innovation(3)
    with pytest.raises(IndexError):
        p.predict(1.0, channel=-1)


def test_noise_parameters_and_fit_parameters():
    p = predvs.make("kf-cv", 2, {"q": 321.0})
    keys = {n.key: n for n in p.noise_parameters()}
    assert keys["q"].value == 321.0 and keys["q"].lo < keys["q"].hi
    assert [n.key for n in predvs.fit_parameters("kf-cv")] == [n.key for n in p.noise_parameters()]
    with pytest.raises(ValueError, match="'hold' has no parameters to fit"):
        predvs.fit_parameters("hold")


def test_diagnostics_of_imm_are_named_per_channel():
    p = predvs.make("imm", 2)
    p.update(0.0, [0.0, 0.0])
    p.update(0.05, [1.0, 1.0])
    d = p.diagnostics()
    assert set(d) >= {"mu_ca_0", "mu_ca_1", "fw_ca_0", "fw_ca_1"} and all(0.0 <= v <= 1.0 for v in d.values())


def test_params_file_round_trip(tmp_path):
    path = tmp_path / "p.yaml"
    predvs.write_params(str(path), [{"name": "kf-cv", "params": {"q": 123.4, "r": "auto"}},
                                    {"name": "fakf", "params": {}}], comment=["made by a test"])
    text = path.read_text()
    assert text.startswith("# made by a test\npredictors:\n")
    assert predvs.read_params(str(path)) == [{"name": "kf-cv", "params": {"q": 123.4, "r": "auto"}},
                                             {"name": "fakf", "params": {}}]
    assert [f for f in os.listdir(tmp_path)] == ["p.yaml"]


def test_params_file_errors_name_the_file_and_line(tmp_path):
    missing = tmp_path / "none.yaml"
    with pytest.raises(ValueError, match=f"{missing}: cannot open the parameter file"):
        predvs.read_params(str(missing))
    bad = tmp_path / "bad.yaml"
    bad.write_text("predictors:\n  - {name: kf-ca, params: {q: 1}}\n  - {name: kf-cv, params: {qq: 2}}\n")
    with pytest.raises(ValueError, match=f"{bad}:3: unknown parameter 'qq' for predictor 'kf-cv'"):
        predvs.read_params(str(bad))
    out = tmp_path / "out.yaml"
    with pytest.raises(ValueError, match="unknown parameter 'qq'"):
        predvs.write_params(str(out), [{"name": "kf-cv", "params": {"qq": 1.0}}])
    with pytest.raises(ValueError, match="unknown predictor 'nope'"):
        predvs.write_params(str(out), [{"name": "nope"}])
    assert sorted(os.listdir(tmp_path)) == ["bad.yaml"]
