# predvs from Python: a notebook-style walkthrough (docs/PYTHON.md shows each cell with its output).
# Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/walkthrough.py
# Cells are separated by "# %%" lines; examples/python/render_markdown.py turns them into the
# Markdown of docs/PYTHON.md, and the CTest python_module runs this file (python/tests).

# %% The registry: every predictor by name, as `predvs list` shows it
import numpy as np
import predvs

for name, summary in predvs.predictors()[:2]:
    print(f"{name:16s} {summary}")
print("...", len(predvs.predictors()), "predictors")

# %% A track: a target on a circle (radius 80 px, 0.5 turn/s) at 30 Hz, 1.5 px noise, 5 % dropped frames
rng = np.random.default_rng(3)
rate_hz = 30.0
t = np.arange(0.0, 12.0, 1.0 / rate_hz)
truth = np.column_stack([320 + 80 * np.cos(np.pi * t), 240 + 80 * np.sin(np.pi * t)])
z = truth + rng.normal(0.0, 1.5, truth.shape)
z[rng.random(len(t)) < 0.05] = np.nan  # dropped frame: u and v not measured
print("frames", len(t), "dropped", int(np.isnan(z[:, 0]).sum()))

# %% One predictor: update with each frame (predict-only on a dropped one), predict two frames ahead
p = predvs.make("kf-cv", channels=2, params={"q": 2000.0})
for tk, zk in zip(t[:30], z[:30]):
    if np.isnan(zk).all():
        p.update(tk)  # predict-only step
    else:
        p.update(tk, zk)  # a NaN entry would mean "this channel not measured"
x, P = p.predict(p.time + 2 / rate_hz)  # x (channels, n_state), P (channels, n_state, n_state)
print("x shape", x.shape, "P shape", P.shape)
print("u: position %.1f px, velocity %.1f px/s, std %.2f px" % (x[0, 0], x[0, 1], np.sqrt(P[0, 0, 0])))
print(p.innovation(0))


# %% Scoring predictors two frames ahead against the truth (the rule of `predvs predict`)
def rmse_ahead(name, params=None, horizon_frames=2):
    # horizon_frames: the horizon the predictor will be asked for, as predict passes it
    p = predvs.make(name, 2, {"horizon_frames": horizon_frames, **(params or {})})
    err = []
    for k, (tk, zk) in enumerate(zip(t, z)):
        p.update(tk) if np.isnan(zk).all() else p.update(tk, zk)
        if k + horizon_frames < len(t):
            err.append(p.predict_positions(t[k + horizon_frames]) - truth[k + horizon_frames])
    return float(np.sqrt(np.mean(np.sum(np.square(err[30:]), axis=1))))


for name in ["hold", "kf-cv", "kf-ca", "fakf", "imm"]:
    print(f"{name:6s} rmse {rmse_ahead(name):6.2f} px")

# %% Errors are the C++ ones, as ValueError
for bad in [lambda: predvs.make("kf-cv", 2, {"qq": 1.0}), lambda: predvs.make("kf-xx", 2)]:
    try:
        bad()
    except ValueError as e:
        print("ValueError:", str(e)[:70])

# %% Noise fitting on numpy arrays (as `predvs fit-noise`): maximum innovation likelihood
fit = predvs.fit_noise("kf-cv", t, z)
for v in fit.values:
    print(f"{v.key}: {v.initial:.4g} -> {v.value:.4g}  95% [{v.lo95:.4g}, {v.hi95:.4g}]")
print(f"log-likelihood {fit.loglik_before:.1f} -> {fit.loglik_after:.1f} over {fit.innovations} innovations")
print(f"kf-cv fitted: rmse {rmse_ahead('kf-cv', fit.params):.2f} px")

# %% Parameter files: what fit-noise writes and `predvs predict/servo/compare --params FILE` read
import os
import tempfile

with tempfile.TemporaryDirectory() as folder:
    path = os.path.join(folder, "params.yaml")
    predvs.write_params(path, fit, comment=["kf-cv fitted on the circle of docs/PYTHON.md"])
    print(open(path).read())
    (entry,) = predvs.read_params(path)
print(entry["name"], sorted(entry["params"]))
