#include "talus/core/exact_sum.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace talus {

namespace {
constexpr int inf_plus = ExactSum::digits, inf_minus = ExactSum::digits + 1;
constexpr int not_a_number = ExactSum::digits + 2;
constexpr std::int64_t low32 = 0xffffffff;
} // namespace

// x = m 2^(s - 1074) with m < 2^53 the significand (with its hidden bit) and s >= 0 its biased
// exponent: m shifted by s mod 32 spans three digits from digit s / 32.
void ExactSum::add(double x) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const std::uint64_t e = (bits >> 52) & 0x7ff;
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  if (e == 0x7ff) {
    ++w_[m ? not_a_number : (bits >> 63 ? inf_minus : inf_plus)];
    return;
  }
  if (e != 0)
    m |= std::uint64_t{1} << 52;
  else if (m == 0)
    return;
  const int s = e != 0 ? static_cast<int>(e) - 1 : 0, k = s >> 5;
  const unsigned __int128 t = static_cast<unsigned __int128>(m) << (s & 31);
  const auto lo = static_cast<std::int64_t>(t & low32);
  const auto mid = static_cast<std::int64_t>((t >> 32) & low32);
  const auto hi = static_cast<std::int64_t>(t >> 64);
  if (bits >> 63)
    w_[k] -= lo, w_[k + 1] -= mid, w_[k + 2] -= hi;
  else
    w_[k] += lo, w_[k + 1] += mid, w_[k + 2] += hi;
  if (++pending_ == carry_interval) normalize();
}

ExactSum& ExactSum::operator+=(const ExactSum& other) {
  ExactSum o = other;
  o.normalize();
  for (int i = 0; i < words; ++i)
    w_[i] += o.w_[i];
  if (++pending_ == carry_interval) normalize();
  return *this;
}

// Floor division by 2^32 (an arithmetic shift) leaves each digit in [0, 2^32).
void ExactSum::normalize() {
  for (int i = 0; i + 1 < digits; ++i) {
    const std::int64_t carry = w_[i] >> 32;
    w_[i] -= carry * (std::int64_t{1} << 32);
    w_[i + 1] += carry;
  }
  pending_ = 0;
}

double ExactSum::value() const {
  if (w_[not_a_number] > 0 || (w_[inf_plus] > 0 && w_[inf_minus] > 0))
    return std::numeric_limits<double>::quiet_NaN();
  if (w_[inf_plus] > 0) return std::numeric_limits<double>::infinity();
  if (w_[inf_minus] > 0) return -std::numeric_limits<double>::infinity();
  ExactSum a = *this;
  a.normalize();
  const bool negative = a.w_[digits - 1] < 0;
  if (negative) { // the magnitude: negate every digit and carry again
    for (int i = 0; i < digits; ++i)
      a.w_[i] = -a.w_[i];
    a.normalize();
  }
  int h = digits - 1;
  while (h >= 0 && a.w_[h] == 0)
    --h;
  if (h < 0) return 0.0;
  auto bit = [&](int i) { return (a.w_[i >> 5] >> (i & 31)) & 1; };
  // The 53 bits from the highest set one down to L (no lower than 2^-1074, where the
  // subnormals' last bit sits), then round to nearest, ties to even, on the bits below L.
  const int msb = 32 * h + 63 - std::countl_zero(static_cast<std::uint64_t>(a.w_[h]));
  int L = msb > 52 ? msb - 52 : 0;
  std::uint64_t m = 0;
  for (int i = msb; i >= L; --i)
    m = (m << 1) | static_cast<std::uint64_t>(bit(i));
  if (L > 0 && bit(L - 1)) {
    bool sticky = (a.w_[(L - 1) >> 5] & ((std::int64_t{1} << ((L - 1) & 31)) - 1)) != 0;
    for (int i = ((L - 1) >> 5) - 1; i >= 0 && !sticky; --i)
      sticky = a.w_[i] != 0;
    if (sticky || (m & 1)) ++m;
    if (m >> 53) m >>= 1, ++L;
  }
  const double r = std::ldexp(static_cast<double>(m), L - 1074);
  return negative ? -r : r;
}

} // namespace talus
