// predvs app — printf "%.{P}g" text of a double, fast (issue 11 item 8: predictions.csv of a
// 2-million-row track is 52 M numbers).
//
// writeGeneral(buf, x, P) writes exactly the characters of
//   std::to_chars(buf, end, x, std::chars_format::general, P)
// (which the standard specifies as printf's "%.{P}g"), i.e. x correctly rounded to P significant
// digits, fixed notation when the decimal exponent X of the rounded value is in [-4, P), trailing
// zeros and a trailing '.' removed, scientific otherwise.
//
// Fast path (the usual case of pixel coordinates and times): x normal, 1 <= P <= 10, X in [-4, P).
// x = m 2^e exactly (m < 2^53), so x 10^k = m 5^k 2^(e+k) with k = P - 1 - X is computed exactly in
// 128-bit integers and rounded to the nearest integer q (10^(P-1) <= q < 10^P); q's digits are x's
// P significant digits (laid out two at a time from a table, on a little-endian machine). An exact tie (round-half-even territory), any other exponent, a
// subnormal, zero, inf or NaN goes to std::to_chars itself, so the text is always to_chars'
// (tests/app/general_number_test.cpp compares both on millions of values).
#pragma once

namespace predvs {

/// Writes x as "%.{precision}g" (std::to_chars general format) at `buf` (room for 32 chars);
/// returns the end of the text (no terminating NUL). precision in [1, 17].
char* writeGeneral(char* buf, double x, int precision);

}  // namespace predvs
