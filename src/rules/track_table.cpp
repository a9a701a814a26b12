#include "workspace_proximity/rules/track_table.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "workspace_proximity/rules/track_growth.hpp"

namespace workspace_proximity {
namespace {

// Grow at once (never smaller than the truth); shrink only when clearly smaller, so a
// tracker's jittering dimensions do not rebuild the geometry every message.
bool needsResize(const Eigen::Vector3d& current, const Eigen::Vector3d& wanted) {
  constexpr double kShrinkSlack = 0.05;  // m
  return (wanted.array() > current.array()).any() ||
         (wanted.array() < current.array() - kShrinkSlack).any();
}

// A tracker's own position error changes a little with every box (a filter's covariance).
// Rounded up to this step and shrunk only when this much smaller, so the margin is never
// below the error and the body is not reshaped every message.
constexpr double kErrorStep = 0.01;         // m
constexpr double kMarginShrinkSlack = 0.02;  // m

TrackErrors errorsOf(const BoxObservation& box) {
  TrackErrors e;
  e.position_error = box.position_error;
  e.velocity_error = box.velocity_error;
  e.velocity_known = box.velocity_known;
  return e;
}

}  // namespace

TrackTable::TrackTable(ProximityWorld* world, const LabelTable* labels, int max_tracks,
                       const BoxLimits& limits, DropCounters* drops, RejectionSink* sink)
    : world_(world), labels_(labels), max_tracks_(max_tracks), limits_(limits), drops_(drops),
      sink_(sink) {}

void TrackTable::reject(const ArrayContext& array, std::string_view id, Drop reason,
                        std::string detail) {
  drops_->add(reason);
  last_reject_ = reason;
  if (sink_ != nullptr) sink_->onRejection(Rejection{reason, array.source, id, std::move(detail)});
}

int TrackTable::find(const std::string& key) const {
  const auto it = index_.find(key);
  return it == index_.end() ? -1 : it->second;
}

int TrackTable::findAt(std::size_t position) const {
  // Trackers send their boxes in much the same order every time: the track that the box at
  // this position of the array updated last time is tried first, one key comparison on a
  // dense array walked in order, and the hash index (a few cache misses per box, the input
  // path's largest cost at 1 000 boxes) only when it is another.
  if (position < hint_.size()) {
    const int hint = hint_[position];
    if (hint >= 0 && hint < size() && tracks_[static_cast<std::size_t>(hint)].key == key_) return hint;
  }
  return find(key_);
}

void TrackTable::selectNearest(const ArrayContext& array, const std::vector<BoxObservation>& boxes) {
  nearest_.clear();
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const double d =
        (array.fixed_from_frame * boxes[i].position - array.robot_centre).squaredNorm();
    nearest_.emplace_back(std::isfinite(d) ? d : HUGE_VAL, i);
  }
  // Too many boxes: keep the ones nearest the robot (they matter first) and say so.
  const auto room = static_cast<std::size_t>(max_tracks_);
  if (nearest_.size() <= room) return;
  std::nth_element(nearest_.begin(), nearest_.begin() + static_cast<long>(room), nearest_.end());
  const std::size_t ignored = nearest_.size() - room;
  drops_->add(Drop::kCap, ignored);
  if (sink_ != nullptr) {
    sink_->onRejection(Rejection{
        Drop::kCap, array.source, std::string_view(),
        std::to_string(nearest_.size()) + " boxes exceed ~max_tracks = " +
            std::to_string(max_tracks_) + "; the " + std::to_string(ignored) +
            " farthest from the robot are ignored"});
  }
  nearest_.resize(room);
}

int TrackTable::ingest(const ArrayContext& array, const std::vector<BoxObservation>& boxes,
                       Drop* last_drop) {
  last_reject_ = Drop::kCount;
  int used = 0;
  selectNearest(array, boxes);
  // Every track updated from this array is marked with its serial: a second box with the
  // same id finds the mark (duplicate) without a per-array set of ids.
  ++array_serial_;
  for (const auto& entry : nearest_) {
    const BoxObservation& box = boxes[entry.second];
    const Drop why = checkBox(box, limits_, &detail_);
    if (why != Drop::kCount) {
      reject(array, box.id, why, detail_);
      continue;
    }
    if (array.qualifier.empty()) {
      key_.assign(box.id);
    } else {
      key_.assign(array.qualifier).append("/").append(box.id);
    }
    const int index = findAt(entry.second);
    if (index >= 0 && tracks_[static_cast<std::size_t>(index)].array_serial == array_serial_) {
      reject(array, box.id, Drop::kDuplicateId, "duplicate id in one array; the first is used");
      continue;
    }
    if (index < 0 && size() >= max_tracks_ && !evictFarther(array, entry.first)) {
      reject(array, box.id, Drop::kCap,
             "~max_tracks reached and every kept track is nearer the robot");
      continue;
    }
    try {
      const int updated = update(array, index, box);
      if (entry.second >= hint_.size()) hint_.resize(entry.second + 1, -1);  // the largest array's size
      hint_[entry.second] = updated;
      ++used;
    } catch (const std::exception& e) {
      // The core's own limits (e.g. a pose that the frame's transform carries past them):
      // drop the box, never the array or the node.
      reject(array, box.id, Drop::kCoreLimits, std::string("rejected by the core: ") + e.what());
    }
  }
  if (last_drop != nullptr) *last_drop = last_reject_;
  return used;
}

bool TrackTable::evictFarther(const ArrayContext& array, double squared_distance) {
  // At the cap, the track farthest from the robot (at its last observed position) gives way
  // to a nearer newcomer, whichever source it came from.
  int farthest = -1;
  double worst = squared_distance;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const double d = (tracks_[i].motion.position - array.robot_centre).squaredNorm();
    if (d > worst) {
      worst = d;
      farthest = static_cast<int>(i);
    }
  }
  if (farthest < 0) return false;
  const Track& t = tracks_[static_cast<std::size_t>(farthest)];
  reject(array, t.key, Drop::kCap,
         "~max_tracks = " + std::to_string(max_tracks_) +
             " reached; this track, the farthest from the robot, gives way to a nearer one");
  remove(farthest);
  return true;
}

int TrackTable::update(const ArrayContext& array, int index, const BoxObservation& box) {
  const BodyMotion motion = boxMotion(box, array.fixed_from_frame);
  if (index >= 0 && tracks_[static_cast<std::size_t>(index)].label != box.label) {
    // A new class means new settings (margin, thresholds): restart the track, so its pairs
    // END and BEGIN again under the new label.
    const Track& t = tracks_[static_cast<std::size_t>(index)];
    reject(array, box.id, Drop::kRelabelled,
           "changed label '" + t.label + "' -> '" + std::string(box.label) + "'; restarted");
    remove(index);
    index = -1;
  }
  if (index < 0) {
    add(array, box, motion);
    return size() - 1;
  }
  Track& t = tracks_[static_cast<std::size_t>(index)];
  t.array_serial = array_serial_;
  if (array.stamp < t.stamp) return index;  // older than what we have
  t.stamp = array.stamp;
  t.motion = motion;
  t.errors = errorsOf(box);
  // No velocity yet: predicted standing still, grown at the label's speed (track_growth.hpp).
  if (!t.errors.velocity_known) t.motion.linear_velocity.setZero();
  const Shape shape = boxShape(box);
  const bool resize = needsResize(t.half, shape.half_extents);
  const double wanted = wantedMargin(t);
  const bool remargin = wanted > t.margin || wanted < t.margin - kMarginShrinkSlack;
  if (resize || remargin) {
    const double margin = remargin ? wanted : t.margin;
    world_->setShape(t.handle, resize ? shape : world_->desc(t.handle).shape, margin);
    if (resize) t.half = shape.half_extents;
    t.margin = margin;
  }
  return index;
}

double TrackTable::wantedMargin(const Track& t) const {
  const LabelSettings& label = labels_->settings(t.settings);
  double own = t.errors.position_error;
  if (own > label.position_error) own = std::ceil(own / kErrorStep) * kErrorStep;
  return trackMargin(label, own);
}

void TrackTable::add(const ArrayContext& array, const BoxObservation& box, const BodyMotion& motion) {
  Track t;
  t.key = key_;
  t.label = std::string(box.label);
  t.settings = labels_->indexOf(t.label);
  t.stamp = array.stamp;
  t.motion = motion;
  t.errors = errorsOf(box);
  if (!t.errors.velocity_known) t.motion.linear_velocity.setZero();
  const Shape shape = boxShape(box);
  t.half = shape.half_extents;
  t.array_serial = array_serial_;
  t.margin = wantedMargin(t);
  t.handle = world_->addBody(BodyDesc{t.key, t.label, BodyGroup::kObject, shape, t.margin},
                             t.motion);
  const int added = size();
  setTrackOfSlot(t.handle.index, added);
  index_.emplace(t.key, added);
  tracks_.push_back(std::move(t));
}

void TrackTable::remove(int index) {
  // Swap-and-pop keeps the tracks dense; the moved track's index entries follow it.
  const auto i = static_cast<std::size_t>(index);
  setTrackOfSlot(tracks_[i].handle.index, -1);
  world_->removeBody(tracks_[i].handle);
  index_.erase(tracks_[i].key);
  if (i + 1 != tracks_.size()) {
    tracks_[i] = std::move(tracks_.back());
    index_[tracks_[i].key] = index;
    setTrackOfSlot(tracks_[i].handle.index, index);
  }
  tracks_.pop_back();
}

void TrackTable::expire(Stamp now, double timeout) {
  // Backwards: remove() moves the last track into the hole, which was visited already.
  for (std::size_t i = tracks_.size(); i-- > 0;) {
    if (secondsBetween(tracks_[i].stamp, now) > timeout) remove(static_cast<int>(i));
  }
}

void TrackTable::advance(Stamp now) {
  for (const Track& t : tracks_) {
    const double age = secondsBetween(t.stamp, now);
    world_->setMotion(t.handle, t.motion.advanced(age));
    // The uncertainty has grown since the measurement, not since now: the margin at the
    // prediction instant is already R(age) wider (the label's settings are looked up every
    // cycle, so live tuning applies at once; no growth: today's prediction, bit for bit).
    world_->setGrowth(t.handle, trackGrowth(labels_->settings(t.settings),
                                            t.motion.linear_velocity.norm(), age, t.errors));
  }
}

void TrackTable::clear() {
  for (const Track& t : tracks_) world_->removeBody(t.handle);
  for (const Track& t : tracks_) setTrackOfSlot(t.handle.index, -1);
  tracks_.clear();
  index_.clear();
}

void TrackTable::refreshSettings(int max_tracks) {
  max_tracks_ = max_tracks;
  for (Track& t : tracks_) {
    t.settings = labels_->indexOf(t.label);
    const double margin = wantedMargin(t);
    const BodyDesc& desc = world_->desc(t.handle);
    if (margin != desc.margin) world_->setShape(t.handle, desc.shape, margin);
    t.margin = margin;
  }
}

void TrackTable::setTrackOfSlot(std::int32_t slot, int track) {
  const auto s = static_cast<std::size_t>(slot);
  if (s >= track_of_slot_.size()) track_of_slot_.resize(s + 1, -1);  // grows with the world
  track_of_slot_[s] = track;
}

void TrackTable::unboundedLines(std::vector<std::string>* lines) const {
  // Walks the dense table each cycle; the common case (every velocity known, or every label
  // with a max_speed) touches no string.
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const Track& t = tracks_[i];
    if (t.errors.velocity_known || labels_->settings(t.settings).max_speed > 0.0) continue;
    bool counted = false;  // one line per label: an earlier track of the same label had it
    for (std::size_t j = 0; j < i && !counted; ++j) {
      const Track& u = tracks_[j];
      counted = !u.errors.velocity_known && u.settings == t.settings;
    }
    if (counted) continue;
    int count = 0;
    for (std::size_t j = i; j < tracks_.size(); ++j) {
      const Track& u = tracks_[j];
      if (!u.errors.velocity_known && u.settings == t.settings) ++count;
    }
    lines->push_back("velocity unknown for " + std::to_string(count) + " track" +
                     (count == 1 ? "" : "s") + " of label '" + t.label + "' (first: " + t.key +
                     ") whose label has no max_speed: their reach is not bounded by any stated "
                     "motion model (set labels/" + t.label + "/max_speed)");
  }
}

}  // namespace workspace_proximity
