#pragma once
// Another version's SweepAndPrune (say main's, before a change), built from that version's
// source tree in its own namespace so that broadphase_bench can run it in the same process as
// the current one. Only built when CMake is given WP_BENCH_BASELINE=<source tree>
// (bench/CMakeLists.txt); this header names none of the core's types, so that both versions'
// headers never meet in one translation unit.

#include <cstddef>
#include <cstdint>
#include <memory>

namespace wp_bench {

class BaselineSap {
 public:
  BaselineSap();
  ~BaselineSap();
  BaselineSap(const BaselineSap&) = delete;
  BaselineSap& operator=(const BaselineSap&) = delete;

  /// The baseline's createProxy / destroyProxy / moveProxy / update with bounds as
  /// {lower x, y, z, upper x, y, z}.
  std::int32_t create(const double* bounds);
  void destroy(std::int32_t proxy);
  void move(std::int32_t proxy, const double* bounds);
  void update();
  /// Its pairs(): `count` pairs, pair i at data[i * stride] (proxy_a) and data[i * stride + 1]
  /// (proxy_b), stride in int32 units.
  const std::int32_t* pairs(std::size_t* count, std::size_t* stride) const;
  /// Its stats().rebuilt.
  bool rebuilt() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wp_bench
