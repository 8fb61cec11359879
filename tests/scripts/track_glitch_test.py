"""ctest track_cube_glitches: `predvs track` on ViSP's cube sequence, whose dots tracker jumps for
a frame now and then (docs/PERFORMANCE.md "Tracker glitches"). Without the glitch gate
(--glitch-sigmas 0) most predictors lose to hold; with track's gate (its default) every predictor's
error is lower, and at most one is at or above hold (kf-ca, measured x1.001).

    track_glitch_test.py PREDVS WORKDIR
"""
import csv
import os
import sys

from script_test import arguments, checked

IMAGES = "/usr/share/visp-images-data/ViSP-images/cube/image.%04d.pgm"


def pooled_rmse(out):
    """predictor -> pooled RMSE of leaderboard.csv in out."""
    with open(os.path.join(out, "leaderboard.csv")) as f:
        return {r["predictor"]: float(r["rmse_px"]) for r in csv.DictReader(f) if r["point"] == "all"}


def main():
    predvs, work = arguments()
    runs = {}
    for g in ("8", "0"):
        out = os.path.join(work, "g" + g)
        r = checked([predvs, "track", "--images", IMAGES, "--glitch-sigmas", g, "--no-plots", "--out", out])
        runs[g] = pooled_rmse(out)
        said = "glitch gate at 8 sigmas" in r.stdout
        assert said == (g == "8"), f"--glitch-sigmas {g}: the gate's line printed: {said}"
    gated, plain = runs["8"], runs["0"]
    hold = gated["hold"]
    assert plain["hold"] == hold, "hold does not depend on the gate"
    losing = sorted(n for n, e in gated.items() if n != "hold" and e >= hold)
    assert len(losing) <= 1, f"with the gate, at or above hold ({hold:.3f} px): {losing}"
    lost = [n for n, e in plain.items() if n != "hold" and e >= hold]
    assert len(lost) >= 5, f"without the gate only {lost} lose to hold: the sequence no longer tests the gate"
    worse = [n for n in gated if n != "hold" and gated[n] >= plain[n]]
    assert not worse, f"the gate does not lower the error of {worse}"
    print(f"cube: hold {hold:.3f} px; gated " + ", ".join(f"{n} {gated[n]:.3f}" for n in sorted(gated) if n != "hold")
          + f"; at or above hold with the gate {losing}, without it {len(lost)} of {len(plain) - 1}")


if __name__ == "__main__":
    sys.exit(main())
