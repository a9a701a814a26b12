#include "workspace_proximity/rules/perception_health.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace workspace_proximity {

PerceptionHealth::PerceptionHealth(std::vector<std::string> topics)
    : topics_(std::move(topics)), entries_(topics_.size()) {}

void PerceptionHealth::onStatus(int i, Stamp now, bool degraded,
                                const std::vector<std::string>& reasons, double unseen_share) {
  Entry& e = entries_[static_cast<std::size_t>(i)];
  e.received = now;
  // A front end that says degraded without saying why is still degraded.
  e.degraded = degraded || !reasons.empty();
  e.reasons = reasons;
  e.unseen_share = unseen_share;
}

void PerceptionHealth::statusLines(Stamp now, double timeout, std::vector<std::string>* lines) const {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const std::string& topic = topics_[i];
    if (e.received == 0) {
      lines->push_back("perception " + topic + ": no status yet");
      continue;
    }
    const double age = secondsBetween(e.received, now);
    if (age > timeout) {
      char text[96];
      std::snprintf(text, sizeof text, ": no status for %.2f s", age);
      lines->push_back("perception " + topic + text);
      continue;
    }
    if (!e.degraded) continue;
    if (e.reasons.empty()) lines->push_back("perception " + topic + ": degraded (no reason given)");
    for (const std::string& r : e.reasons) lines->push_back("perception " + topic + ": " + r);
  }
}

double PerceptionHealth::unseenShare(Stamp now, double timeout) const {
  constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double share = kUnknown;
  for (const Entry& e : entries_) {
    if (e.received == 0 || secondsBetween(e.received, now) > timeout) return kUnknown;
    if (!std::isfinite(e.unseen_share)) return kUnknown;
    share = std::isnan(share) ? e.unseen_share : std::max(share, e.unseen_share);
  }
  return share;
}

void PerceptionHealth::reset() {
  for (Entry& e : entries_) e = Entry();
}

}  // namespace workspace_proximity
