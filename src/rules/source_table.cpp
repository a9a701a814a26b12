#include "workspace_proximity/rules/source_table.hpp"

#include "workspace_proximity/rules/format.hpp"

namespace workspace_proximity {

SourceTable::SourceTable(const std::vector<std::string>& names, bool qualify) {
  sources_.resize(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    sources_[i].name = names[i];
    sources_[i].qualifier = qualify ? names[i] : std::string();
  }
}

void SourceTable::noteReceipt(int i, Stamp now) {
  Source& s = sources_[static_cast<std::size_t>(i)];
  if (s.last_receipt != 0 && now > s.last_receipt) {
    // Smooth the interval, not its inverse: the mean of 1 / interval overstates the rate
    // (arrays arriving in pairs 5 ms apart at 20 per second read as 100 Hz).
    const double interval = secondsBetween(s.last_receipt, now);
    s.rate = s.rate == 0.0 ? 1.0 / interval : 1.0 / (0.9 / s.rate + 0.1 * interval);
  }
  s.last_receipt = now;
  ++s.arrays;
}

Drop SourceTable::checkStamp(int i, Stamp stamp, Stamp now, double max_future,
                             double track_timeout, std::string* detail) const {
  const Source& s = sources_[static_cast<std::size_t>(i)];
  const double ahead = secondsBetween(now, stamp);
  if (ahead > max_future) {
    *detail = format("stamped %.3f s in the future (clocks out of sync?)", ahead);
    return Drop::kFuture;
  }
  if (-ahead > track_timeout) {
    *detail = format("%.3f s old (> ~track_timeout)", -ahead);
    return Drop::kOld;
  }
  if (s.last_stamp != 0 && stamp < s.last_stamp) {
    *detail = "older than the previous one";
    return Drop::kOutOfOrder;
  }
  return Drop::kCount;
}

void SourceTable::silentLines(Stamp now, double silent_after, double track_timeout,
                              std::vector<std::string>* lines) const {
  for (const Source& s : sources_) {
    // A type it cannot read: DEGRADED for as long as the messages keep coming in it.
    if (!s.refused_type.empty()) lines->push_back("source " + s.name + ": " + s.refused_type);
    if (s.last_receipt == 0) {
      lines->push_back("source " + s.name + ": no data yet");
    } else if (secondsBetween(s.last_receipt, now) > silent_after) {
      lines->push_back("source " + s.name +
                       format(": no data for %.2f s", secondsBetween(s.last_receipt, now)));
    } else if (s.last_stamp != 0 && secondsBetween(s.last_stamp, now) > track_timeout) {
      // Its tracks expire by their stamps, which lag the arrays' arrival by the tracker's
      // latency: on the same clock, so that an emptied scene is never read as clear.
      lines->push_back("source " + s.name +
                       format(": newest array stamped %.2f s ago (> ~track_timeout)",
                              secondsBetween(s.last_stamp, now)));
    } else if (s.last_used == 0 || secondsBetween(s.last_used, now) > silent_after) {
      // Arrays arrive but none is used (an unreachable frame, bad stamps, only bad boxes):
      // as unknown as silence.
      const std::string why = s.last_drop == Drop::kCount ? std::string("?") : dropName(s.last_drop);
      lines->push_back("source " + s.name +
                       (s.last_used == 0
                            ? std::string(": arrays arrive but none could be used yet")
                            : format(": arrays arrive but none used for %.2f s",
                                     secondsBetween(s.last_used, now))) +
                       " (dropped: " + why + ")");
    }
  }
}

void SourceTable::reset() {
  for (Source& s : sources_) {
    s.last_receipt = 0;
    s.last_stamp = 0;
    s.last_used = 0;
    s.rate = 0.0;
  }
}

}  // namespace workspace_proximity
