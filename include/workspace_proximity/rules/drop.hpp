#pragma once
/// Why an input was dropped: an enum with a name table, counters per reason, and the record
/// a rejection carries to whoever logs it. Diagnostics count by the enum, never by the text,
/// so rewording a message cannot move a counter.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace workspace_proximity {

enum class Drop : std::uint8_t {
  // One box of an array.
  kEmptyId = 0,     ///< the box has no id
  kNonFinite,       ///< NaN or infinity in the pose, dimensions, twist or errors
  kDimensions,      ///< an edge too small or too large
  kPosition,        ///< coordinates beyond the box limits
  kOrientation,     ///< quaternion too far from unit length
  kSpeed,           ///< linear speed beyond the limit
  kAngularSpeed,    ///< angular speed beyond the limit
  kDuplicateId,     ///< a second box with the same id in one array
  kCap,             ///< ~max_tracks reached (the box, or a farther track it replaced)
  kCoreLimits,      ///< the core refused the body (limits after the frame's transform)
  kRelabelled,      ///< a track changed label and was restarted (not lost: counted)
  // A whole array.
  kFrame,           ///< empty frame, or tf cannot reach it
  kFuture,          ///< stamped more than ~max_future ahead of the clock
  kOld,             ///< older than ~track_timeout
  kOutOfOrder,      ///< older than the previous array of the same source
  kSuperseded,      ///< a newer array of the same source arrived before it was used
  kArrayFailure,    ///< processing the array threw (a bug; logged as an error)
  kCycleFailure,    ///< a prediction cycle threw (a bug; logged as an error)
  kMessageType,     ///< a message type (or version: md5) the monitor cannot read
  kMalformed,       ///< a foreign message whose bytes do not hold its type (truncated, ...)
  kCount
};

/// The reason's name as diagnostics show it ("dropped: <name>").
const char* dropName(Drop reason);

/// One rejection, built only when something is rejected. `source` and `id` are views into the
/// caller's data, valid for the duration of the call that reports it.
struct Rejection {
  Drop reason = Drop::kCount;
  std::string_view source;  ///< input topic (or "" when not from an input)
  std::string_view id;      ///< track id (or "" for a whole array)
  std::string detail;       ///< human-readable explanation with the numbers
};

/// Told of every rejection (the ROS bridge logs it, throttled per reason; the replay records it).
class RejectionSink {
 public:
  virtual ~RejectionSink() = default;
  virtual void onRejection(const Rejection& rejection) = 0;
};

/// Counts per reason since start (never reset, so diagnostics only ever count up).
class DropCounters {
 public:
  void add(Drop reason, std::uint64_t n = 1) { counts_[index(reason)] += n; }
  std::uint64_t count(Drop reason) const { return counts_[index(reason)]; }
  std::uint64_t total() const;

 private:
  static std::size_t index(Drop reason) { return static_cast<std::size_t>(reason); }
  std::array<std::uint64_t, static_cast<std::size_t>(Drop::kCount)> counts_{};
};

}  // namespace workspace_proximity
