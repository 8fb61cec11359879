// predvs — a sampled signal with gaps: linear interpolation over its finite samples.
#pragma once

#include <cstddef>
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

/// Rows [i0, i1) of interpolateShifted(t_s, y, shift_s), written to out[0 .. i1 - i0): the same
/// values, bit for bit (the cursor starts at the lower bound of t_s[i0] + shift_s, where the
/// whole-track pass has it on reaching row i0). For a track processed in blocks of rows.
void interpolateShifted(const std::vector<double>& t_s, const std::vector<double>& y, double shift_s, size_t i0,
                        size_t i1, double* out);

/// Median of the differences of consecutive times (the frame period of a track); few distinct
/// differences are counted without a copy of them, the same result as sorting (sampled_signal.cpp).
/// Throws std::invalid_argument when fewer than two times are given.
double medianPeriod(const std::vector<double>& t_s);

}  // namespace predvs
