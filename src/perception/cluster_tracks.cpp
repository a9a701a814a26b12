#include "workspace_proximity/perception/cluster_tracks.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace workspace_proximity {
namespace perception {
namespace {

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }
constexpr double kHuge = 1e300;

// The tracker's parameters with the clusters' one label.
TrackerParams trackerParams(const ClusterTrackParams& p) {
  TrackerParams t = p.tracker;
  TrackerLabel label;
  label.name = p.label;
  label.max_accel = p.max_accel;
  label.max_speed = p.max_speed;
  t.labels = {label};
  return t;
}

const ClusterTrackParams& checked(const ClusterTrackParams& p) {
  const std::vector<std::string> problems = validate(p);
  if (!problems.empty()) throw std::invalid_argument("cluster tracks: " + problems.front());
  return p;
}

}  // namespace

std::vector<std::string> validate(const ClusterTrackParams& p) {
  std::vector<std::string> problems;
  if (p.label.empty()) problems.push_back("label must not be empty");
  if (!(std::isfinite(p.max_accel) && p.max_accel >= 0.0)) {
    problems.push_back("max_accel must be finite and >= 0 m/s^2");
  }
  if (!finitePositive(p.max_speed)) problems.push_back("max_speed must be finite and > 0 m/s");
  if (!finitePositive(p.sigma)) problems.push_back("sigma must be finite and > 0 m");
  if (!(std::isfinite(p.max_merge_gap) && p.max_merge_gap >= 0.0)) {
    problems.push_back("max_merge_gap must be finite and >= 0 s");
  }
  if (!(std::isfinite(p.fragment_gap) && p.fragment_gap >= 0.0 && p.fragment_gap <= 10.0)) {
    problems.push_back("fragment_gap must be within [0, 10] m");
  }
  if (p.sensors < 1 || p.sensors > 1000) problems.push_back("sensors must be in [1, 1000]");
  for (const std::string& s : validate(trackerParams(p))) problems.push_back("tracker: " + s);
  return problems;
}

ClusterTracks::ClusterTracks(const ClusterTrackParams& params)
    : params_(checked(params)), tracker_(trackerParams(params_)) {
  detections_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  parent_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  lo_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  hi_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  first_in_track_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
  tight_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  track_lo_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
  track_hi_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
  tight_lo_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
  tight_hi_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
  const auto cells = static_cast<std::size_t>(params_.tracker.capacity) * static_cast<std::size_t>(params_.sensors);
  sight_id_.assign(cells, 0);
  sight_stamp_.assign(cells, 0);
  sight_min_.assign(cells, Eigen::Vector3d::Zero());
  sight_max_.assign(cells, Eigen::Vector3d::Zero());
  core_min_.assign(cells, Eigen::Vector3d::Zero());
  core_max_.assign(cells, Eigen::Vector3d::Zero());
  core_lo_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  core_hi_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
  sensor_stamp_.assign(static_cast<std::size_t>(params_.sensors), -1);
  output_.reserve(static_cast<std::size_t>(params_.tracker.capacity));
}

ClusterFrameUse ClusterTracks::update(Stamp stamp, const std::vector<Detection>& clusters, int sensor) {
  if (sensor < 0 || sensor >= params_.sensors) throw std::out_of_range("cluster tracks: sensor index out of range");
  // A frame older than the tracker's newest: applied at that newer stamp, since the filter
  // cannot go back; in the gap the object moved at most max_speed x gap, taken as 3 sigma.
  double sigma = params_.sigma;
  ClusterFrameUse use = ClusterFrameUse::kUsed;
  if (tracker_.stamp() != 0 && stamp < tracker_.stamp()) {
    const double gap = secondsBetween(stamp, tracker_.stamp());
    if (gap > params_.max_merge_gap) {
      ++too_late_;
      return ClusterFrameUse::kTooLate;
    }
    const double moved = params_.max_speed * gap / 3.0;
    sigma = std::sqrt(sigma * sigma + moved * moved);
    stamp = tracker_.stamp();
    use = ClusterFrameUse::kLate;
    ++late_;
  }
  detections_.clear();
  const std::size_t n = std::min(clusters.size(), detections_.capacity());
  for (std::size_t i = 0; i < n; ++i) {
    workspace_proximity::Detection& d = detections_.emplace_back();
    d.position = clusters[i].centre.cast<double>();
    d.dimensions = clusters[i].size.cast<double>();
    d.label = 0;
    d.sigma = sigma;
  }
  // Clusters beyond the tracker's max_detections are counted, never silently lost (the
  // node reports them; CloudFrame's max_clusters is the same 512 by default).
  overflow_ += static_cast<long>(clusters.size() - n);
  mergeFragments(stamp);  // also with both merges off: it notes each detection's core
  tracker_.update(stamp, detections_);
  unite(sensor, stamp);
  return use;
}

int ClusterTracks::root(int i) {
  while (parent_[static_cast<std::size_t>(i)] != i) {
    const auto k = static_cast<std::size_t>(i);
    parent_[k] = parent_[static_cast<std::size_t>(parent_[k])];  // path halving
    i = parent_[k];
  }
  return i;
}

void ClusterTracks::linkWithinTracks(Stamp stamp) {
  // The live tracks after the last frame: each one's cores (the largest cluster of what each
  // sensor's latest frame gave it, where it was seen), not its published box, which holds
  // what earlier merges took in: a box re-centred on what it took in, with an allowance every
  // frame, would follow anything moving away at up to allowance / period (a person walking
  // away from the forklift dragging its box along).
  if (output_.empty() || tracker_.stamp() == 0) return;
  const auto sensors = static_cast<std::size_t>(params_.sensors);
  const int n = static_cast<int>(detections_.size());
  first_in_track_.assign(output_.size(), -1);  // within the reserved capacity
  // Each track's footprint once per frame: its cores moved by its velocity when known, grown
  // by its 3 sigma position error and what it may have moved beyond that (velocity error, or
  // max_speed) since each was seen; and the tight one, grown by the latter alone.
  track_lo_.clear();  // within the reserved capacity
  track_hi_.clear();
  tight_lo_.clear();
  tight_hi_.clear();
  for (std::size_t i = 0; i < output_.size(); ++i) {
    const BoxObservation& b = tracker_.tracks()[i];  // the filter's
    const int slot = tracker_.outputSlot(static_cast<int>(i));
    const std::uint64_t id = tracker_.idOfSlot(slot);
    const double speed = b.velocity_known ? b.velocity_error : params_.max_speed;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(kHuge), hi = -lo;
    Eigen::Vector3d tight_lo = lo, tight_hi = hi;
    for (std::size_t o = 0; o < sensors; ++o) {
      const std::size_t c = static_cast<std::size_t>(slot) * sensors + o;
      if (sight_id_[c] != id || sight_stamp_[c] != sensor_stamp_[o]) continue;
      const double dt = std::max(0.0, secondsBetween(sight_stamp_[c], stamp));
      const Eigen::Vector3d shift = b.velocity_known ? Eigen::Vector3d(b.linear_velocity * dt)
                                                     : Eigen::Vector3d::Zero();
      const double grow = b.position_error + speed * dt;
      lo = lo.cwiseMin(core_min_[c] + shift - Eigen::Vector3d::Constant(grow));
      hi = hi.cwiseMax(core_max_[c] + shift + Eigen::Vector3d::Constant(grow));
      tight_lo = tight_lo.cwiseMin(core_min_[c] + shift - Eigen::Vector3d::Constant(speed * dt));
      tight_hi = tight_hi.cwiseMax(core_max_[c] + shift + Eigen::Vector3d::Constant(speed * dt));
    }
    track_lo_.push_back(lo);  // lo > hi: no sensor's latest frame saw it (holds nothing)
    track_hi_.push_back(hi);
    tight_lo_.push_back(tight_lo);
    tight_hi_.push_back(tight_hi);
  }
  for (int j = 0; j < n; ++j) {
    const auto k = static_cast<std::size_t>(j);
    // The oldest track (smallest id) whose footprint holds the detection's whole.
    int owner = -1;
    std::uint64_t owner_id = 0;
    bool owner_tight = false;
    for (std::size_t i = 0; i < output_.size(); ++i) {
      bool inside = true;
      for (int a = 0; a < 2 && inside; ++a) {
        inside = lo_[k][a] >= track_lo_[i][a] && hi_[k][a] <= track_hi_[i][a];
      }
      if (!inside) continue;
      const std::uint64_t id = tracker_.idOfSlot(tracker_.outputSlot(static_cast<int>(i)));
      if (owner < 0 || id < owner_id) {
        owner = static_cast<int>(i);
        owner_id = id;
        owner_tight = true;
        for (int a = 0; a < 2 && owner_tight; ++a) {
          owner_tight = lo_[k][a] >= tight_lo_[i][a] && hi_[k][a] <= tight_hi_[i][a];
        }
      }
    }
    if (owner < 0) continue;
    tight_[k] = owner_tight ? 1 : 0;
    int& first = first_in_track_[static_cast<std::size_t>(owner)];
    if (first < 0) {
      first = j;
    } else if (root(j) != root(first)) {
      parent_[static_cast<std::size_t>(root(j))] = root(first);
      ++merged_within_tracks_;
    }
  }
}

void ClusterTracks::mergeFragments(Stamp stamp) {
  const int n = static_cast<int>(detections_.size());
  parent_.resize(detections_.size());
  lo_.resize(detections_.size());
  hi_.resize(detections_.size());
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    parent_[k] = i;
    lo_[k] = detections_[k].position - 0.5 * detections_[k].dimensions;
    hi_[k] = detections_[k].position + 0.5 * detections_[k].dimensions;
  }
  tight_.assign(detections_.size(), 0);  // within the reserved capacity
  // Every pair (n^2 / 2 footprint tests: 130 000 at the 512 clusters' capacity).
  for (int i = 0; i < n && params_.merge_fragments; ++i) {
    const auto a = static_cast<std::size_t>(i);
    for (int j = i + 1; j < n; ++j) {
      const auto b = static_cast<std::size_t>(j);
      const bool near = lo_[b].x() - hi_[a].x() <= params_.fragment_gap &&
                        lo_[a].x() - hi_[b].x() <= params_.fragment_gap &&
                        lo_[b].y() - hi_[a].y() <= params_.fragment_gap &&
                        lo_[a].y() - hi_[b].y() <= params_.fragment_gap;
      if (near) parent_[static_cast<std::size_t>(root(j))] = root(i);
    }
  }
  if (params_.merge_within_tracks) linkWithinTracks(stamp);
  // Each root's core: its largest member's box (by footprint area), before the union, with
  // the members that lay inside the track's last cores grown by its velocity error (or
  // max_speed) only: so a core grows no faster than the track's stated motion, while what the
  // position error's allowance took in stays out of it (and cannot drag it along).
  core_lo_.assign(lo_.begin(), lo_.end());  // within the reserved capacity
  core_hi_.assign(hi_.begin(), hi_.end());
  auto area = [](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (hi.x() - lo.x()) * (hi.y() - lo.y());
  };
  for (int i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(root(i));
    const auto k = static_cast<std::size_t>(i);
    if (area(lo_[k], hi_[k]) > area(core_lo_[r], core_hi_[r])) {
      core_lo_[r] = lo_[k];
      core_hi_[r] = hi_[k];
    }
  }
  for (int i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(root(i));
    const auto k = static_cast<std::size_t>(i);
    if (!tight_[k]) continue;
    core_lo_[r] = core_lo_[r].cwiseMin(lo_[k]);
    core_hi_[r] = core_hi_[r].cwiseMax(hi_[k]);
  }
  // Each root takes its members' union; the detections are then the roots, in order.
  for (int i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(root(i));
    const auto k = static_cast<std::size_t>(i);
    lo_[r] = lo_[r].cwiseMin(lo_[k]);
    hi_[r] = hi_[r].cwiseMax(hi_[k]);
  }
  std::size_t out = 0;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (parent_[k] != i) continue;
    core_lo_[out] = core_lo_[k];
    core_hi_[out] = core_hi_[k];
    workspace_proximity::Detection& d = detections_[out++];
    d = detections_[k];
    d.position = 0.5 * (lo_[k] + hi_[k]);
    d.dimensions = hi_[k] - lo_[k];
  }
  detections_.resize(out);
  core_lo_.resize(out);
  core_hi_.resize(out);
}

void ClusterTracks::unite(int sensor, Stamp stamp) {
  const auto sensors = static_cast<std::size_t>(params_.sensors);
  sensor_stamp_[static_cast<std::size_t>(sensor)] = stamp;
  const std::vector<BoxObservation>& tracks = tracker_.tracks();
  output_.assign(tracks.begin(), tracks.end());  // within the reserved capacity
  for (std::size_t i = 0; i < output_.size(); ++i) {
    BoxObservation& b = output_[i];
    const int slot = tracker_.outputSlot(static_cast<int>(i));
    const std::uint64_t id = tracker_.idOfSlot(slot);
    const std::size_t base = static_cast<std::size_t>(slot) * sensors;
    // The tracker's box: this frame's detection (or the coasting track's last) at the filtered centre.
    Eigen::Vector3d lo = b.position - 0.5 * b.dimensions;
    Eigen::Vector3d hi = b.position + 0.5 * b.dimensions;
    const int det = tracker_.detectionOfSlot(slot);
    if (det >= 0) {  // this sensor's sight of the track, relative to the filtered centre
      const workspace_proximity::Detection& d = detections_[static_cast<std::size_t>(det)];
      const std::size_t k = base + static_cast<std::size_t>(sensor);
      sight_id_[k] = id;
      sight_stamp_[k] = stamp;
      sight_min_[k] = d.position - 0.5 * d.dimensions - b.position;
      sight_max_[k] = d.position + 0.5 * d.dimensions - b.position;
      core_min_[k] = core_lo_[static_cast<std::size_t>(det)];  // where it was seen
      core_max_[k] = core_hi_[static_cast<std::size_t>(det)];
    }
    // Every sensor whose latest frame saw this track, this one too: its detection where it
    // was seen, though the filter put the centre elsewhere (a reused slot has another id).
    for (std::size_t o = 0; o < sensors; ++o) {
      const std::size_t k = base + o;
      if (sight_id_[k] != id || sight_stamp_[k] != sensor_stamp_[o]) continue;
      lo = lo.cwiseMin(b.position + sight_min_[k]);
      hi = hi.cwiseMax(b.position + sight_max_[k]);
    }
    b.position = 0.5 * (lo + hi);
    b.dimensions = hi - lo;
  }
}

}  // namespace perception
}  // namespace workspace_proximity
