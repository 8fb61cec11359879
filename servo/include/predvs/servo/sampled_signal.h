// predvs — a sampled signal with gaps: linear interpolation over its finite samples.
#pragma once

#include <vector>

namespace predvs {

/// Linear interpolation of the samples (t_s, y) at time t (s, t_s increasing), using only finite y
/// (a NaN sample is a gap). NaN when t lies outside the span of the finite samples (no
/// extrapolation).
double interpolateAt(const std::vector<double>& t_s, const std::vector<double>& y, double t);

/// interpolateAt(t_s, y, t_s[i] + shift_s) for every row i, in one pass: the same rule and the same
/// arithmetic, with the binary search replaced by a cursor (t_s[i] + shift_s does not decrease with
/// i, so neither does its lower bound). shift_s >= 0 is the horizon of an h-step comparison.
std::vector<double> interpolateShifted(const std::vector<double>& t_s, const std::vector<double>& y, double shift_s);

}  // namespace predvs
