// Built with workspace_proximity defined as wp_baseline and only the baseline's include folder
// (bench/CMakeLists.txt): every name below that says workspace_proximity is the baseline's.

#include "baseline_sap.hpp"

#include <cstddef>
#include <type_traits>

#include "workspace_proximity/sweep_and_prune.hpp"

namespace wp_bench {

struct BaselineSap::Impl {
  workspace_proximity::SweepAndPrune sap;
};

BaselineSap::BaselineSap() : impl_(std::make_unique<Impl>()) {}
BaselineSap::~BaselineSap() = default;

namespace {
workspace_proximity::Aabb box(const double* b) {
  workspace_proximity::Aabb a;
  a.lower = Eigen::Vector3d(b[0], b[1], b[2]);
  a.upper = Eigen::Vector3d(b[3], b[4], b[5]);
  return a;
}
}  // namespace

std::int32_t BaselineSap::create(const double* bounds) { return impl_->sap.createProxy(box(bounds)); }
void BaselineSap::destroy(std::int32_t proxy) { impl_->sap.destroyProxy(proxy); }
void BaselineSap::move(std::int32_t proxy, const double* bounds) { impl_->sap.moveProxy(proxy, box(bounds)); }
void BaselineSap::update() { impl_->sap.update(); }

const std::int32_t* BaselineSap::pairs(std::size_t* count, std::size_t* stride) const {
  const auto& p = impl_->sap.pairs();
  using Pair = std::decay_t<decltype(p[0])>;
  static_assert(sizeof(Pair) % sizeof(std::int32_t) == 0, "pairs are made of int32 fields");
  static_assert(offsetof(Pair, proxy_a) == 0 && offsetof(Pair, proxy_b) == sizeof(std::int32_t),
                "proxy_a, proxy_b first");
  *count = p.size();
  *stride = sizeof(Pair) / sizeof(std::int32_t);
  return p.empty() ? nullptr : &p[0].proxy_a;
}

bool BaselineSap::rebuilt() const { return impl_->sap.stats().rebuilt; }

}  // namespace wp_bench
