# predvs — sourced by the closed-loop study scripts (closed-loop-white-target.sh,
# closed-loop-coasting.sh): one `predvs compare` run per grid, every grid on the same predictor list,
# so every variant of a grid runs on the same seeds.
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
