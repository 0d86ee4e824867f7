#include "obj_number.hpp"

#include <array>
#include <cmath>

namespace pbd::detail {
namespace {

// 10^−k for fraction digit k as tinyobjloader gets it: its table below 8, std::pow from 8 on (computed at run time
// by the same std::pow, never folded by the compiler, so the bits are the library's).
double tenth_power(int k) {
  static constexpr double kTable[] = {1.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001};
  if (k < 8) return kTable[k];
  static const std::array<double, 64> kPow = [] {
    std::array<double, 64> p{};
    volatile double ten = 10.0;  // a run-time value: std::pow is called, not constant-folded
    for (int i = 8; i < 64; ++i) p[std::size_t(i)] = std::pow(ten, -double(i));
    return p;
  }();
  return k < 64 ? kPow[std::size_t(k)] : std::pow(10.0, -double(k));
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

double obj_number(std::string_view token) {
  // The same steps and the same floating-point operations as tryParseDouble; this file is compiled without
  // floating-point contraction (io/CMakeLists.txt), as the library was.
  const char* c = token.data();
  const char* end = c + token.size();
  double mantissa = 0.0;
  int exponent = 0;
  bool negative = false;
  if (*c == '+' || *c == '-') negative = *c++ == '-';
  while (c != end && is_digit(*c)) {
    mantissa *= 10;
    mantissa += static_cast<int>(*c - '0');
    ++c;
  }
  if (c != end && *c == '.') {
    ++c;
    for (int read = 1; c != end && is_digit(*c); ++read, ++c) mantissa += static_cast<int>(*c - '0') * tenth_power(read);
  }
  if (c != end && (*c == 'e' || *c == 'E')) {
    ++c;
    bool exponent_negative = false;
    if (*c == '+' || *c == '-') exponent_negative = *c++ == '-';
    while (c != end && is_digit(*c) && exponent <= 2147483647 / 10) {
      exponent *= 10;
      exponent += static_cast<int>(*c - '0');
      ++c;
    }
    if (exponent_negative) exponent = -exponent;
  }
  return (negative ? -1 : 1) * (exponent ? std::ldexp(mantissa * std::pow(5.0, exponent), exponent) : mantissa);
}

}  // namespace pbd::detail
