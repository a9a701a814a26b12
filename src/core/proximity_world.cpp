#include "workspace_proximity/proximity_world.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "workspace_proximity/contact_window.hpp"
#include "workspace_proximity/event_tracker.hpp"
#include "workspace_proximity/pair_table.hpp"
#include "workspace_proximity/swept_bounds.hpp"
#include "worker_pool.hpp"

namespace workspace_proximity {
namespace {

// Pair-rule verdicts cached per pair.
constexpr std::uint8_t kVerdictUnknown = 0;
constexpr std::uint8_t kVerdictAllowed = 1;
constexpr std::uint8_t kVerdictDenied = 2;

// Adds the nanoseconds from its construction to its destruction to *total; reads no clock
// when disabled.
class StageTimer {
 public:
  explicit StageTimer(std::int64_t* total, bool enabled = true)
      : total_(enabled ? total : nullptr) {
    if (total_ != nullptr) start_ = std::chrono::steady_clock::now();
  }
  ~StageTimer() {
    if (total_ == nullptr) return;
    *total_ += std::chrono::duration_cast<std::chrono::nanoseconds>(
                   std::chrono::steady_clock::now() - start_)
                   .count();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  std::int64_t* total_;
  std::chrono::steady_clock::time_point start_;
};

// f(), its time added to *total when enabled (a returned value is not copied).
template <class F>
auto timed(std::int64_t* total, bool enabled, F&& f) {
  StageTimer timer(total, enabled);
  return f();
}

// A body's bounds as the broad phase sees them: its swept bounds grown by its reach.
Aabb grown(const Aabb& box, double reach) {
  if (reach == 0.0) return box;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(reach);
  return Aabb{box.lower - r, box.upper + r};
}

SweepAndPruneConfig broadPhaseConfig(const WorldConfig& config) {
  SweepAndPruneConfig c = config.broad_phase;
  c.initial_proxy_capacity = config.initial_body_capacity;
  c.initial_pair_capacity = config.initial_pair_capacity;
  return c;
}

// The one check of a body's shape and margin, and of its motion, for every entry point.
void checkShape(const char* where, const std::string& id, const Shape& shape, double margin) {
  if (!shape.valid()) {
    throw std::invalid_argument(std::string(where) + ": body '" + id +
                                "' has a non-finite or non-positive dimension");
  }
  if (!validMargin(margin)) {
    throw std::invalid_argument(std::string(where) + ": body '" + id +
                                "' has a negative, non-finite or huge margin");
  }
}

void checkMotion(const char* where, const std::string& id, const BodyMotion& motion) {
  if (!motion.valid()) {
    throw std::invalid_argument(std::string(where) + ": body '" + id +
                                "' has a non-finite or out-of-range motion or a non-unit quaternion");
  }
}

}  // namespace

// Everything the world keeps, behind ProximityWorld's one pointer; the public methods forward
// here (the end of this file).
struct ProximityWorld::Impl {
  explicit Impl(const WorldConfig& config);

  // The public API (proximity_world.hpp says what each does).
  BodyHandle addBody(const BodyDesc& desc, const BodyMotion& motion);
  void removeBody(BodyHandle body);
  void setMotion(BodyHandle body, const BodyMotion& motion);
  void setPath(BodyHandle body, const MotionSegment* segments, int count);
  void setGrowth(BodyHandle body, const MarginGrowth& growth);
  void setShape(BodyHandle body, const Shape& shape, double margin);
  bool contains(BodyHandle body) const;
  const BodyDesc& desc(BodyHandle body) const;
  const BodyMotion& motion(BodyHandle body) const;
  const MarginGrowth& growth(BodyHandle body) const;
  int pathSize(BodyHandle body) const;
  const PathSegment* path(BodyHandle body) const;
  Aabb sweptBounds(BodyHandle body) const;
  void setReach(BodyHandle body, double reach);
  double reach(BodyHandle body) const;
  void setRules(const PairRules& rules);
  const std::vector<PairEvent>& predict(double horizon);
  const std::vector<NearPair>& predictNear(double horizon);
  const std::vector<PairEvent>& predictEvents();

  struct BodyRecord;
  // The world's own record of a broad-phase pair, kept from the pair's begin to its end.
  struct PairRecord {
    std::int32_t proxy_a = -1;  // the broad phase's pair (the cache's key)
    std::int32_t proxy_b = -1;
    std::int32_t body_a = -1;   // body slots of the two proxies
    std::int32_t body_b = -1;
    std::uint8_t verdict = 0;   // pair rules: unknown, allowed, denied
    bool swapped = false;       // body_b's id sorts before body_a's (events name it first)
    std::int32_t event_record = -1;  // the event tracker's record last time (a hint)
  };
  BodyRecord& record(BodyHandle body);
  const BodyRecord& record(BodyHandle body) const;
  BodyRecord& liveRecord(BodyHandle body, const char* what);

  // predict() in steps.
  void freeRemovedSlots();
  void updateBounds(double horizon);
  void syncPairCache();
  void collectNearPairs();
  void predictPairs(double horizon);
  // Pairs ahead of the one evaluated whose bodies' records are prefetched, and how many cache
  // lines of each record: the header, half, margin, shape, motion and pose (through the pose's
  // translation, ~350 bytes; BodyRecord keeps them first).
  static constexpr std::size_t kPrefetchAhead = 8;
  static constexpr int kPrefetchLines = 6;
  void prefetchBodies(const PairRecord& pair) const;
  // One pair's counts and stage times, summed into stats_ (per thread while in parallel).
  struct PairCounters {
    int allowed = 0, axis_candidates = 0, contacts = 0, narrow_iterations = 0;
    std::int64_t ns_axis = 0, ns_narrow = 0;
  };
  bool evaluatePair(PairRecord& pair, double horizon, PairCounters* counters,
                    ContactPrediction* prediction);
  void addCounters(const PairCounters& counters);
  void predictPairsInParallel(double horizon);
  void runPairPart(int part);
  static void pairTask(void* impl, int part) { static_cast<Impl*>(impl)->runPairPart(part); }
  PairBody pairBody(std::int32_t slot) const;
  ContactWindow windowOf(PairBody* a, PairBody* b, double horizon);
  bool allowed(PairRecord& pair);
  void reportIfNear(std::int32_t slot_a, std::int32_t slot_b);
  void report(PairRecord& pair, const ContactPrediction& prediction);

  WorldConfig config_;
  std::vector<BodyRecord> bodies_;
  std::int32_t free_list_ = -1;
  int live_count_ = 0;
  std::uint32_t next_serial_ = 0;
  std::vector<std::int32_t> removed_;       // removed this cycle, freed at the next predict
  std::vector<std::int32_t> to_free_;
  double last_horizon_ = -1.0;
  bool rules_changed_ = true;
  std::uint64_t cycle_ = 0;                 // predict() calls so far (never wraps)
  bool near_done_ = false;                  // predictNear() ran; predictEvents() may follow
  double near_horizon_ = 0.0;               // its horizon, s

  SweepAndPrune broad_phase_;
  std::vector<std::int32_t> body_of_proxy_;    // body slot per broad-phase proxy id
  BasicPairTable<PairRecord> pair_cache_;       // the broad phase's pairs, as the world sees them
  NarrowPhase narrow_phase_;
  EventTracker tracker_;
  std::vector<NearPair> near_pairs_;
  std::vector<std::int32_t> reaching_;         // slots of the live bodies with a reach (scratch)
  WorldStats stats_;

  // The per-pair stages on config_.pair_threads threads (predictPairsInParallel): the pairs
  // in chunks that each thread claims in turn; every thread lists its contacts, and the
  // reports then follow in the pairs' order, as on one thread.
  struct PairPart {
    std::vector<std::pair<std::int32_t, ContactPrediction>> contacts;  // pair index, prediction
    PairCounters counters;
    std::exception_ptr error;
  };
  std::unique_ptr<WorkerPool> workers_;        // started at the first parallel prediction
  std::vector<PairPart> parts_;                // one per thread
  std::vector<std::int32_t> chunk_part_;       // per chunk: the thread that took it
  std::vector<std::int32_t> chunk_first_;      // its first contact in that thread's list
  std::vector<std::int32_t> chunk_count_;      // and how many it found
  std::atomic<int> next_chunk_{0};
  int chunks_ = 0;
  int chunk_size_ = 0;
  double pair_horizon_ = 0.0;
};

struct ProximityWorld::Impl::BodyRecord {
  enum class State : std::uint8_t { kFree, kLive, kRemoved };

  // Hot first, in the order updateBounds and the pair stages read them, so that a body's
  // per-cycle work touches few cache lines (prefetchBodies asks for the first six); the names
  // and the path come last.
  State state = State::kFree;
  bool dirty = true;
  bool has_path = false;  // set by setPath (else path holds the growing body's one segment)
  bool grows = false;     // !growth.none()
  SweepAndPrune::ProxyId proxy = -1;
  std::uint32_t generation = 0;
  std::uint32_t serial = 0;  // unique over the world's life: names the body in event keys
  std::int32_t next_free = -1;
  double reach = 0.0;  // m: the broad phase sees `swept` grown by this (setReach)
  Eigen::Vector3d half = Eigen::Vector3d::Zero();  // rotation-inflated half extents + margin
  // desc.shape and desc.margin, copied here beside the rest of what the pair stages read of a
  // body (desc's names come first there: two more cache lines a body otherwise).
  double margin = 0.0;
  Shape shape;
  BodyMotion motion;  // now: the constant twist, or the path's first segment
  // The pose at t = 0 (motion.poseAt(0)), set by updateBounds whenever the motion changed: the
  // swept bounds, every pair stage and the narrow phase's poses of a body that does not turn
  // start from it, so its rotation matrix is built once per motion, not once per use.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // The orientation pose's rotation was built from (NaN: none yet). Tracks that keep their
  // orientation and robot links at rest then cost one comparison instead of a normalisation
  // and a rotation matrix per cycle. The rotation depends on the orientation alone, so a
  // reused slot needs no reset.
  Eigen::Vector4d pose_orientation = Eigen::Vector4d::Constant(std::numeric_limits<double>::quiet_NaN());
  Aabb swept;
  BodyDesc desc;
  MarginGrowth growth;
  // Piecewise motion (setPath), or the one segment of a growing body: prepared by
  // updateBounds. The vector keeps its capacity across cycles and slot reuse.
  std::vector<PathSegment> path;
};

namespace {
const WorldConfig& checked(const WorldConfig& config) {
  if (config.pair_threads < 1 || config.pair_threads > WorldConfig::kMaxPairThreads) {
    throw std::invalid_argument("ProximityWorld: pair_threads must be in [1, " +
                                std::to_string(WorldConfig::kMaxPairThreads) + "]");
  }
  if (config.parallel_pairs < 1) {
    throw std::invalid_argument("ProximityWorld: parallel_pairs must be at least 1");
  }
  return config;
}
}  // namespace

ProximityWorld::Impl::Impl(const WorldConfig& config)
    : config_(checked(config)),
      broad_phase_(broadPhaseConfig(config)),
      pair_cache_(config.initial_pair_capacity),
      narrow_phase_(config.narrow_phase),
      tracker_(config.initial_event_capacity) {
  bodies_.reserve(static_cast<std::size_t>(std::max(config.initial_body_capacity, 1)));
  body_of_proxy_.reserve(bodies_.capacity());
  removed_.reserve(bodies_.capacity());
  to_free_.reserve(bodies_.capacity());
  near_pairs_.reserve(static_cast<std::size_t>(std::max(config.initial_pair_capacity, 1)));
}


ProximityWorld::Impl::BodyRecord& ProximityWorld::Impl::record(BodyHandle body) {
  if (!contains(body)) throw std::invalid_argument("ProximityWorld: stale or invalid body handle");
  return bodies_[body.index];
}

const ProximityWorld::Impl::BodyRecord& ProximityWorld::Impl::record(BodyHandle body) const {
  if (!contains(body)) throw std::invalid_argument("ProximityWorld: stale or invalid body handle");
  return bodies_[body.index];
}

ProximityWorld::Impl::BodyRecord& ProximityWorld::Impl::liveRecord(BodyHandle body, const char* what) {
  BodyRecord& b = record(body);
  if (b.state != BodyRecord::State::kLive) {
    throw std::invalid_argument(std::string(what) + ": body '" + b.desc.id + "' was removed");
  }
  return b;
}

bool ProximityWorld::Impl::contains(BodyHandle body) const {
  return body.index >= 0 && body.index < static_cast<std::int32_t>(bodies_.size()) &&
         bodies_[body.index].generation == body.generation &&
         bodies_[body.index].state != BodyRecord::State::kFree;
}

BodyHandle ProximityWorld::Impl::addBody(const BodyDesc& desc, const BodyMotion& motion) {
  constexpr const char* kWhere = "ProximityWorld::addBody";
  if (desc.id.empty()) throw std::invalid_argument("ProximityWorld::addBody: empty id");
  checkShape(kWhere, desc.id, desc.shape, desc.margin);
  checkMotion(kWhere, desc.id, motion);
  // Everything that can fail happens before the slot is taken, so a rejected body leaves
  // no trace (a geometry built for a free slot is simply replaced when the slot is used).
  const std::int32_t index =
      free_list_ >= 0 ? free_list_ : static_cast<std::int32_t>(bodies_.size());
  narrow_phase_.setShape(index, desc.shape);
  const double horizon = std::max(last_horizon_, 0.0);
  const Aabb swept = workspace_proximity::sweptBounds(desc.shape, motion, desc.margin, horizon);
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
  b.shape = desc.shape;
  b.margin = desc.margin;
  b.motion = motion;
  b.has_path = false;
  b.growth = MarginGrowth();
  b.grows = false;
  b.reach = 0.0;  // the slot's last body may have had one; the broad phase got `swept` alone
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

void ProximityWorld::Impl::removeBody(BodyHandle body) {
  BodyRecord& b = record(body);
  if (b.state != BodyRecord::State::kLive) return;  // removing twice is harmless
  broad_phase_.destroyProxy(b.proxy);
  b.proxy = -1;
  b.state = BodyRecord::State::kRemoved;
  removed_.push_back(body.index);
  --live_count_;
}

void ProximityWorld::Impl::setMotion(BodyHandle body, const BodyMotion& motion) {
  BodyRecord& b = liveRecord(body, "ProximityWorld::setMotion");
  checkMotion("ProximityWorld::setMotion", b.desc.id, motion);
  b.motion = motion;
  b.has_path = false;
  b.dirty = true;
}

void ProximityWorld::Impl::setPath(BodyHandle body, const MotionSegment* segments, int count) {
  BodyRecord& b = liveRecord(body, "ProximityWorld::setPath");
  if (!validPath(segments, count)) {
    throw std::invalid_argument("ProximityWorld::setPath: body '" + b.desc.id +
                                "' has an invalid path (1 to 64 segments from t = 0, increasing "
                                "starts, valid motions and margins)");
  }
  b.motion = segments[0].motion;
  b.dirty = true;
  if (count == 1 && segments[0].margin == 0.0) {
    b.has_path = false;  // one constant twist: the plain path, bit for bit
    return;
  }
  b.path.resize(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    PathSegment& s = b.path[static_cast<std::size_t>(k)];
    s.start = segments[k].start;
    s.motion = segments[k].motion;
    s.extra_margin = segments[k].margin;
  }
  b.has_path = true;
}

void ProximityWorld::Impl::setGrowth(BodyHandle body, const MarginGrowth& growth) {
  BodyRecord& b = liveRecord(body, "ProximityWorld::setGrowth");
  if (!growth.valid()) {
    throw std::invalid_argument("ProximityWorld::setGrowth: body '" + b.desc.id +
                                "' has a negative, non-finite or out-of-range margin growth");
  }
  const bool grows = !growth.none();
  b.growth = growth;
  // Tracks set their growth every cycle: one that neither grew nor grows keeps its bounds.
  if (!grows && !b.grows) return;
  b.grows = grows;
  b.dirty = true;
}

void ProximityWorld::Impl::setShape(BodyHandle body, const Shape& shape, double margin) {
  BodyRecord& b = liveRecord(body, "ProximityWorld::setShape");
  checkShape("ProximityWorld::setShape", b.desc.id, shape, margin);
  narrow_phase_.setShape(body.index, shape);
  b.desc.shape = b.shape = shape;
  b.desc.margin = b.margin = margin;
  b.dirty = true;
}

void ProximityWorld::Impl::setReach(BodyHandle body, double reach) {
  BodyRecord& b = liveRecord(body, "ProximityWorld::setReach");
  if (!std::isfinite(reach) || reach < 0.0 || reach > Limits::kMaxSize) {
    throw std::invalid_argument("ProximityWorld::setReach: body '" + b.desc.id +
                                "': reach must be in [0, 1e4] m");
  }
  if (reach == b.reach) return;
  b.reach = reach;
  b.dirty = true;
}

double ProximityWorld::Impl::reach(BodyHandle body) const { return record(body).reach; }

const BodyDesc& ProximityWorld::Impl::desc(BodyHandle body) const { return record(body).desc; }
const BodyMotion& ProximityWorld::Impl::motion(BodyHandle body) const { return record(body).motion; }
const MarginGrowth& ProximityWorld::Impl::growth(BodyHandle body) const { return record(body).growth; }

int ProximityWorld::Impl::pathSize(BodyHandle body) const {
  const BodyRecord& b = record(body);
  return (b.has_path || b.grows) ? static_cast<int>(b.path.size()) : 0;
}

const PathSegment* ProximityWorld::Impl::path(BodyHandle body) const {
  const BodyRecord& b = record(body);
  return (b.has_path || b.grows) ? b.path.data() : nullptr;
}
Aabb ProximityWorld::Impl::sweptBounds(BodyHandle body) const { return record(body).swept; }

void ProximityWorld::Impl::setRules(const PairRules& rules) {
  config_.rules = rules;
  rules_changed_ = true;
}

// The per-pair helpers below are `inline`: in a shared library an exported function may be
// interposed, so the compiler would not inline them into the pair loop otherwise.

const std::vector<PairEvent>& ProximityWorld::Impl::predict(double horizon) {
  predictNear(horizon);
  return predictEvents();
}

const std::vector<NearPair>& ProximityWorld::Impl::predictNear(double horizon) {
  if (!std::isfinite(horizon) || horizon < 0.0 || horizon > Limits::kMaxHorizon) {
    throw std::invalid_argument("ProximityWorld::predict: horizon must be in [0, 1e4] s");
  }
  // The last predictNear() was not followed by its events (its caller threw in between): they
  // are predicted now and dropped, so that the tracker's pairs and the freed slots stay in step.
  if (near_done_) predictEvents();
  stats_ = WorldStats();
  ++cycle_;
  freeRemovedSlots();
  {
    StageTimer timer(&stats_.ns_bounds);
    updateBounds(horizon);
  }
  stats_.bodies = live_count_;
  {
    // Before the broad phase: the few bodies with a reach (the robot's) against every body
    // is a linear scan, cheaper than the broad phase's update at thousands of objects, and
    // what speed and separation acts on must not wait for it.
    StageTimer timer(&stats_.ns_near);
    collectNearPairs();
  }
  near_done_ = true;
  near_horizon_ = horizon;
  return near_pairs_;
}

const std::vector<PairEvent>& ProximityWorld::Impl::predictEvents() {
  if (!near_done_) {
    throw std::logic_error("ProximityWorld::predictEvents: predictNear() has not run since the "
                           "last prediction");
  }
  near_done_ = false;
  {
    StageTimer timer(&stats_.ns_broad);
    broad_phase_.update();
    syncPairCache();
  }
  stats_.broad_phase = broad_phase_.stats();
  {
    StageTimer timer(&stats_.ns_pairs);
    predictPairs(near_horizon_);
  }
  if (!config_.time_pair_stages) stats_.ns_axis = stats_.ns_pairs;
  {
    StageTimer timer(&stats_.ns_events);
    tracker_.endCycle();  // BEGIN / ONGOING / END, earliest first
  }
  return tracker_.events();
}

void ProximityWorld::Impl::freeRemovedSlots() {
  // Bodies removed before the previous predict() had their END events then; their slots
  // can be reused now. Bodies removed since stay nameable through this predict().
  for (std::int32_t index : to_free_) {
    BodyRecord& b = bodies_[index];
    b.state = BodyRecord::State::kFree;
    ++b.generation;
    narrow_phase_.clearShape(index);
    b.next_free = free_list_;
    free_list_ = index;
  }
  to_free_.clear();
  std::swap(to_free_, removed_);
}

void ProximityWorld::Impl::updateBounds(double horizon) {
  // Swept bounds of every body that moved (all of them when the horizon changed).
  const bool horizon_changed = horizon != last_horizon_;
  last_horizon_ = horizon;
  for (BodyRecord& b : bodies_) {
    if (b.state != BodyRecord::State::kLive || !(b.dirty || horizon_changed)) continue;
    if (b.motion.orientation.coeffs() == b.pose_orientation) {
      // Bit for bit what poseAt(0) gives: the same rotation, the same translation sum.
      b.pose.translation() = b.motion.position + b.motion.linear_velocity * 0.0;
    } else {
      b.pose = b.motion.poseAt(0.0);
      b.pose_orientation = b.motion.orientation.coeffs();
    }
    if (b.has_path || b.grows) {
      if (!b.has_path) {
        // A growing body with one constant twist: a path of one segment.
        b.path.resize(1);
        b.path[0].start = 0.0;
        b.path[0].motion = b.motion;
        b.path[0].extra_margin = 0.0;
      }
      b.swept = preparePath(b.shape, b.margin, b.growth, horizon, b.path.data(),
                            static_cast<int>(b.path.size()));
      b.half = b.path[0].half;
    } else {
      if (b.shape.type == ShapeType::kBox && isExactlyZero(b.motion.angular_velocity)) {
        // A box that does not turn (most tracks): rotationHalfExtents' value, without the call.
        b.half = (b.pose.linear().cwiseAbs() * b.shape.half_extents).array() + b.margin;
      } else {
        b.half = rotationHalfExtents(b.shape, b.pose.linear(), b.motion.angular_velocity,
                                     b.margin, horizon);
      }
      b.swept = sweptBoundsOfHalf(b.half, b.motion, horizon);
    }
    broad_phase_.moveProxy(b.proxy, grown(b.swept, b.reach));
    b.dirty = false;
  }
}

void ProximityWorld::Impl::syncPairCache() {
  // The broad phase's pairs now = before - ended + began (disjoint): the cache follows, and
  // a new pair's bodies and verdict are looked up once, when it begins.
  for (const BroadPair& p : broad_phase_.endedPairs()) pair_cache_.erase(p.proxy_a, p.proxy_b);
  for (const BroadPair& p : broad_phase_.beganPairs()) {
    PairRecord* pair = pair_cache_.insert(p.proxy_a, p.proxy_b, nullptr);
    pair->body_a = body_of_proxy_[static_cast<std::size_t>(pair->proxy_a)];
    pair->body_b = body_of_proxy_[static_cast<std::size_t>(pair->proxy_b)];
    pair->verdict = kVerdictUnknown;
    pair->event_record = -1;
    // Ids are fixed while both bodies live, and so is the pair: compared once, not per event.
    pair->swapped = bodies_[pair->body_b].desc.id < bodies_[pair->body_a].desc.id;
  }
  // A quarter of headroom, as in the broad phase: the cache grows while the pair count climbs
  // to its usual level, not when it first touches a new maximum by chance.
  if (4 * static_cast<std::size_t>(pair_cache_.size()) > 3 * pair_cache_.capacity()) {
    pair_cache_.reserve(2 * pair_cache_.capacity());
  }
}

void ProximityWorld::Impl::collectNearPairs() {
  // Every live body against the live bodies with a reach, each pair once, named as the broad
  // phase names it (the lower proxy first), so that the distances are the ones a pass over the
  // broad phase's pairs would give, bit for bit.
  near_pairs_.clear();
  reaching_.clear();
  const auto n = static_cast<std::int32_t>(bodies_.size());
  for (std::int32_t i = 0; i < n; ++i) {
    if (bodies_[i].state == BodyRecord::State::kLive && bodies_[i].reach > 0.0) reaching_.push_back(i);
  }
  if (!reaching_.empty()) {
    for (std::int32_t j = 0; j < n; ++j) {
      const BodyRecord& other = bodies_[j];
      if (other.state != BodyRecord::State::kLive) continue;
      for (const std::int32_t i : reaching_) {
        // Two bodies with a reach: the pair is seen from the lower slot only.
        if (i == j || (other.reach > 0.0 && j < i)) continue;
        const bool i_first = bodies_[i].proxy < other.proxy;
        reportIfNear(i_first ? i : j, i_first ? j : i);
      }
    }
  }
  stats_.near_pairs = static_cast<int>(near_pairs_.size());
}

void ProximityWorld::Impl::predictPairs(double horizon) {
  // Per pair: rules, contact window, narrow phase inside the window, report.
  tracker_.beginCycle();
  stats_.broad_pairs = pair_cache_.size();
  if (config_.pair_threads > 1 && pair_cache_.size() >= config_.parallel_pairs) {
    predictPairsInParallel(horizon);
  } else {
    PairCounters counters;
    ContactPrediction prediction;
    std::vector<PairRecord>& pairs = pair_cache_.mutablePairs();
    const std::size_t n = pairs.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (i + kPrefetchAhead < n) prefetchBodies(pairs[i + kPrefetchAhead]);
      if (evaluatePair(pairs[i], horizon, &counters, &prediction)) report(pairs[i], prediction);
    }
    addCounters(counters);
  }
  rules_changed_ = false;
}

void ProximityWorld::Impl::addCounters(const PairCounters& counters) {
  stats_.allowed_pairs += counters.allowed;
  stats_.axis_candidates += counters.axis_candidates;
  stats_.contacts += counters.contacts;
  stats_.narrow_iterations += counters.narrow_iterations;
  stats_.ns_axis += counters.ns_axis;
  stats_.ns_narrow += counters.ns_narrow;
}

inline bool ProximityWorld::Impl::evaluatePair(PairRecord& pair, double horizon,
                                               PairCounters* counters,
                                               ContactPrediction* prediction) {
  // Reads the bodies and the narrow phase's geometry, and writes the pair's own record only:
  // threads may evaluate different pairs at once.
  if (!allowed(pair)) return false;
  ++counters->allowed;
  PairBody a = pairBody(pair.body_a), b = pairBody(pair.body_b);
  const bool timed_pairs = config_.time_pair_stages;
  if (a.piecewise() || b.piecewise()) {
    // The merged breakpoints of both bodies, then the same steps as a constant-twist pair.
    const PairPieces pieces(a, b, horizon);
    const ContactWindow window =
        timed(&counters->ns_axis, timed_pairs, [&] { return piecewiseWindow(pieces); });
    if (window.axis.empty()) return false;
    ++counters->axis_candidates;
    *prediction = timed(&counters->ns_narrow, timed_pairs,
                        [&] { return narrow_phase_.predict(a, b, window); });
  } else {
    const ContactWindow window =
        timed(&counters->ns_axis, timed_pairs, [&] { return windowOf(&a, &b, horizon); });
    if (window.axis.empty()) return false;
    ++counters->axis_candidates;
    if (window.empty()) return false;
    *prediction = timed(&counters->ns_narrow, timed_pairs,
                        [&] { return narrow_phase_.predict(a, b, window); });
  }
  counters->narrow_iterations += prediction->iterations;
  if (!prediction->contact) return false;
  ++counters->contacts;
  return true;
}

void ProximityWorld::Impl::predictPairsInParallel(double horizon) {
  const int threads = config_.pair_threads;
  if (!workers_) {
    workers_ = std::make_unique<WorkerPool>(threads - 1);
    parts_.resize(static_cast<std::size_t>(threads));
  }
  // Chunks small enough to share the pairs out evenly (eight or more a thread), large enough
  // that claiming one (an atomic increment) costs nothing next to its pairs.
  const int pairs = pair_cache_.size();
  chunk_size_ = std::max(16, std::min(256, pairs / (8 * threads)));
  chunks_ = (pairs + chunk_size_ - 1) / chunk_size_;
  chunk_part_.resize(static_cast<std::size_t>(chunks_));
  chunk_first_.resize(static_cast<std::size_t>(chunks_));
  chunk_count_.resize(static_cast<std::size_t>(chunks_));
  next_chunk_.store(0, std::memory_order_relaxed);
  pair_horizon_ = horizon;
  workers_->run(threads, &Impl::pairTask, this);
  // Every part is finished: run() returns after the workers' last writes, under its mutex.
  for (const PairPart& part : parts_) {
    if (part.error) std::rethrow_exception(part.error);
  }
  for (const PairPart& part : parts_) addCounters(part.counters);
  // The reports in the pairs' order, as predictPairs makes them on one thread: the event
  // tracker's records and the events are the same for any number of threads.
  std::vector<PairRecord>& records = pair_cache_.mutablePairs();
  for (std::size_t c = 0; c < static_cast<std::size_t>(chunks_); ++c) {
    const PairPart& part = parts_[static_cast<std::size_t>(chunk_part_[c])];
    const std::size_t first = static_cast<std::size_t>(chunk_first_[c]);
    const std::size_t end = first + static_cast<std::size_t>(chunk_count_[c]);
    for (std::size_t k = first; k < end; ++k) {
      report(records[static_cast<std::size_t>(part.contacts[k].first)], part.contacts[k].second);
    }
  }
}

void ProximityWorld::Impl::runPairPart(int index) {
  PairPart& part = parts_[static_cast<std::size_t>(index)];
  part.contacts.clear();
  part.counters = PairCounters();
  part.error = nullptr;
  std::vector<PairRecord>& records = pair_cache_.mutablePairs();
  const int pairs = static_cast<int>(records.size());
  try {
    ContactPrediction prediction;
    for (;;) {
      const int c = next_chunk_.fetch_add(1, std::memory_order_relaxed);
      if (c >= chunks_) break;
      const std::size_t cu = static_cast<std::size_t>(c);
      chunk_part_[cu] = index;
      chunk_first_[cu] = static_cast<std::int32_t>(part.contacts.size());
      const int end = std::min(pairs, (c + 1) * chunk_size_);
      for (int i = c * chunk_size_; i < end; ++i) {
        if (i + static_cast<int>(kPrefetchAhead) < end) {
          prefetchBodies(records[static_cast<std::size_t>(i) + kPrefetchAhead]);
        }
        if (evaluatePair(records[static_cast<std::size_t>(i)], pair_horizon_, &part.counters,
                         &prediction)) {
          part.contacts.emplace_back(i, prediction);
        }
      }
      chunk_count_[cu] = static_cast<std::int32_t>(part.contacts.size()) - chunk_first_[cu];
    }
  } catch (...) {
    part.error = std::current_exception();
    next_chunk_.store(chunks_, std::memory_order_relaxed);  // the others stop soon
  }
}

inline void ProximityWorld::Impl::prefetchBodies(const PairRecord& pair) const {
  // The pairs come in the sweep's order, their bodies' records from all over the array: the
  // first cache lines of both (what evaluatePair reads) are asked for a few pairs ahead. At
  // 10 000 dense walkers (30 000 pairs, the records 6 MB) the per-pair stages took ~17 % less
  // (4.8 -> 4.0 ms, alternating; 3 lines: 8 %).
  for (const std::int32_t slot : {pair.body_a, pair.body_b}) {
    const char* r = reinterpret_cast<const char*>(&bodies_[static_cast<std::size_t>(slot)]);
    for (int line = 0; line < kPrefetchLines; ++line) __builtin_prefetch(r + 64 * line);
  }
}

inline PairBody ProximityWorld::Impl::pairBody(std::int32_t slot) const {
  const BodyRecord& r = bodies_[slot];
  PairBody body;
  body.shape = &r.shape;
  body.motion = &r.motion;
  body.margin = r.margin;
  body.half = r.half;
  body.geometry = slot;  // the narrow phase's geometry cache is indexed by body slot
  body.pose = &r.pose;   // updateBounds keeps it current
  if (r.has_path || r.grows) {
    body.segments = r.path.data();
    body.segment_count = static_cast<int>(r.path.size());
    if (r.grows) body.growth = &r.growth;
  }
  return body;
}

inline ContactWindow ProximityWorld::Impl::windowOf(PairBody* a, PairBody* b, double horizon) {
  return refineWindow(*a, *b, axisWindow(*a, *b, horizon));
}

inline bool ProximityWorld::Impl::allowed(PairRecord& pair) {
  // Rules are evaluated once per broad-phase pair (and again after setRules), not every cycle.
  if (pair.verdict == kVerdictUnknown || rules_changed_) {
    const bool allow = config_.rules.allowed(bodies_[pair.body_a].desc, bodies_[pair.body_b].desc);
    pair.verdict = allow ? kVerdictAllowed : kVerdictDenied;
  }
  return pair.verdict == kVerdictAllowed;
}

inline void ProximityWorld::Impl::reportIfNear(std::int32_t slot_a, std::int32_t slot_b) {
  const BodyRecord& ra = bodies_[slot_a];
  const BodyRecord& rb = bodies_[slot_b];
  const double reach = ra.reach + rb.reach;
  if (!(reach > 0.0)) return;
  // The boxes around the centres (`half` holds each shape now) a lower bound apart on some
  // axis further than the reach: the shapes are too. Most pairs stop here.
  const Eigen::Vector3d gap = (ra.motion.position - rb.motion.position).cwiseAbs() - ra.half - rb.half;
  if (gap.maxCoeff() > reach) return;
  // The pair rules, as the broad phase's pairs have them (only for the few pairs this near).
  if (!config_.rules.allowed(ra.desc, rb.desc)) return;
  const PairBody a = pairBody(slot_a), b = pairBody(slot_b);
  const ShapeDistance d = narrow_phase_.distanceNow(a, b);
  ++stats_.narrow_iterations;
  if (d.distance > reach) return;
  NearPair near;
  near.body_a = BodyHandle{slot_a, ra.generation};
  near.body_b = BodyHandle{slot_b, rb.generation};
  near.distance = d.overlapping ? 0.0 : d.distance;
  near.point_a = d.point_a;
  near.point_b = d.point_b;
  near.normal = d.normal;
  near_pairs_.push_back(near);
}

inline void ProximityWorld::Impl::report(PairRecord& pair, const ContactPrediction& prediction) {
  const BodyRecord& a = bodies_[pair.body_a];
  const BodyRecord& b = bodies_[pair.body_b];
  // Name the pair so that body_a's id sorts first, as the message contract asks.
  const bool swap = pair.swapped;
  PairEvent event;
  event.body_a = BodyHandle{swap ? pair.body_b : pair.body_a, swap ? b.generation : a.generation};
  event.body_b = BodyHandle{swap ? pair.body_a : pair.body_b, swap ? a.generation : b.generation};
  event.time_to_contact = prediction.time_to_contact;
  event.time_to_separation = prediction.time_to_separation;
  event.distance = prediction.distance;
  event.point_a = swap ? prediction.point_b : prediction.point_a;
  event.point_b = swap ? prediction.point_a : prediction.point_b;
  event.normal = swap ? Eigen::Vector3d(-prediction.normal) : prediction.normal;
  event.closing_speed = prediction.closing_speed;
  // The bodies' serials name the pair for the tracker: never reused, unlike slots.
  const std::uint32_t lo = std::min(a.serial, b.serial);
  const std::uint32_t hi = std::max(a.serial, b.serial);
  // The pair's record last time first: no look-up in the tracker's index while it lasts.
  pair.event_record =
      tracker_.report((static_cast<std::uint64_t>(lo) << 32) | hi, event, pair.event_record);
}

// ---------------------------------------------------------------------------------------------
// The public class: one pointer to the state.

ProximityWorld::ProximityWorld(const WorldConfig& config) : impl_(std::make_unique<Impl>(config)) {}
ProximityWorld::~ProximityWorld() = default;

BodyHandle ProximityWorld::addBody(const BodyDesc& desc, const BodyMotion& motion) {
  return impl_->addBody(desc, motion);
}
void ProximityWorld::removeBody(BodyHandle body) { impl_->removeBody(body); }
void ProximityWorld::setMotion(BodyHandle body, const BodyMotion& motion) { impl_->setMotion(body, motion); }
void ProximityWorld::setPath(BodyHandle body, const MotionSegment* segments, int count) {
  impl_->setPath(body, segments, count);
}
void ProximityWorld::setGrowth(BodyHandle body, const MarginGrowth& growth) { impl_->setGrowth(body, growth); }
void ProximityWorld::setShape(BodyHandle body, const Shape& shape, double margin) {
  impl_->setShape(body, shape, margin);
}
bool ProximityWorld::contains(BodyHandle body) const { return impl_->contains(body); }
const BodyDesc& ProximityWorld::desc(BodyHandle body) const { return impl_->desc(body); }
const BodyMotion& ProximityWorld::motion(BodyHandle body) const { return impl_->motion(body); }
const MarginGrowth& ProximityWorld::growth(BodyHandle body) const { return impl_->growth(body); }
int ProximityWorld::pathSize(BodyHandle body) const { return impl_->pathSize(body); }
const PathSegment* ProximityWorld::path(BodyHandle body) const { return impl_->path(body); }
Aabb ProximityWorld::sweptBounds(BodyHandle body) const { return impl_->sweptBounds(body); }
int ProximityWorld::bodyCount() const { return impl_->live_count_; }
void ProximityWorld::setReach(BodyHandle body, double reach) { impl_->setReach(body, reach); }
double ProximityWorld::reach(BodyHandle body) const { return impl_->reach(body); }
void ProximityWorld::setRules(const PairRules& rules) { impl_->setRules(rules); }
const std::vector<PairEvent>& ProximityWorld::predict(double horizon) { return impl_->predict(horizon); }
const std::vector<NearPair>& ProximityWorld::predictNear(double horizon) {
  return impl_->predictNear(horizon);
}
const std::vector<PairEvent>& ProximityWorld::predictEvents() { return impl_->predictEvents(); }
const WorldStats& ProximityWorld::stats() const { return impl_->stats_; }
const std::vector<NearPair>& ProximityWorld::nearPairs() const { return impl_->near_pairs_; }

}  // namespace workspace_proximity
