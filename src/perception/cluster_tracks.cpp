#include "workspace_proximity/perception/cluster_tracks.hpp"

#include <cmath>
#include <stdexcept>

namespace workspace_proximity {
namespace perception {
namespace {

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

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
  for (const std::string& s : validate(trackerParams(p))) problems.push_back("tracker: " + s);
  return problems;
}

ClusterTracks::ClusterTracks(const ClusterTrackParams& params)
    : params_(checked(params)), tracker_(trackerParams(params_)) {
  detections_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
}

ClusterFrameUse ClusterTracks::update(Stamp stamp, const std::vector<Detection>& clusters) {
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
  tracker_.update(stamp, detections_);
  return use;
}

}  // namespace perception
}  // namespace workspace_proximity
