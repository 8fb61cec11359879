// predvs — a sampled signal with gaps: linear interpolation over its finite samples.
#pragma once

#include <vector>

namespace predvs {

/// Linear interpolation of the samples (t_s, y) at time t (s, t_s increasing), using only finite y
/// (a NaN sample is a gap). NaN when t lies outside the span of the finite samples (no
/// extrapolation).
double interpolateAt(const std::vector<double>& t_s, const std::vector<double>& y, double t);

}  // namespace predvs
