// ExactSum: a sum of doubles with no rounding error until it is read, so that the same terms
// added in any order, on any number of threads or processes, give the same bits: the exact sum
// rounded once to the nearest double (ties to even).
//
// Every finite double is an integer multiple of 2^-1074 below 2^1024, so the sum is held as a
// fixed-point integer in signed 32-bit digits of 2^-1074 units (int64 words with room for
// carries). Parts formed apart combine by adding their digits (operator+=, or an integer MPI sum
// of words()), which is exact and associative. Infinities and NaNs are counted apart: the sum is
// NaN with any NaN or with both infinities, else the infinity.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace talus {

class ExactSum {
public:
  static constexpr int digits = 68;              // 2176 bits: 2^-1074 to past 2^1024, with headroom
  static constexpr int words = digits + 3;       // the digits, then counts of +inf, -inf and NaN
  static constexpr int carry_interval = 1 << 30; // adds between carries (a digit gains < 2^32)

  void add(double x);
  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }
  ExactSum& operator+=(const ExactSum& other);
  // The exact sum, rounded to nearest (ties to even); +-inf past the largest double.
  double value() const;

  // The words to sum as integers across processes: normalize() first, so that a sum of up to
  // 2^30 of them cannot overflow; normalize() again after the sum.
  std::int64_t* data() { return w_.data(); }
  // Carries each digit's excess into the next: digits in [0, 2^32), the top one signed.
  void normalize();

private:
  std::array<std::int64_t, words> w_{};
  std::int32_t pending_ = 0; // adds since the last normalize()
};

} // namespace talus
