#pragma once
/// Tracked objects: each track key (the box id, qualified by its topic with several inputs)
/// owns one body of the ProximityWorld. The table applies the rules that turn arrays of boxes
/// into tracks: box checks, duplicate ids, the ~max_tracks cap (nearest to the robot win),
/// relabelling (restart), size hysteresis, expiry, and latency compensation. ROS-free.

#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/drop.hpp"
#include "workspace_proximity/rules/level_policy.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/rules/track_growth.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

struct Track {
  std::string key;       ///< id, qualified by the topic with several input topics
  BodyHandle handle;     ///< its body in the world
  std::string label;
  int settings = LabelTable::kDefault;  ///< index into the LabelTable
  Stamp stamp = 0;       ///< observation time of `motion`
  BodyMotion motion;     ///< in the fixed frame, at `stamp`
  Eigen::Vector3d half = Eigen::Vector3d::Zero();  ///< current shape's half extents, m
  /// Its tracker's own errors from the last box (the label's settings stay a floor). With
  /// velocity_known false, motion's linear velocity is 0 (nominal; track_growth.hpp).
  TrackErrors errors;
  double margin = 0.0;  ///< m, the margin its body has now (trackMargin, rounded up)
  std::uint64_t array_serial = 0;  ///< the last array that updated it
};

/// Where a batch of boxes came from and where it goes.
struct ArrayContext {
  std::string_view source;     ///< topic name, for rejections
  std::string_view qualifier;  ///< id prefix ("" keeps ids as they are)
  Stamp stamp = 0;             ///< observation time of every box
  Eigen::Isometry3d fixed_from_frame = Eigen::Isometry3d::Identity();
  Eigen::Vector3d robot_centre = Eigen::Vector3d::Zero();  ///< for the cap, fixed frame
};

class TrackTable {
 public:
  /// `world`, `labels`, `drops` are borrowed and must outlive the table; `sink` may be null.
  TrackTable(ProximityWorld* world, const LabelTable* labels, int max_tracks, const BoxLimits& limits,
             DropCounters* drops, RejectionSink* sink);

  /// Turns one array's boxes into tracks. Beyond ~max_tracks the boxes farthest from the
  /// robot are ignored; a new box evicts a farther track when the table is full. Rejected
  /// boxes are counted and reported; the rest are used. Returns the number of boxes used;
  /// `last_drop` (may be null) receives the reason of the last box dropped, if any.
  /// Allocation-free for known tracks.
  int ingest(const ArrayContext& array, const std::vector<BoxObservation>& boxes,
             Drop* last_drop = nullptr);
  /// Drops tracks whose stamp is older than `timeout` seconds at `now` (their pairs END).
  void expire(Stamp now, double timeout);
  /// Latency compensation: every track's body is moved from its own stamp to `now`, and its
  /// margin grows from that stamp on as its label says (track_growth.hpp).
  void advance(Stamp now);
  /// Removes every track (their pairs END at the next predict).
  void clear();
  /// The label table or the cap changed (live tuning): every track looks its settings up
  /// again and takes its label's margin (+ position_error, or its own when larger) now, its
  /// growth at advance(). A lower cap applies to arrays from now on.
  void refreshSettings(int max_tracks);

  /// Appends one line per label for tracks whose velocity is unknown while their label states
  /// no max_speed: their growth uses a fallback speed (unknownVelocitySpeed), not a motion
  /// model anyone stated, so the monitor must not call the scene clear (DEGRADED while such a
  /// track lives). Nothing is appended, and nothing allocated, when there is none.
  void unboundedLines(std::vector<std::string>* lines) const;

  int size() const { return static_cast<int>(tracks_.size()); }
  const Track& track(int i) const { return tracks_[static_cast<std::size_t>(i)]; }
  /// Index of the track owning world body slot `slot`, or -1.
  int trackOfSlot(std::int32_t slot) const {
    const auto s = static_cast<std::size_t>(slot);
    return s < track_of_slot_.size() ? track_of_slot_[s] : -1;
  }
  /// The track with this key, or -1.
  int find(const std::string& key) const;

 private:
  void reject(const ArrayContext& array, std::string_view id, Drop reason, std::string detail);
  // The boxes to consider, nearest the robot first when there are more than the cap.
  void selectNearest(const ArrayContext& array, const std::vector<BoxObservation>& boxes);
  bool evictFarther(const ArrayContext& array, double squared_distance);
  // The track for key_, the id of the box at `position` in its array (the hint first).
  int findAt(std::size_t position) const;
  // Updates track `index` (-1: a new one) from `box`; returns the track's index now.
  int update(const ArrayContext& array, int index, const BoxObservation& box);
  void add(const ArrayContext& array, const BoxObservation& box, const BodyMotion& motion);
  void remove(int index);
  void setTrackOfSlot(std::int32_t slot, int track);
  // The margin track `t` needs for its label and own position error (see kErrorStep).
  double wantedMargin(const Track& t) const;

  ProximityWorld* world_;
  const LabelTable* labels_;
  int max_tracks_;
  BoxLimits limits_;
  DropCounters* drops_;
  RejectionSink* sink_;

  // Dense (per-cycle loops walk it linearly), found by key through the index; removal swaps
  // the last track into the hole.
  std::vector<Track> tracks_;
  std::unordered_map<std::string, int> index_;
  std::vector<int> track_of_slot_;  // by world body slot; grows with the world's slots only

  // Reused by every array.
  std::vector<std::pair<double, std::size_t>> nearest_;  // squared distance, box index
  std::string key_;                                      // qualified id
  // Per position in an array: the track its box updated last time (-1: none), tried before
  // the index (findAt). Any value is safe: it is used only when its key matches.
  std::vector<int> hint_;
  std::string detail_;                                   // rejection text
  std::uint64_t array_serial_ = 0;
  Drop last_reject_ = Drop::kCount;  // reason of the last rejection (ingest reports it)
};

}  // namespace workspace_proximity
