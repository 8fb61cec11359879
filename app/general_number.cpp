#include "general_number.h"

#include <charconv>
#include <cstdint>
#include <cstring>

namespace predvs {
namespace {

__extension__ typedef unsigned __int128 u128;  // GCC and Clang on 64-bit targets

constexpr uint64_t kPow10[] = {1ull,         10ull,         100ull,         1000ull,
                               10000ull,     100000ull,     1000000ull,     10000000ull,
                               100000000ull, 1000000000ull, 10000000000ull};
constexpr uint64_t kPow5[] = {1ull,          5ull,           25ull,          125ull,
                              625ull,        3125ull,        15625ull,       78125ull,
                              390625ull,     1953125ull,     9765625ull,     48828125ull,
                              244140625ull,  1220703125ull,  6103515625ull,  30517578125ull};
constexpr int kMaxK = 15;  // kPow5's last index: 10 digits for values down to 1e-5
// The digits are laid out as bytes of an integer (digitBytes): the fast path needs the text order
// to be the byte order, i.e. a little-endian machine; elsewhere std::to_chars does it all.
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr bool kLittleEndian = true;
#else
constexpr bool kLittleEndian = false;
#endif

char* slow(char* buf, double x, int precision) {
  return std::to_chars(buf, buf + 32, x, std::chars_format::general, precision).ptr;
}

/// round(m 5^k 2^-s) to the nearest integer; false on an exact tie.
inline bool roundScaled(uint64_t m, int k, int s, uint64_t& q) {
  const u128 M = static_cast<u128>(m) * kPow5[k];
  if (s < 64) {  // the usual case: the remainder is in the low word (the same q and tie test in 64 bits)
    const uint64_t lo = static_cast<uint64_t>(M), hi = static_cast<uint64_t>(M >> 64);
    const uint64_t mask64 = (uint64_t{1} << s) - 1, half64 = uint64_t{1} << (s - 1);
    const uint64_t rem64 = lo & mask64;
    if (rem64 == half64) return false;
    q = ((hi << (63 - s)) << 1 | (lo >> s)) + (rem64 > half64 ? 1 : 0);  // (M >> s), s in [1, 63]
    return true;
  }
  const u128 mask = (static_cast<u128>(1) << s) - 1, half = static_cast<u128>(1) << (s - 1);
  const u128 rem = M & mask;
  if (rem == half) return false;
  q = static_cast<uint64_t>(M >> s) + (rem > half ? 1 : 0);
  return true;
}

/// "00".."99" as little-endian 16-bit words: the first digit in the low byte.
struct PairTable {
  uint16_t pair[100];
  constexpr PairTable() : pair() {
    for (int i = 0; i < 100; ++i) pair[i] = static_cast<uint16_t>(('0' + i / 10) | (('0' + i % 10) << 8));
  }
};
constexpr PairTable kPairs{};

/// The ten digits of q < 10^10, zero-padded, as bytes of a 128-bit word (digit 0 = most
/// significant in the lowest byte, i.e. the text in memory order on a little-endian machine).
inline u128 digitBytes(uint64_t q) {
  const uint32_t hi = static_cast<uint32_t>(q / 100000000);   // 2 digits
  const uint32_t lo = static_cast<uint32_t>(q % 100000000);   // 8 digits
  const uint32_t a = lo / 10000, b = lo % 10000;               // 4 + 4 digits
  const uint64_t low8 = static_cast<uint64_t>(kPairs.pair[a / 100]) | static_cast<uint64_t>(kPairs.pair[a % 100]) << 16 |
                        static_cast<uint64_t>(kPairs.pair[b / 100]) << 32 | static_cast<uint64_t>(kPairs.pair[b % 100]) << 48;
  return static_cast<u128>(kPairs.pair[hi]) | static_cast<u128>(low8) << 16;
}

}  // namespace

char* writeGeneral(char* buf, double x, int precision) {
  const int P = precision;
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  if (!kLittleEndian || P < 1 || P > 10 || biased == 0 || biased == 0x7ff) return slow(buf, x, precision);
  const uint64_t m = (bits & ((uint64_t{1} << 52) - 1)) | (uint64_t{1} << 52);
  const int e = biased - 1075;  // |x| = m 2^e, 2^52 <= m < 2^53
  // X estimate: |x| in [2^(e+52), 2^(e+53)), so floor(log10|x|) is this or one more.
  int X = static_cast<int>(static_cast<double>(e + 52) * 0.30102999566398120);
  if (static_cast<double>(e + 52) * 0.30102999566398120 < X) --X;  // floor for negatives
  uint64_t q = 0;
  for (int attempt = 0;; ++attempt) {
    const int k = P - 1 - X;
    if (X < -4 || X >= P || k < 0 || k > kMaxK || attempt > 2) return slow(buf, x, precision);
    const int s = -(e + k);  // > 0 here: |x| < 10^P <= 2^34 and k <= 15 give e + k < 0
    if (s <= 0 || s >= 127) return slow(buf, x, precision);
    if (!roundScaled(m, k, s, q)) return slow(buf, x, precision);
    if (q < kPow10[P - 1]) {
      --X;  // x below 10^X
    } else if (q >= kPow10[P]) {
      ++X;  // x at or above 10^(X+1), or rounded up to it
    } else {
      break;
    }
  }
  // q has P digits; the value is q 10^(X - P + 1). Its digits are built in a register, two at a
  // time from a table (ten bytes, little-endian: the first digit in the lowest byte), the '.'
  // inserted by shifts, and stored at once; the fraction's trailing zeros (and a bare '.') are
  // then cut by the length.
  int frac = P - 1 - X;  // digits after the point (for X < 0, the -X - 1 zeros included)
  for (uint64_t r = q; frac > 0 && r % 10 == 0; r /= 10) --frac;
  const u128 digits = P == 10 ? digitBytes(q) : digitBytes(q) >> (8 * (10 - P));  // P bytes
  char* p = buf;
  if (bits >> 63) *p++ = '-';
  if (X < 0) {
    std::memcpy(p, "0.0000", 6);
    p += 2 - X - 1;
    std::memcpy(p, &digits, 16);
    return p + frac - (-X - 1);
  }
  if (frac == 0) {  // an integer: the X + 1 digits, no point (nothing of the fraction is kept)
    std::memcpy(p, &digits, 16);
    return p + X + 1;
  }
  // The X + 1 digits before the point, the '.', and the rest from byte X + 1 of the digits: three
  // unaligned stores (16 bytes from p, the point, 16 bytes from p + X + 2 <= p + 11, within the 32
  // bytes of room) instead of building the text in a 128-bit word with shifts by a variable amount.
  char d[32] = {};
  std::memcpy(d, &digits, 16);
  std::memcpy(p, d, 16);
  p[X + 1] = '.';
  std::memcpy(p + X + 2, d + X + 1, 16);
  p += X + 2 + frac;
  return p;
}

}  // namespace predvs
