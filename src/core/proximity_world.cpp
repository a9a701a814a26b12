#include "workspace_proximity/proximity_world.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "workspace_proximity/swept_bounds.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace workspace_proximity {
namespace {

// Pair-rule verdicts cached per pair.
constexpr std::uint8_t kVerdictUnknown = 0;
constexpr std::uint8_t kVerdictAllowed = 1;
constexpr std::uint8_t kVerdictDenied = 2;

std::int64_t nanosSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                              start)
      .count();
}

SweepAndPruneConfig broadPhaseConfig(const WorldConfig& config) {
  SweepAndPruneConfig c = config.broad_phase;
  c.initial_proxy_capacity = config.initial_body_capacity;
  c.initial_pair_capacity = config.initial_pair_capacity;
  return c;
}

}  // namespace

struct ProximityWorld::BodyRecord {
  enum class State : std::uint8_t { kFree, kLive, kRemoved };

  BodyDesc desc;
  BodyMotion motion;
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  double bounding_radius = 0.0;
  Eigen::Vector3d half = Eigen::Vector3d::Zero();  // rotation-inflated half extents + margin
  Aabb swept;
  SweepAndPrune::ProxyId proxy = -1;
  std::uint32_t generation = 0;
  std::uint32_t serial = 0;  // unique over the world's life: names the body in event keys
  std::int32_t next_free = -1;
  State state = State::kFree;
  bool dirty = true;
};

ProximityWorld::ProximityWorld(const WorldConfig& config)
    : config_(config),
      broad_phase_(broadPhaseConfig(config)),
      pair_cache_(config.initial_pair_capacity),
      narrow_phase_(config.narrow_phase),
      tracker_(config.initial_event_capacity) {
  bodies_.reserve(static_cast<std::size_t>(std::max(config.initial_body_capacity, 1)));
  body_of_proxy_.reserve(bodies_.capacity());
  removed_.reserve(bodies_.capacity());
  to_free_.reserve(bodies_.capacity());
}

ProximityWorld::~ProximityWorld() = default;

ProximityWorld::BodyRecord& ProximityWorld::record(BodyHandle body) {
  if (!contains(body)) throw std::invalid_argument("ProximityWorld: stale or invalid body handle");
  return bodies_[body.index];
}

const ProximityWorld::BodyRecord& ProximityWorld::record(BodyHandle body) const {
  if (!contains(body)) throw std::invalid_argument("ProximityWorld: stale or invalid body handle");
  return bodies_[body.index];
}

bool ProximityWorld::contains(BodyHandle body) const {
  return body.index >= 0 && body.index < static_cast<std::int32_t>(bodies_.size()) &&
         bodies_[body.index].generation == body.generation &&
         bodies_[body.index].state != BodyRecord::State::kFree;
}

BodyHandle ProximityWorld::addBody(const BodyDesc& desc, const BodyMotion& motion) {
  if (desc.id.empty()) throw std::invalid_argument("ProximityWorld::addBody: empty id");
  if (!desc.shape.valid()) {
    throw std::invalid_argument("ProximityWorld::addBody: body '" + desc.id +
                                "' has a non-finite or non-positive dimension");
  }
  if (!std::isfinite(desc.margin) || desc.margin < 0.0 || desc.margin > Limits::kMaxMargin) {
    throw std::invalid_argument("ProximityWorld::addBody: body '" + desc.id +
                                "' has a negative, non-finite or huge margin");
  }
  if (!motion.valid()) {
    throw std::invalid_argument("ProximityWorld::addBody: body '" + desc.id +
                                "' has a non-finite or out-of-range motion or a non-unit quaternion");
  }
  // Everything that can fail happens before the slot is taken, so a rejected body leaves
  // no trace.
  std::shared_ptr<fcl::CollisionGeometryd> geometry = makeGeometry(desc.shape);
  const double horizon = std::max(last_horizon_, 0.0);
  const Aabb swept = workspace_proximity::sweptBounds(desc.shape, motion, desc.margin, horizon);
  const std::int32_t index =
      free_list_ >= 0 ? free_list_ : static_cast<std::int32_t>(bodies_.size());
  const SweepAndPrune::ProxyId proxy = broad_phase_.createProxy(swept);
  if (static_cast<std::size_t>(proxy) >= body_of_proxy_.size()) body_of_proxy_.resize(proxy + 1, -1);
  body_of_proxy_[static_cast<std::size_t>(proxy)] = index;

  if (free_list_ >= 0) {
    free_list_ = bodies_[index].next_free;
  } else {
    bodies_.emplace_back();
  }
  BodyRecord& b = bodies_[index];
  b.desc = desc;
  b.motion = motion;
  b.geometry = std::move(geometry);
  b.bounding_radius = desc.shape.boundingRadius();
  b.serial = next_serial_++;
  b.state = BodyRecord::State::kLive;
  b.dirty = true;
  b.next_free = -1;
  b.half = rotationHalfExtents(desc.shape, motion, desc.margin, horizon);
  b.swept = swept;
  b.proxy = proxy;
  ++live_count_;
  return BodyHandle{index, b.generation};
}

void ProximityWorld::removeBody(BodyHandle body) {
  BodyRecord& b = record(body);
  if (b.state != BodyRecord::State::kLive) return;  // removing twice is harmless
  broad_phase_.destroyProxy(b.proxy);
  b.proxy = -1;
  b.state = BodyRecord::State::kRemoved;
  removed_.push_back(body.index);
  --live_count_;
}

void ProximityWorld::setMotion(BodyHandle body, const BodyMotion& motion) {
  BodyRecord& b = record(body);
  if (b.state != BodyRecord::State::kLive) {
    throw std::invalid_argument("ProximityWorld::setMotion: body '" + b.desc.id +
                                "' was removed");
  }
  if (!motion.valid()) {
    throw std::invalid_argument("ProximityWorld::setMotion: body '" + b.desc.id +
                                "' has a non-finite or out-of-range motion or a non-unit quaternion");
  }
  b.motion = motion;
  b.dirty = true;
}

void ProximityWorld::setShape(BodyHandle body, const Shape& shape, double margin) {
  BodyRecord& b = record(body);
  if (b.state != BodyRecord::State::kLive) {
    throw std::invalid_argument("ProximityWorld::setShape: body '" + b.desc.id + "' was removed");
  }
  if (!shape.valid() || !std::isfinite(margin) || margin < 0.0 || margin > Limits::kMaxMargin) {
    throw std::invalid_argument("ProximityWorld::setShape: body '" + b.desc.id +
                                "' gets an invalid shape or margin");
  }
  b.desc.shape = shape;
  b.desc.margin = margin;
  b.geometry = makeGeometry(shape);
  b.bounding_radius = shape.boundingRadius();
  b.dirty = true;
}

const BodyDesc& ProximityWorld::desc(BodyHandle body) const { return record(body).desc; }
const BodyMotion& ProximityWorld::motion(BodyHandle body) const { return record(body).motion; }
Aabb ProximityWorld::sweptBounds(BodyHandle body) const { return record(body).swept; }

void ProximityWorld::setRules(const PairRules& rules) {
  config_.rules = rules;
  rules_changed_ = true;
}

void ProximityWorld::syncPairCache() {
  // The broad phase's pairs now = before - ended + began (disjoint): the cache follows, and
  // a new pair's bodies and verdict are looked up once, when it begins.
  for (const BroadPair& p : broad_phase_.endedPairs()) pair_cache_.erase(p.proxy_a, p.proxy_b);
  for (const BroadPair& p : broad_phase_.beganPairs()) {
    PairRecord* pair = pair_cache_.insert(p.proxy_a, p.proxy_b, nullptr);
    pair->body_a = body_of_proxy_[static_cast<std::size_t>(pair->proxy_a)];
    pair->body_b = body_of_proxy_[static_cast<std::size_t>(pair->proxy_b)];
    pair->verdict = kVerdictUnknown;
  }
  // A quarter of headroom, as in the broad phase: the cache grows while the pair count climbs
  // to its usual level, not when it first touches a new maximum by chance.
  if (4 * static_cast<std::size_t>(pair_cache_.size()) > 3 * pair_cache_.capacity()) {
    pair_cache_.reserve(2 * pair_cache_.capacity());
  }
}

void ProximityWorld::freeRemovedSlots() {
  // Bodies removed before the previous predict() had their END events then; their slots
  // can be reused now. Bodies removed since stay nameable through this predict().
  for (std::int32_t index : to_free_) {
    BodyRecord& b = bodies_[index];
    b.state = BodyRecord::State::kFree;
    ++b.generation;
    b.geometry.reset();
    b.next_free = free_list_;
    free_list_ = index;
  }
  to_free_.clear();
  std::swap(to_free_, removed_);
}

const std::vector<PairEvent>& ProximityWorld::predict(double horizon) {
  if (!std::isfinite(horizon) || horizon < 0.0 || horizon > Limits::kMaxHorizon) {
    throw std::invalid_argument("ProximityWorld::predict: horizon must be in [0, 1e4] s");
  }
  stats_ = WorldStats();
  freeRemovedSlots();

  // 1. Swept bounds of every body that moved (all of them when the horizon changed).
  auto t0 = std::chrono::steady_clock::now();
  const bool horizon_changed = horizon != last_horizon_;
  last_horizon_ = horizon;
  for (BodyRecord& b : bodies_) {
    if (b.state != BodyRecord::State::kLive || !(b.dirty || horizon_changed)) continue;
    b.half = rotationHalfExtents(b.desc.shape, b.motion, b.desc.margin, horizon);
    b.swept = workspace_proximity::sweptBounds(b.desc.shape, b.motion, b.desc.margin, horizon);
    broad_phase_.moveProxy(b.proxy, b.swept);
    b.dirty = false;
  }
  stats_.ns_bounds = nanosSince(t0);

  // 2. Incremental sweep-and-prune.
  t0 = std::chrono::steady_clock::now();
  broad_phase_.update();
  syncPairCache();
  stats_.ns_broad = nanosSince(t0);
  stats_.broad_phase = broad_phase_.stats();
  stats_.bodies = live_count_;

  // 3-4. Rules, per-axis time of impact, narrow phase.
  tracker_.beginCycle();
  std::vector<PairRecord>& pairs = pair_cache_.mutablePairs();
  stats_.broad_pairs = static_cast<int>(pairs.size());
  std::int64_t ns_axis = 0;
  std::int64_t ns_narrow = 0;
  const bool timed = config_.time_pair_stages;
  const auto pairs_start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point ta, tn;
  for (PairRecord& pair : pairs) {
    const std::int32_t ia = pair.body_a;
    const std::int32_t ib = pair.body_b;
    BodyRecord& a = bodies_[ia];
    BodyRecord& b = bodies_[ib];
    if (pair.verdict == kVerdictUnknown || rules_changed_) {
      // Rules are evaluated once per broad-phase pair, not every cycle.
      pair.verdict = config_.rules.allowed(a.desc, b.desc) ? kVerdictAllowed : kVerdictDenied;
    }
    if (pair.verdict != kVerdictAllowed) continue;
    ++stats_.allowed_pairs;

    if (timed) ta = std::chrono::steady_clock::now();
    const TimeInterval window =
        boxContactInterval(a.motion.position, a.half, a.motion.linear_velocity, b.motion.position,
                           b.half, b.motion.linear_velocity, horizon);
    if (timed) ns_axis += nanosSince(ta);
    if (window.empty()) continue;
    ++stats_.axis_candidates;

    if (timed) tn = std::chrono::steady_clock::now();
    const NarrowBody na{a.geometry.get(), &a.motion, a.desc.margin, a.bounding_radius};
    const NarrowBody nb{b.geometry.get(), &b.motion, b.desc.margin, b.bounding_radius};
    const ContactPrediction prediction = narrow_phase_.predict(na, nb, window);
    if (timed) ns_narrow += nanosSince(tn);
    stats_.narrow_iterations += prediction.iterations;
    if (!prediction.contact) continue;
    ++stats_.contacts;

    // Name the pair so that body_a's id sorts first, as the message contract asks.
    const bool swap = b.desc.id < a.desc.id;
    PairEvent event;
    event.body_a = BodyHandle{swap ? ib : ia, swap ? b.generation : a.generation};
    event.body_b = BodyHandle{swap ? ia : ib, swap ? a.generation : b.generation};
    event.time_to_contact = prediction.time_to_contact;
    event.time_to_separation = prediction.time_to_separation;
    event.distance = prediction.distance;
    event.point_a = swap ? prediction.point_b : prediction.point_a;
    event.point_b = swap ? prediction.point_a : prediction.point_b;
    event.normal = swap ? Eigen::Vector3d(-prediction.normal) : prediction.normal;
    event.closing_speed = prediction.closing_speed;
    const std::uint32_t lo = std::min(a.serial, b.serial);
    const std::uint32_t hi = std::max(a.serial, b.serial);
    tracker_.report((static_cast<std::uint64_t>(lo) << 32) | hi, event);
  }
  rules_changed_ = false;
  stats_.ns_pairs = nanosSince(pairs_start);
  stats_.ns_axis = timed ? ns_axis : stats_.ns_pairs;
  stats_.ns_narrow = ns_narrow;

  // 5. Events: BEGIN / ONGOING / END, earliest first.
  t0 = std::chrono::steady_clock::now();
  tracker_.endCycle();
  stats_.ns_events = nanosSince(t0);
  return tracker_.events();
}

}  // namespace workspace_proximity
