# predvs — sourced by the closed-loop study scripts (closed-loop-white-target.sh,
# closed-loop-coasting.sh, imm-closed-loop.sh, feedforward-damping.sh): one `predvs compare` run per
# grid, every grid on the same predictor list, so every variant of a grid runs on the same seeds; and
# the grids they share.
#
#   compare_grid GRID COMPARE_ARGS...
#
# Uses the caller's variables: script (its name, for messages), bin, runs, list (the YAML
# elements of --set predictors=[...]) and out; writes OUT/GRID (the leaderboards) and OUT/GRID.log,
# and exits 1 naming the log when compare fails.
compare_grid() {
  local grid=$1
  shift
  echo "$script: $grid ($runs runs per cell)" >&2
  "$bin" compare "$@" --runs "$runs" --set "predictors=[$list]" --out "$out/$grid" --no-plots >"$out/$grid.log" 2>&1 ||
    { echo "$script: error: $grid failed, see $out/$grid.log" >&2; exit 1; }
}

# The closed-loop grids: `scenarios`, the closed-loop scenarios with a moving target and every sweep
# value (24 cells), and `held-out`, ibvs-moving-target over 60 / 25 / 10 Hz, 0.5 / 2 px of noise and a
# target 1x / 3x as fast (12 cells).
closed_loop_grids() {
  compare_grid scenarios --scenarios delay-study,ibvs-moving-target,e5-line,e5-circle,e8-ibvs,e8-vtc,e9-ibvs,e9-broyden
  compare_grid held-out --scenarios ibvs-moving-target --sweep noise.sigma=0.5,2 --sweep timing.base_period_s=0.0167,0.04,0.1 \
    --sweep target.trajectory.omega=0.5,1.5
}

# The occlusion grids: `occlusion-L` for each length L (s) given, ibvs-moving-target with one occlusion
# of L s at 12 s over 60 / 25 Hz, 0.5 / 2 px and a target 1x / 3x as fast (8 cells each);
# `rendered-twin`, ibvs-rendered-dots through its geometric twin (0.038 and 0.5 px; a 0.5 s occlusion);
# `e8-vtc-occlusion` (3 s, the loop told to extrapolate).
occlusion_grids() {
  local L
  for L in "$@"; do
    compare_grid "occlusion-$L" --scenarios ibvs-moving-target --set "occlusions=[{start_s: 12, end_s: $(python3 -c "print(12 + $L)")}]" \
      --sweep noise.sigma=0.5,2 --sweep timing.base_period_s=0.0167,0.04 --sweep target.trajectory.omega=0.5,1.5
  done
  compare_grid rendered-twin --scenarios ibvs-rendered-dots --set 'source={type: geometric}' --sweep noise.sigma=0.038,0.5
  compare_grid e8-vtc-occlusion --scenarios e8-vtc-occlusion
}
