#pragma once
/// Byte reader shared by the fuzz harnesses: turns libFuzzer's input into integers, strings
/// and "interesting" doubles. Reads past the end return zeros, so every input is a program.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace wp_fuzz {

/// Aborts with a message: the harnesses' way of reporting a violated invariant.
[[noreturn]] inline void fail(const char* what, const std::string& detail = std::string()) {
  std::fprintf(stderr, "\n*** INVARIANT VIOLATED: %s %s\n", what, detail.c_str());
  std::fflush(stderr);
  std::abort();
}

/// True when the environment variable `name` is "1..." (read once per name by the caller).
inline bool envFlag(const char* name) {
  const char* s = std::getenv(name);
  return s != nullptr && s[0] == '1';
}

/// A double with all its digits, for failure messages and traces.
inline std::string str(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

inline std::string str(const Eigen::Vector3d& v) {
  return str(v.x()) + " " + str(v.y()) + " " + str(v.z());
}

#define WP_FUZZ_CHECK(cond, detail)                                      \
  do {                                                                   \
    if (!(cond)) ::wp_fuzz::fail(#cond, (detail));                       \
  } while (0)

/// The entry of `table` picked by the bits of `byte` from bit `shift` up (as many bits as the
/// table's size, a power of two, needs): one input byte chooses several settings.
template <class T, std::size_t N>
T pickByBits(const T (&table)[N], std::uint8_t byte, int shift) {
  static_assert(N > 0 && (N & (N - 1)) == 0, "table size must be a power of two");
  return table[(byte >> shift) & (N - 1)];
}

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return pos_ >= size_; }
  std::size_t remaining() const { return pos_ < size_ ? size_ - pos_ : 0; }

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  // Each read is its own statement: the order of evaluation of operands is unspecified.
  std::uint16_t u16() {
    const unsigned lo = byte();
    const unsigned hi = byte();
    return static_cast<std::uint16_t>(lo | (hi << 8));
  }
  std::uint32_t u32() {
    const std::uint32_t lo = u16();
    const std::uint32_t hi = u16();
    return lo | (hi << 16);
  }
  std::uint64_t u64() {
    const std::uint64_t lo = u32();
    const std::uint64_t hi = u32();
    return lo | (hi << 32);
  }
  bool flag() { return (byte() & 1u) != 0; }

  /// Any bit pattern, NaNs with payloads included.
  double raw() {
    const std::uint64_t bits = u64();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }

  /// A double that is usually a small, exact grid value (so bodies meet and touch), often one
  /// of the edge cases (zero signs, denormals, huge, inf, NaN, epsilon neighbours), sometimes
  /// a wide-range or arbitrary value.
  double number() { return clampRange(anyNumber()); }

  /// Mostly a positive size on a grid (1/16 .. 16 m), otherwise any number().
  double dimension() {
    const std::uint8_t selector = byte();
    if (selector < 160) return (byte() + 1) / 16.0;
    return number();
  }

  /// Mostly a small non-negative margin (0 .. 0.5 m in 1/512 m), otherwise any number().
  double margin() {
    const std::uint8_t selector = byte();
    if (selector < 128) return byte() / 512.0;
    return number();
  }

  /// A value in [0, 1]: fractions, probabilities.
  double unit() { return byte() / 255.0; }

  /// A string of up to max_len bytes (any byte, NUL included).
  std::string text(std::size_t max_len) {
    const std::size_t n = byte() % (max_len + 1);
    std::string s;
    for (std::size_t i = 0; i < n && !empty(); ++i) s.push_back(static_cast<char>(byte()));
    return s;
  }

  /// A quaternion: unit, nearly unit (around the 1e-6 tolerance), or arbitrary.
  Eigen::Quaterniond quaternion() {
    switch (byte() % 6) {
      case 0:
        return Eigen::Quaterniond::Identity();
      case 1: {
        // Axis-angle with an arbitrary angle.
        const Eigen::Vector3d axis = vector();
        const double angle = number();
        const double n = axis.norm();
        if (!(n > 0.0) || !std::isfinite(n)) return Eigen::Quaterniond::Identity();
        return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis / n));
      }
      case 2: {
        // Normalised from four arbitrary numbers (NaN when they are all zero or huge).
        const Eigen::Quaterniond q = rawQuaternion();
        return Eigen::Quaterniond(q.coeffs() / q.coeffs().norm());
      }
      case 3:
        return rawQuaternion();
      case 4: {
        // Length 1 + k * 1e-7, k in [-128, 127]: on both sides of the 1e-6 tolerance.
        const double k = static_cast<std::int8_t>(byte());
        Eigen::Quaterniond q(Eigen::AngleAxisd(number(), Eigen::Vector3d::UnitZ()));
        q.coeffs() *= 1.0 + k * 1e-7;
        return q;
      }
      default: {
        // A unit quaternion with each coefficient nudged by up to a few ulps or more.
        Eigen::Quaterniond q(Eigen::AngleAxisd(number(), Eigen::Vector3d(1, 2, 3).normalized()));
        for (int i = 0; i < 4; ++i) {
          const int steps = static_cast<std::int8_t>(byte()) % 4;
          for (int s = 0; s < std::abs(steps); ++s) {
            q.coeffs()[i] = std::nextafter(q.coeffs()[i], steps > 0 ? 2.0 : -2.0);
          }
        }
        return q;
      }
    }
  }

  Eigen::Quaterniond rawQuaternion() {
    const double w = number();
    const double x = number();
    const double y = number();
    const double z = number();
    return Eigen::Quaterniond(w, x, y, z);
  }

  Eigen::Vector3d vector() {
    const double x = number();
    const double y = number();
    const double z = number();
    return Eigen::Vector3d(x, y, z);
  }

 private:
  double anyNumber() {
    const std::uint8_t selector = byte();
    if (selector < 64) return special(byte());
    if (selector < 176) return static_cast<std::int8_t>(byte()) / 8.0;  // [-16, 16) in 1/8 m
    if (selector < 216) {
      // A 16-bit mantissa scaled by any binary exponent: tiny to huge, denormals included.
      const int mantissa = static_cast<std::int16_t>(u16());
      const int exponent = static_cast<std::int8_t>(byte()) * 9;  // about [-1150, 1150]
      return std::ldexp(static_cast<double>(mantissa), exponent);
    }
    return raw();
  }

  // Exploration aid once a finding is known: WP_FUZZ_RANGE=R moves every finite non-zero
  // number's magnitude into [1/R, R] (NaN, infinities and zeros stay), so the fuzzer can get
  // past overflow or underflow findings to others. Unset (the default): no change.
 public:
  static double clampRange(double x) {
    static const double range = [] {
      const char* s = std::getenv("WP_FUZZ_RANGE");
      const double r = s != nullptr ? std::atof(s) : 0.0;
      return r > 1.0 ? r : 0.0;
    }();
    if (range == 0.0 || !std::isfinite(x) || x == 0.0) return x;
    const double m = std::abs(x);
    if (m > range) return std::copysign(range, x);
    if (m < 1.0 / range) return std::copysign(1.0 / range, x);
    return x;
  }

 private:
  static double special(std::uint8_t i) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    constexpr double kMax = std::numeric_limits<double>::max();
    constexpr double kMin = std::numeric_limits<double>::min();
    constexpr double kDenorm = std::numeric_limits<double>::denorm_min();
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    static const double table[] = {
        0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 2.0, 0.1, -0.1, 1e-9, -1e-9, 1e-6, 1e-3,
        10.0, 100.0, 1000.0, 1e5, -1e5, 1e9, -1e9, 1e15, 1e150, -1e150, 1e300, -1e300,
        kMax, -kMax, kMin, -kMin, kDenorm, -kDenorm, 2.2e-310, -2.2e-310, 1e-300,
        kInf, -kInf, std::numeric_limits<double>::quiet_NaN(),
        -std::numeric_limits<double>::quiet_NaN(), kEps, 1.0 - kEps / 2, 1.0 + kEps,
        3.141592653589793, 1e-12, 0.25, 60.0, 2.0 + kEps * 2, 1e5 + 1e-11, 100.0000000000001,
        1000.0000000000001, 3.4028234663852886e38, 3.4028235677973366e38, 1.1754943508222875e-38,
        1.401298464324817e-45, 16777217.0, -16777217.0, 0.30000000000000004};
    return table[i % (sizeof table / sizeof table[0])];
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// The fuzzer's whole run for one input: a `Harness` built from it, then run.
template <class Harness>
int runHarness(const std::uint8_t* data, std::size_t size) {
  Input in(data, size);
  Harness harness(in);
  harness.run();
  return 0;
}

}  // namespace wp_fuzz
