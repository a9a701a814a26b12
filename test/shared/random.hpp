#pragma once
// Random numbers for tests, benchmarks and the demo: one seeded engine, the draws they need.
// Reproducible: the same seed gives the same sequence on every run and machine (std::mt19937
// and the standard distributions' algorithms as implemented by libstdc++).

#include <cstdint>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace wp_test {

/// Also a uniform random bit generator itself, so the standard distributions take it.
class Rng {
 public:
  using result_type = std::mt19937::result_type;

  explicit Rng(std::uint32_t seed) : engine_(seed) {}

  static constexpr result_type min() { return std::mt19937::min(); }
  static constexpr result_type max() { return std::mt19937::max(); }
  result_type operator()() { return engine_(); }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  /// Uniform integer in [lo, hi].
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine_); }
  /// True with probability p.
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  /// Each component uniform in [lo, hi).
  Eigen::Vector3d vector(double lo, double hi) {
    // Each draw its own statement: the order of evaluation of arguments is unspecified.
    const double x = uniform(lo, hi);
    const double y = uniform(lo, hi);
    const double z = uniform(lo, hi);
    return Eigen::Vector3d(x, y, z);
  }
  /// Uniformly distributed rotation (normalised Gaussian quaternion).
  Eigen::Quaterniond rotation() {
    std::normal_distribution<double> n(0.0, 1.0);
    const double w = n(engine_);
    const double x = n(engine_);
    const double y = n(engine_);
    const double z = n(engine_);
    return Eigen::Quaterniond(w, x, y, z).normalized();
  }
  /// Turn about the vertical by a uniform angle in [-pi, pi).
  Eigen::Quaterniond yaw() { return yaw(uniform(-M_PI, M_PI)); }
  static Eigen::Quaterniond yaw(double angle) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
  }

  /// The engine, for other distributions.
  std::mt19937& engine() { return engine_; }

 private:
  std::mt19937 engine_;
};

}  // namespace wp_test
