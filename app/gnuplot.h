// predvs app — PNG plots drawn by gnuplot (pngcairo terminal).
//
// The plots are reproducible by hand: each one is a gnuplot script plus whitespace-separated data
// files written into the output directory, then `gnuplot SCRIPT` is run from that directory.
#pragma once

#include <string>

namespace predvs {

/// True if a `gnuplot` executable is on PATH.
bool gnuplotAvailable();

/// Throws std::runtime_error("gnuplot not found ...") unless gnuplotAvailable().
void requireGnuplot();

/// Runs `gnuplot SCRIPT` with `dir` as working directory (stdout/stderr go to SCRIPT.log there).
/// Throws std::runtime_error naming the script and the first line of gnuplot's complaint when
/// gnuplot exits with a non-zero status.
void runGnuplot(const std::string& dir, const std::string& script);

/// A distinct colour for the k-th predictor of a comparison ("#rrggbb", 12 before repeating).
std::string seriesColor(size_t k);

/// Quotes a string for a gnuplot double-quoted literal (escapes \ and ").
std::string gnuplotQuote(const std::string& s);

}  // namespace predvs
