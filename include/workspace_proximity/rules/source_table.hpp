#pragma once
/// The input sources (tracker topics): when each last sent something, its rate, and the
/// array-level rules (too far in the future, too old, out of order, silent).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "workspace_proximity/rules/drop.hpp"
#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

struct Source {
  std::string name;       ///< resolved topic name
  std::string qualifier;  ///< prefix for track ids ("" with the single default topic)
  Stamp last_receipt = 0; ///< clock when the last array arrived (0: never)
  Stamp last_stamp = 0;   ///< header stamp of the last array used (0: none yet)
  double rate = 0.0;      ///< Hz, smoothed over the intervals between arrivals
  std::uint64_t arrays = 0;  ///< arrays received
  /// Clock when an array of this source last gave the monitor data (at least one box used, or
  /// an empty scene); 0: never. A source whose arrays all get dropped is as silent as one that
  /// sends nothing.
  Stamp last_used = 0;
  Drop last_drop = Drop::kCount;  ///< why its last dropped array or box was dropped
  /// Why its last message's type was refused (an unknown type or md5); empty when its last
  /// message was of a type the monitor reads.
  std::string refused_type;
};

class SourceTable {
 public:
  /// `names`: resolved topic names. With `qualify`, track ids become "<name>/<id>" so two
  /// trackers' track 7 stay apart.
  SourceTable(const std::vector<std::string>& names, bool qualify);

  int size() const { return static_cast<int>(sources_.size()); }
  const Source& source(int i) const { return sources_[static_cast<std::size_t>(i)]; }

  /// An array arrived at `now`: counts it and updates the rate.
  void noteReceipt(int i, Stamp now);
  /// Drop::kCount when an array stamped `stamp` may be used at `now`; otherwise kFuture (more
  /// than max_future ahead), kOld (older than track_timeout) or kOutOfOrder (older than the
  /// last array used), with the explanation in `*detail`.
  Drop checkStamp(int i, Stamp stamp, Stamp now, double max_future, double track_timeout,
                  std::string* detail) const;
  /// The array stamped `stamp` is being used.
  void accept(int i, Stamp stamp) { sources_[static_cast<std::size_t>(i)].last_stamp = stamp; }
  /// An array of source i gave data at `when` (its receipt).
  void markUsed(int i, Stamp when) { sources_[static_cast<std::size_t>(i)].last_used = when; }
  /// Something of source i was dropped for `reason`.
  void noteDrop(int i, Drop reason) { sources_[static_cast<std::size_t>(i)].last_drop = reason; }
  /// Source i's messages are of a type refused for `why` ("" : of a readable type again).
  void setRefusedType(int i, std::string why) {
    sources_[static_cast<std::size_t>(i)].refused_type = std::move(why);
  }

  /// One status line per source whose messages are of a refused type, and one per source
  /// that never sent anything, has been silent for more than
  /// `silent_after` seconds at `now`, or whose arrays have all been dropped for that long,
  /// appended to `lines`.
  /// `track_timeout` (s): a source whose newest used array is stamped longer ago than this is
  /// silent too (its tracks, which expire by stamp, are gone).
  void silentLines(Stamp now, double silent_after, double track_timeout,
                   std::vector<std::string>* lines) const;

  /// Forgets receipts, stamps and rates (after the clock went back).
  void reset();

 private:
  std::vector<Source> sources_;
};

}  // namespace workspace_proximity
