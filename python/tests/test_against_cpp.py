"""The module against the C++ library on the same track: every predictor, x/P and innovations.

The C++ side is predvs_py_reference (python/tests/reference_run.cpp), which reads the same CSV
with the app's track reader and prints with %.17g. Both call the same compiled predictors, so the
only possible differences are in getting the numbers across (CSV parsing, array conversion, the
NaN / predict-only dispatch): the tolerance is 1e-12 absolute and the test reports the largest
difference seen (0 expected).
"""
import subprocess

import numpy as np

import predvs
from conftest import read_track

TOLERANCE = 1e-12  # the bound; both sides run the same code, so 0 is expected
RATE_HZ = 30.0
HORIZON_S = 2 / RATE_HZ  # two frames ahead, as `predvs predict --delay-frames 2`


def four_channel_track(track_csv, path):
    """A 2-point wide CSV from the generated track: point 0 = measured (u, v), point 1 = truth
    (u_true, v_true), with single channels blanked (NaN channel) and rows 60-64 all blank
    (predict-only steps). Returns (t, z (frames, 4))."""
    a = np.genfromtxt(track_csv, delimiter=",", names=True)
    t = np.asarray(a["t"], dtype=float)
    z = np.column_stack([a["u"], a["v"], a["u_true"], a["v_true"]]).astype(float)
    k = np.arange(len(t))
    z[k % 7 == 3, 1] = np.nan
    z[k % 11 == 5, 2] = np.nan
    z[60:65, :] = np.nan
    with open(path, "w") as f:
        f.write("t,u0,v0,u1,v1\n")
        for tk, row in zip(t, z):
            f.write(",".join([repr(float(tk))] + ["" if np.isnan(v) else repr(float(v)) for v in row]) + "\n")
    return t, z


def specs():
    """Every predictor with its defaults, and every one with noise keys at 2x their default."""
    out = [(name, name, {}) for name, _ in predvs.predictors()]
    for name, _ in predvs.predictors():
        keys = predvs.make(name, 1).noise_parameters()
        if keys:
            params = {k.key: 2.0 * k.value for k in keys}
            label = name + "".join(f":{k}={v!r}" for k, v in params.items())
            out.append((label, name, params))
    return out


def run_python(name, params, t, z):
    m = z.shape[1]
    p = predvs.make(name, m, params)
    n = p.predict(0.0)[0].shape[1]
    X = np.full((len(t), m, 3), np.nan)
    P = np.full((len(t), m, 3, 3), np.nan)
    I = np.zeros((len(t), m, 3))
    for k, (tk, zk) in enumerate(zip(t, z)):
        if np.isnan(zk).all():
            p.update(tk)
        else:
            p.update(tk, zk)
        x, Pk = p.predict(tk + HORIZON_S)
        X[k, :, :n], P[k, :, :n, :n] = x, Pk
        for c in range(m):
            inn = p.innovation(c)
            I[k, c] = (inn.eps, inn.S, float(inn.valid))
    return X, P, I


def read_reference(path, frames, m):
    """{spec label: (X (frames, m, 3), P (frames, m, 3, 3), I (frames, m, 3))} of the C++ output."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        assert header[:3] == ["spec", "row", "channel"] and len(header) == 18, header
        labels, values = [], []
        for line in f:
            label, rest = line.rstrip("\n").split(",", 1)
            labels.append(label)
            values.append(rest)
    data = np.array([np.array(v.split(","), dtype=float) for v in values])
    out = {}
    for label in dict.fromkeys(labels):
        rows = data[[i for i, l in enumerate(labels) if l == label]]
        assert rows.shape[0] == frames * m, label
        out[label] = (rows[:, 2:5].reshape(frames, m, 3), rows[:, 5:14].reshape(frames, m, 3, 3),
                      rows[:, 14:17].reshape(frames, m, 3))
    return out


def max_abs_diff(a, b):
    assert np.array_equal(np.isnan(a), np.isnan(b)), "NaN in different places"
    d = np.abs(np.where(np.isnan(a), 0.0, a) - np.where(np.isnan(b), 0.0, b))
    return float(d.max()) if d.size else 0.0


def test_every_predictor_matches_cpp_on_the_same_track(track_csv, reference_exe, tmp_path):
    # GIVEN a 4-channel track with NaN channels and predict-only rows, and the C++ results on it
    wide = tmp_path / "wide.csv"
    t, z = four_channel_track(track_csv, wide)
    assert np.isnan(z).all(axis=1).sum() >= 5 and (np.isnan(z).any(axis=1) & ~np.isnan(z).all(axis=1)).any()
    all_specs = specs()
    ref = tmp_path / "reference.csv"
    subprocess.run([reference_exe, str(wide), str(ref), repr(HORIZON_S)] + [s[0] for s in all_specs], check=True)
    assert len(all_specs) > len(predvs.predictors())
    reference = read_reference(ref, len(t), z.shape[1])
    assert list(reference) == [s[0] for s in all_specs]
    worst = {}
    for label, name, params in all_specs:
        # WHEN the module runs the same predictor with the same params over the same rows
        X, P, I = run_python(name, params, t, z)
        Xr, Pr, Ir = reference[label]
        # THEN x, P at t + horizon and the innovations agree to 1e-12 after every row
        worst[label] = max(max_abs_diff(X, Xr), max_abs_diff(P, Pr), max_abs_diff(I, Ir))
        assert np.isfinite(X[-1, :, 0]).all(), label
    print("largest |python - C++| over x, P, innovation:", max(worst.values()))
    bad = {k: v for k, v in worst.items() if not v <= TOLERANCE}
    assert not bad, bad
