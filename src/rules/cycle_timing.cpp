#include "workspace_proximity/rules/cycle_timing.hpp"

#include <algorithm>
#include <cstdio>

namespace workspace_proximity {

void CycleTiming::add(CycleStage stage, double ms) {
  Ring& r = rings_[static_cast<int>(stage)];
  r.ms[r.next] = ms;
  r.next = (r.next + 1) % kWindow;
  r.size = std::min(r.size + 1, kWindow);
}

double CycleTiming::last(CycleStage stage) const {
  const Ring& r = rings_[static_cast<int>(stage)];
  return r.size == 0 ? 0.0 : r.ms[(r.next + kWindow - 1) % kWindow];
}

double CycleTiming::percentile(CycleStage stage, double p) const {
  const Ring& r = rings_[static_cast<int>(stage)];
  if (r.size == 0) return 0.0;
  // Off the hot path (diagnostics at 1 Hz, shutdown): a copy and a partial sort are fine.
  std::vector<double> v(r.ms.begin(), r.ms.begin() + static_cast<long>(r.size));
  const std::size_t k =
      std::min(r.size - 1, static_cast<std::size_t>(std::clamp(p, 0.0, 1.0) * (r.size - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

const char* CycleTiming::name(CycleStage stage) {
  switch (stage) {
    case CycleStage::kInput: return "input";
    case CycleStage::kNear: return "near";
    case CycleStage::kSsm: return "ssm";
    case CycleStage::kSafety: return "safety";
    case CycleStage::kPredict: return "predict";
    case CycleStage::kReport: return "report";
    case CycleStage::kContacts: return "contacts";
    case CycleStage::kMarkers: return "markers";
    case CycleStage::kArrival: return "arrival";
    case CycleStage::kTransit: return "transit";
    case CycleStage::kBroad: return "broad";
    case CycleStage::kSerialise: return "serialise";
    case CycleStage::kToSafety: return "to_safety";
    case CycleStage::kToContacts: return "to_contacts";
    default: return "?";
  }
}

std::string CycleTiming::summary() const {
  std::string out;
  for (int i = 0; i < kStages; ++i) {
    const auto s = static_cast<CycleStage>(i);
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "%s%s %.3f/%.3f/%.3f", i ? ", " : "", name(s),
                  percentile(s, 0.5), percentile(s, 0.99), percentile(s, 1.0));
    out += buffer;
  }
  return out + " ms (median/p99/max)";
}

}  // namespace workspace_proximity
