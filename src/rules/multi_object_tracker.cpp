#include "workspace_proximity/rules/multi_object_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxCapacity = 100000;
constexpr std::size_t kIdChars = 48;  // reserved per id: prefix (<= 15) + up to 20 digits

bool finiteNonNegative(double x) { return std::isfinite(x) && x >= 0.0; }
bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

Eigen::Vector4d yawQuaternion(double yaw) {
  return Eigen::Vector4d(0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw));
}

std::vector<std::string> validate(const TrackerParams& p) {
  std::vector<std::string> problems;
  auto check = [&](bool ok, const std::string& what) {
    if (!ok) problems.push_back(what);
  };
  check(p.capacity >= 1 && p.capacity <= kMaxCapacity, "capacity must be in [1, 100000]");
  check(p.max_detections >= 1 && p.max_detections <= kMaxCapacity,
        "max_detections must be in [1, 100000]");
  check(finitePositive(p.gate_chi2), "gate_chi2 must be finite and > 0");
  check(finitePositive(p.gate_distance), "gate_distance must be finite and > 0 m");
  check(p.confirm_hits >= 1, "confirm_hits must be >= 1");
  check(p.max_misses >= 1, "max_misses must be >= 1");
  check(finitePositive(p.timeout), "timeout must be finite and > 0 s");
  check(finitePositive(p.known_velocity_error), "known_velocity_error must be finite and > 0 m/s");
  check(p.id_prefix.size() <= 15, "id_prefix must have at most 15 characters");
  check(!p.labels.empty(), "labels must not be empty");
  for (const TrackerLabel& l : p.labels) {
    check(!l.name.empty(), "labels: a label has an empty name");
    check(finiteNonNegative(l.max_accel), "labels/" + l.name + "/max_accel must be finite and >= 0");
    check(finitePositive(l.max_speed), "labels/" + l.name + "/max_speed must be finite and > 0");
  }
  return problems;
}

MultiObjectTracker::MultiObjectTracker(const TrackerParams& params)
    : params_(params),
      assignment_(std::clamp(std::max(params.capacity, params.max_detections), 1, kMaxCapacity)) {
  const std::vector<std::string> problems = validate(params_);
  if (!problems.empty()) {
    throw std::invalid_argument("MultiObjectTracker: " + problems.front());
  }
  // Every buffer at its full size now: update() only reuses them.
  const auto cap = static_cast<std::size_t>(params_.capacity);
  const auto dets = static_cast<std::size_t>(params_.max_detections);
  state_.assign(cap, kFree);
  id_.assign(cap, 0);
  id_text_.resize(cap);
  for (std::string& s : id_text_) s.reserve(kIdChars);
  label_.assign(cap, 0);
  hits_.assign(cap, 0);
  misses_.assign(cap, 0);
  seen_.assign(cap, 0);
  detection_of_.assign(cap, -1);
  position_.assign(cap, Eigen::Vector3d::Zero());
  velocity_.assign(cap, Eigen::Vector3d::Zero());
  dimensions_.assign(cap, Eigen::Vector3d::Ones());
  quaternion_.assign(cap, Eigen::Vector4d(0, 0, 0, 1));
  p_pp_.assign(cap, 0.0);
  p_pv_.assign(cap, 0.0);
  p_vv_.assign(cap, 0.0);
  free_.reserve(cap);
  for (std::size_t i = cap; i-- > 0;) free_.push_back(static_cast<int>(i));  // slot 0 first
  live_.reserve(cap);
  used_.reserve(dets);
  cost_.assign(cap * dets, 0.0);
  match_of_row_.assign(cap, -1);
  matched_det_.assign(dets, 0);
  output_.reserve(cap);
  output_slot_.reserve(cap);
}

bool MultiObjectTracker::validDetection(const Detection& d) const {
  if (!d.position.allFinite() || !d.dimensions.allFinite() || !d.quaternion.allFinite()) return false;
  if ((d.dimensions.array() < 2.0 * Limits::kMinSize).any()) return false;
  if ((d.dimensions.array() > 2.0 * Limits::kMaxSize).any()) return false;
  if (std::abs(d.quaternion.norm() - 1.0) > 0.01) return false;
  if (!finitePositive(d.sigma)) return false;
  return d.label >= 0 && d.label < static_cast<int>(params_.labels.size());
}

bool MultiObjectTracker::footprintsOverlap(std::size_t s, const Detection& d) const {
  // Axis-aligned in (x, y): the track's box (as last detected) grown by its 3 sigma error.
  const double grow = 3.0 * std::sqrt(std::max(0.0, p_pp_[s]));
  for (int k = 0; k < 2; ++k) {
    const double reach = 0.5 * (dimensions_[s][k] + d.dimensions[k]) + grow;
    if (std::abs(d.position[k] - position_[s][k]) > reach) return false;
  }
  return true;
}

void MultiObjectTracker::predict(int slot, double dt) {
  const auto s = static_cast<std::size_t>(slot);
  position_[s] += velocity_[s] * dt;
  // P <- F P F^T + Q, F = [1 dt; 0 1], Q the discrete white acceleration (sigma_a = a_max / 3).
  const double sa = params_.labels[static_cast<std::size_t>(label_[s])].max_accel / 3.0;
  const double q = sa * sa;
  const double a = p_pp_[s], b = p_pv_[s], c = p_vv_[s];
  const double dt2 = dt * dt;
  p_pp_[s] = a + 2.0 * b * dt + c * dt2 + q * dt2 * dt2 / 4.0;
  p_pv_[s] = b + c * dt + q * dt2 * dt / 2.0;
  p_vv_[s] = c + q * dt2;
}

void MultiObjectTracker::correct(int slot, const Detection& d) {
  const auto s = static_cast<std::size_t>(slot);
  // H = [1 0] per axis; the three axes share P, so one gain for all.
  const double a = p_pp_[s], b = p_pv_[s], c = p_vv_[s];
  double r = d.sigma * d.sigma;
  if (params_.gate_footprint) {
    // Gated by footprint, possibly beyond the Mahalanobis gate: the offset is put on the gate
    // as noise, so two sensors' differing centres of one object do not read as a velocity.
    r = std::max(r, (d.position - position_[s]).squaredNorm() / params_.gate_chi2 - a);
  }
  const double innovation_var = a + r;
  const double k_p = a / innovation_var, k_v = b / innovation_var;
  const Eigen::Vector3d innovation = d.position - position_[s];
  position_[s] += k_p * innovation;
  velocity_[s] += k_v * innovation;
  p_pp_[s] = (1.0 - k_p) * a;
  p_pv_[s] = (1.0 - k_p) * b;
  p_vv_[s] = c - k_v * b;
  dimensions_[s] = d.dimensions;
  quaternion_[s] = d.quaternion.normalized();
  label_[s] = d.label;
  seen_[s] = stamp_;
  misses_[s] = 0;
  ++hits_[s];
  if (state_[s] == kTentative && hits_[s] >= params_.confirm_hits) state_[s] = kConfirmed;
}

int MultiObjectTracker::birth(const Detection& d) {
  if (free_.empty()) return -1;
  const int slot = free_.back();
  free_.pop_back();
  live_.push_back(slot);
  const auto s = static_cast<std::size_t>(slot);
  const double v0 = params_.labels[static_cast<std::size_t>(d.label)].max_speed;
  id_[s] = next_id_++;
  char digits[24];
  std::snprintf(digits, sizeof digits, "%llu", static_cast<unsigned long long>(id_[s]));
  id_text_[s].assign(params_.id_prefix).append(digits);  // within the reserved capacity
  label_[s] = d.label;
  position_[s] = d.position;
  velocity_[s].setZero();  // unknown: 1 sigma of the label's max_speed around 0
  p_pp_[s] = d.sigma * d.sigma;
  p_pv_[s] = 0.0;
  p_vv_[s] = v0 * v0;
  dimensions_[s] = d.dimensions;
  quaternion_[s] = d.quaternion.normalized();
  seen_[s] = stamp_;
  hits_[s] = 1;
  misses_[s] = 0;
  state_[s] = params_.confirm_hits <= 1 ? kConfirmed : kTentative;
  return slot;
}

void MultiObjectTracker::release(int slot) {
  const auto s = static_cast<std::size_t>(slot);
  state_[s] = kFree;
  id_[s] = 0;
  free_.push_back(slot);
  const auto it = std::find(live_.begin(), live_.end(), slot);
  *it = live_.back();
  live_.pop_back();
}

void MultiObjectTracker::clear() {
  while (!live_.empty()) release(live_.back());
  output_.clear();
  output_slot_.clear();
}

OptimalAssignment::OptimalAssignment(int max_side) {
  const auto work = static_cast<std::size_t>(max_side) + 1;
  u_.assign(work, 0.0);
  v_.assign(work, 0.0);
  minv_.assign(work, 0.0);
  p_.assign(work, 0);
  way_.assign(work, 0);
  done_.assign(work, 0);
}

void OptimalAssignment::solve(const double* cost_matrix, int rows, int cols, int* row_match) {
  std::fill(row_match, row_match + rows, -1);
  if (rows == 0 || cols == 0) return;
  // The method needs n <= m: the matrix as it is, or transposed.
  const bool transposed = rows > cols;
  const int n = transposed ? cols : rows;
  const int m = transposed ? rows : cols;
  auto cost = [&](int i, int j) {  // 1-based row i and column j of the n x m problem
    const int r = transposed ? j - 1 : i - 1;
    const int c = transposed ? i - 1 : j - 1;
    return cost_matrix[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) +
                       static_cast<std::size_t>(c)];
  };
  auto at = [](auto& array, int k) -> auto& { return array[static_cast<std::size_t>(k)]; };
  std::fill(u_.begin(), u_.begin() + n + 1, 0.0);
  std::fill(v_.begin(), v_.begin() + m + 1, 0.0);
  std::fill(p_.begin(), p_.begin() + m + 1, 0);
  std::fill(way_.begin(), way_.begin() + m + 1, 0);
  // Row i joins the assignment along the shortest augmenting path from it, found Dijkstra-like
  // on reduced costs (cost - u - v >= 0); the potentials keep the partial assignment optimal.
  for (int i = 1; i <= n; ++i) {
    p_[0] = i;
    int j0 = 0;
    std::fill(minv_.begin(), minv_.begin() + m + 1, kInf);
    std::fill(done_.begin(), done_.begin() + m + 1, 0);
    do {
      at(done_, j0) = 1;
      const int i0 = at(p_, j0);
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (at(done_, j)) continue;
        const double cur = cost(i0, j) - at(u_, i0) - at(v_, j);
        if (cur < at(minv_, j)) {
          at(minv_, j) = cur;
          at(way_, j) = j0;
        }
        if (at(minv_, j) < delta) {
          delta = at(minv_, j);
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (at(done_, j)) {
          at(u_, at(p_, j)) += delta;
          at(v_, j) -= delta;
        } else {
          at(minv_, j) -= delta;
        }
      }
      j0 = j1;
    } while (at(p_, j0) != 0);
    do {  // flip the path
      const int j1 = at(way_, j0);
      at(p_, j0) = at(p_, j1);
      j0 = j1;
    } while (j0 != 0);
  }
  for (int j = 1; j <= m; ++j) {
    const int i = at(p_, j);
    if (i == 0) continue;
    if (transposed) {
      row_match[j - 1] = i - 1;
    } else {
      row_match[i - 1] = j - 1;
    }
  }
}

bool MultiObjectTracker::update(Stamp stamp, const Detection* detections, int count) {
  if (started_ && stamp < stamp_) return false;
  const double dt = started_ ? secondsBetween(stamp_, stamp) : 0.0;
  started_ = true;
  stamp_ = stamp;
  stats_ = TrackerStats();

  // The detections to use.
  used_.clear();
  for (int k = 0; k < count; ++k) {
    if (!validDetection(detections[k])) {
      ++stats_.rejected;
    } else if (static_cast<int>(used_.size()) >= params_.max_detections) {
      ++stats_.dropped;
    } else {
      used_.push_back(k);
    }
  }
  stats_.detections = static_cast<int>(used_.size());

  // Predict every live track to the frame, then cost every gated pair.
  const int tracks = static_cast<int>(live_.size());
  const int dets = stats_.detections;
  for (int slot : live_) {
    predict(slot, dt);
    detection_of_[static_cast<std::size_t>(slot)] = -1;
  }
  // A gated-out pair costs more than any set of gated pairs together (each at most gate_chi2):
  // the optimum has as many gated pairs as possible, then the least total d^2.
  const double gated_out = params_.gate_chi2 * (std::min(tracks, dets) + 1) + 1.0;
  const double gate2 = params_.gate_distance * params_.gate_distance;
  for (int t = 0; t < tracks; ++t) {
    const auto s = static_cast<std::size_t>(live_[static_cast<std::size_t>(t)]);
    for (int j = 0; j < dets; ++j) {
      const Detection& d = detections[used_[static_cast<std::size_t>(j)]];
      double c = gated_out;
      if (d.label == label_[s] && !params_.gate_footprint) {
        const double squared = (d.position - position_[s]).squaredNorm();
        const double mahalanobis = squared / (p_pp_[s] + d.sigma * d.sigma);
        if (squared <= gate2 && mahalanobis <= params_.gate_chi2) c = mahalanobis;
      } else if (d.label == label_[s]) {
        const double squared = (d.position - position_[s]).head<2>().squaredNorm();
        const double mahalanobis = squared / (p_pp_[s] + d.sigma * d.sigma);
        if (squared <= gate2 && (mahalanobis <= params_.gate_chi2 || footprintsOverlap(s, d))) {
          c = std::min(mahalanobis, params_.gate_chi2);
        }
      }
      cost_[static_cast<std::size_t>(t) * static_cast<std::size_t>(dets) +
            static_cast<std::size_t>(j)] = c;
    }
  }
  std::fill(matched_det_.begin(), matched_det_.begin() + dets, 0);
  assignment_.solve(cost_.data(), tracks, dets, match_of_row_.data());

  // Matched tracks take their detection; the others coast, and may die. Rows are indices into
  // live_ as it was: the deaths wait until every row has been read.
  for (int t = 0; t < tracks; ++t) {
    const int slot = live_[static_cast<std::size_t>(t)];
    const int j = match_of_row_[static_cast<std::size_t>(t)];
    const bool gated = j >= 0 && cost_[static_cast<std::size_t>(t) * static_cast<std::size_t>(dets) +
                                       static_cast<std::size_t>(j)] < gated_out;
    if (gated) {
      correct(slot, detections[used_[static_cast<std::size_t>(j)]]);
      detection_of_[static_cast<std::size_t>(slot)] = used_[static_cast<std::size_t>(j)];
      matched_det_[static_cast<std::size_t>(j)] = 1;
      ++stats_.matched;
    } else {
      ++misses_[static_cast<std::size_t>(slot)];
      match_of_row_[static_cast<std::size_t>(t)] = -1;
    }
  }
  for (int t = tracks; t-- > 0;) {
    const int slot = live_[static_cast<std::size_t>(t)];
    const auto s = static_cast<std::size_t>(slot);
    if (misses_[s] >= params_.max_misses || secondsBetween(seen_[s], stamp_) > params_.timeout) {
      release(slot);
      ++stats_.deleted;
    }
  }
  // Every detection left over starts a track, while there is room.
  for (int j = 0; j < dets; ++j) {
    if (matched_det_[static_cast<std::size_t>(j)]) continue;
    const int born = birth(detections[used_[static_cast<std::size_t>(j)]]);
    if (born >= 0) {
      detection_of_[static_cast<std::size_t>(born)] = used_[static_cast<std::size_t>(j)];
      ++stats_.born;
    } else {
      ++stats_.dropped;
    }
  }
  stats_.live = static_cast<int>(live_.size());
  publish();
  return true;
}

void MultiObjectTracker::publish() {
  output_.clear();
  output_slot_.clear();
  for (int slot : live_) {
    const auto s = static_cast<std::size_t>(slot);
    if (state_[s] != kConfirmed) continue;
    BoxObservation b;
    b.id = id_text_[s];
    b.label = params_.labels[static_cast<std::size_t>(label_[s])].name;
    b.position = position_[s];
    b.quaternion = quaternion_[s];
    b.dimensions = dimensions_[s];
    b.linear_velocity = velocity_[s];
    b.position_error = 3.0 * std::sqrt(std::max(0.0, p_pp_[s]));
    b.velocity_error = 3.0 * std::sqrt(std::max(0.0, p_vv_[s]));
    b.velocity_known = b.velocity_error <= params_.known_velocity_error;
    output_.push_back(b);
    output_slot_.push_back(slot);
  }
}

}  // namespace workspace_proximity
