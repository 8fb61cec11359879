// predvs app — the command line, callable in-process.
//
//   predvs list
//   predvs predict --input FILE.csv --predictor NAME|all (--horizon-s S | --delay-frames H)
//                  --out DIR [--param [NAME.]KEY=VALUE ...] [--no-plots]
//   predvs servo   [--scenario NAME|FILE] [--predictors a,b,c] [--seed N] [--set PATH=VALUE]...
//                  [--out DIR] [--no-plots]
//   predvs compare [--scenarios a,b|all] [--predictors x,y|all] [--runs N] [--seed S] [--jobs J]
//                  [--set PATH=VALUE]... [--sweep PATH=V1,V2]... [--out DIR=out/compare] [--no-plots]
//                  (compare_command.h; several --sweep: a grid over the product of their values)
//   predvs track   --images PATTERN|DIR|IMAGE|VIDEO [--source dots] [--predictor NAME|a,b|all]
//                  [--delay-frames H=2] [--fps F=30] [--set KEY=VALUE]... [--out DIR] (track_command.h)
//   predvs calibrate camera --images DIR|PATTERN --pattern circles|chessboard|apriltag [...]
//   predvs calibrate latency --log LOG.csv [...]          (calibrate_command.h)
//   --set overrides any scenario key before the strict parse (scenario_override.h); servo and
//   compare also take --camera FILE [--camera-name NAME] and --set-file FILE (scenario_inputs.h).
//
// `predvs servo` runs any scenario file once per predictor on one seed (servo_command.h): a closed
// loop (`kind: closed-loop`, the default scenario ibvs-moving-target) or an open-loop prediction
// experiment (`kind: open-loop`: E1-E4, E6, E7, E12), reporting the figures `predvs compare`
// aggregates, under the same names (report.h).
// `predvs predict` is the open-loop prediction of a recorded CSV track; it and fit-noise, make-track
// and track-study are defined in track_cli.h, which runCli adds, and which the `predvs` executable
// runs without this file's other commands (app/main.cpp; runCli is `predvs-all`).
#pragma once

#include "cli_args.h"  // commandLine

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

/// Runs the command line `args` (WITHOUT the program name, e.g. {"servo", "--seed", "3"}).
/// Normal output goes to `out`, progress and errors to `err`. Returns the exit status: 0 on
/// success (and for --help), 2 for every bad argument, file or scenario, in which case exactly
/// one line "predvs: error: ..." was written to `err` and no output directory was created.
int runCli(std::vector<std::string> args, std::ostream& out, std::ostream& err);

}  // namespace predvs
