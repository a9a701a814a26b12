#include "workspace_proximity/rules/drop.hpp"

namespace workspace_proximity {
namespace {

// Indexed by Drop; the names are part of the diagnostics' interface ("dropped: <name>").
constexpr const char* kNames[] = {
    "empty id", "non-finite", "dimensions", "position",   "orientation",  "speed",
    "angular speed", "duplicate id", "cap", "core limits", "relabelled",  "frame",
    "future", "old", "out-of-order", "superseded", "array failure", "cycle failure",
    "message type", "malformed"};
static_assert(sizeof(kNames) / sizeof(kNames[0]) == static_cast<std::size_t>(Drop::kCount),
              "one name per Drop reason");

}  // namespace

const char* dropName(Drop reason) {
  const auto i = static_cast<std::size_t>(reason);
  return i < static_cast<std::size_t>(Drop::kCount) ? kNames[i] : "unknown";
}

std::uint64_t DropCounters::total() const {
  std::uint64_t sum = 0;
  for (std::uint64_t c : counts_) sum += c;
  return sum;
}

}  // namespace workspace_proximity
