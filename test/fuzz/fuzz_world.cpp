// libFuzzer harness over ProximityWorld: the input is a little program of operations (add,
// remove, setMotion, setShape, setRules, predict, advance) with arbitrary numbers: huge, tiny,
// denormal, infinite and NaN included. The API must reject invalid input with
// std::invalid_argument (caught here); any other exception, a crash, a sanitizer report or a
// violated invariant (checked after every predict) is a finding.
//
// The harness keeps its own model of the world (which handles are live or still nameable,
// which pairs were active after the last predict, the current pair rules) and checks the
// world against it: among others, every pair keeps its pair number from BEGIN to END, and two
// live boxes that overlap now by an independent separating-axis test (test/shared/oracles.hpp)
// have a contact event at time 0 unless the rules deny the pair. Robot bodies get a reach (0 to
// 1.5 m, from their order: no input bytes), every other predict runs in its two halves
// (predictNear, then predictEvents), and the pairs within reach are checked: live, allowed, no
// farther than the reach, each once, and every clearly overlapping allowed pair with a reach
// among them. Set WP_FUZZ_STRICT=1 to also report a *valid* input (by the documented
// rules) that the API rejected, e.g. finite numbers whose bounds overflow to infinity.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_input.hpp"
#include "oracles.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;
using wp_fuzz::fail;
using wp_fuzz::Input;

namespace {

constexpr int kMaxBodies = 24;       // bodies ever added per input: bounds the narrow phase
constexpr int kMaxOperations = 160;
constexpr int kMaxPredicts = 24;
constexpr double kSlack = 1e-9;

using wp_fuzz::str;

bool strictMode() {
  static const bool strict = wp_fuzz::envFlag("WP_FUZZ_STRICT");
  return strict;
}

// WP_FUZZ_TRACE=1 prints every operation and its outcome (for replaying a finding).
bool traceMode() {
  static const bool trace = wp_fuzz::envFlag("WP_FUZZ_TRACE");
  return trace;
}

// Printable form of an id (ids may hold any byte, NUL included).
std::string printable(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (c >= 0x20 && c < 0x7F) {
      out.push_back(static_cast<char>(c));
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  return out;
}

std::string str(const wp::BodyMotion& m) {
  return "position " + str(m.position) + " q " + str(m.orientation.w()) + " " +
         str(m.orientation.vec()) + " v " + str(m.linear_velocity) + " w " + str(m.angular_velocity);
}

std::string str(const wp::Shape& s) {
  return "shape type " + std::to_string(static_cast<int>(s.type)) + " half " + str(s.half_extents) +
         " radius " + str(s.radius) + " length " + str(s.length);
}

std::string str(wp::BodyHandle h) {
  return "(" + std::to_string(h.index) + "," + std::to_string(h.generation) + ")";
}

// Validity by the documented rules, written independently of Shape::valid() and
// BodyMotion::valid(): 1 valid, 0 invalid, -1 within rounding of a tolerance.
int shapeValid(const wp::Shape& s) {
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  switch (static_cast<int>(s.type)) {
    case 0:
      return positive(s.half_extents.x()) && positive(s.half_extents.y()) &&
             positive(s.half_extents.z());
    case 1:
      return positive(s.radius);
    case 2:
      return positive(s.radius) && positive(s.length);
    case 3:
      return positive(s.radius) && std::isfinite(s.length) && s.length >= 0.0;
    default:
      return 0;
  }
}

int motionValid(const wp::BodyMotion& m) {
  if (!m.position.allFinite() || !m.linear_velocity.allFinite() ||
      !m.angular_velocity.allFinite() || !m.orientation.coeffs().allFinite()) {
    return 0;
  }
  long double n2 = 0.0L;
  for (int i = 0; i < 4; ++i) {
    const long double c = m.orientation.coeffs()[i];
    n2 += c * c;
  }
  const double error = std::abs(static_cast<double>(std::sqrt(n2)) - 1.0);
  if (error < 1e-6 - 1e-12) return 1;
  if (error > 1e-6 + 1e-12) return 0;
  return -1;
}

int marginValid(double margin) { return std::isfinite(margin) && margin >= 0.0; }

int both(int a, int b) {
  if (a == 0 || b == 0) return 0;
  if (a < 0 || b < 0) return -1;
  return 1;
}

struct ModelBody {
  wp::BodyHandle handle;
  wp::BodyDesc desc;
  bool live = true;
  int removed_after = -1;  // successful predicts done when it was removed
  double reach = 0.0;      // m (setReach)
};

using PairKey = std::pair<std::uint64_t, std::uint64_t>;

std::uint64_t handleKey(wp::BodyHandle h) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(h.index)) << 32) | h.generation;
}

PairKey pairKey(wp::BodyHandle a, wp::BodyHandle b) {
  const std::uint64_t x = handleKey(a), y = handleKey(b);
  return x < y ? PairKey{x, y} : PairKey{y, x};
}

class Harness {
 public:
  explicit Harness(Input& in)
      : in_(in), config_(makeConfig(in)), world_(config_), rules_(config_.rules) {}

  void run() {
    for (int op = 0; op < kMaxOperations && !in_.empty() && predicts_ < kMaxPredicts; ++op) {
      switch (in_.byte() % 10) {
        case 0:
        case 1:
        case 2:
          add();
          break;
        case 3:
          remove();
          break;
        case 4:
          setMotion();
          break;
        case 5:
          setShape();
          break;
        case 6:
          setRules();
          break;
        case 7:
          advance();
          break;
        default:
          predict();
          break;
      }
    }
    if (!in_.empty() || predicts_ == 0) predict();
  }

 private:
  static wp::WorldConfig makeConfig(Input& in) {
    const std::uint8_t b = in.byte();
    wp::WorldConfig c;
    static const double factors[] = {1.0, 0.0, 0.05, 1e9};
    c.broad_phase.rebuild_factor = wp_fuzz::pickByBits(factors, b, 6);
    static const int capacities[] = {1, 2, 3, 256};
    c.initial_body_capacity = wp_fuzz::pickByBits(capacities, b, 0);
    c.initial_pair_capacity = wp_fuzz::pickByBits(capacities, b, 2);
    c.initial_event_capacity = wp_fuzz::pickByBits(capacities, b, 4);
    const std::uint8_t n = in.byte();
    if (n & 1) c.narrow_phase.max_iterations = 1 + (n >> 5);
    if (n & 2) c.narrow_phase.distance_tolerance = 1e-3;
    c.rules = (n & 4) ? wp::PairRules::allowAll() : wp::PairRules();
    if (n & 8) {  // the per-pair stages on two threads, from the first pair on
      c.pair_threads = 2;
      c.parallel_pairs = 1;
    }
    return c;
  }

  // ---- input --------------------------------------------------------------------------

  wp::Shape shape() {
    wp::Shape s;
    const std::uint8_t t = in_.byte();
    const bool raw_fields = (t & 0x80) != 0;
    const std::uint8_t type = t < 0xF0 ? (t & 3) : t;  // 0xF0.. are invalid types
    Eigen::Vector3d h;
    h.x() = in_.dimension();
    h.y() = in_.dimension();
    h.z() = in_.dimension();
    const double radius = in_.dimension();
    const double length = in_.byte() < 32 ? 0.0 : in_.dimension();
    if (raw_fields || type > 3) {
      s.type = static_cast<wp::ShapeType>(type);
      s.half_extents = h;
      s.radius = radius;
      s.length = length;
      return s;
    }
    switch (type) {
      case 0:
        return wp::Shape::box(h);
      case 1:
        return wp::Shape::sphere(radius);
      case 2:
        return wp::Shape::cylinder(radius, length);
      default:
        return wp::Shape::capsule(radius, length);
    }
  }

  wp::BodyMotion motion() {
    wp::BodyMotion m;
    m.position = in_.vector();
    m.orientation = in_.quaternion();
    const std::uint8_t kind = in_.byte();
    if (kind & 1) m.linear_velocity = in_.vector();
    if (kind & 2) m.angular_velocity = in_.vector();
    return m;
  }

  // A handle: usually one the world gave out (live, removed or stale), sometimes made up.
  wp::BodyHandle handle() {
    const std::uint8_t b = in_.byte();
    if (b < 224 && !bodies_.empty()) return bodies_[b % bodies_.size()].handle;
    const std::int32_t index = static_cast<std::int8_t>(in_.byte());
    const std::uint32_t generation = in_.byte() % 4;
    return wp::BodyHandle{index, generation};
  }

  // ---- model ----------------------------------------------------------------------------

  bool nameable(const ModelBody& b) const { return b.live || predicts_ <= b.removed_after + 1; }

  // The model body a handle names, or nullptr (stale or made-up handle).
  ModelBody* lookup(wp::BodyHandle h) {
    for (ModelBody& b : bodies_) {
      if (b.handle == h && nameable(b)) return &b;
    }
    return nullptr;
  }

  // Whether an operation on a live body may succeed: yes for a live body, no otherwise,
  // unknown once the world has rejected a valid input (it may hold a half-added body).
  int liveExpectation(const ModelBody* b) const {
    if (b != nullptr && b->live) return 1;
    return tainted_ ? -1 : 0;
  }

  int liveCount() const {
    int n = 0;
    for (const ModelBody& b : bodies_) n += b.live ? 1 : 0;
    return n;
  }

  // An API call finished: compare with what the documented rules expect.
  void outcome(const std::string& what, int expected_valid, bool threw) {
    if (traceMode()) {
      std::fprintf(stderr, "%s -> %s (expected %s)\n", what.c_str(), threw ? "rejected" : "ok",
                   expected_valid == 1 ? "valid" : expected_valid == 0 ? "invalid" : "either");
    }
    if (!threw && expected_valid == 0) fail("invalid input accepted by", what);
    if (threw && expected_valid == 1) {
      if (strictMode()) fail("valid input rejected by", what);
      tainted_ = true;  // the world may be half-updated: stop model-based checks
    }
  }

  // ---- operations -----------------------------------------------------------------------

  void add() {
    if (static_cast<int>(bodies_.size()) >= kMaxBodies) return;
    wp::BodyDesc desc;
    const std::uint8_t naming = in_.byte();
    if ((naming & 15) != 0) {
      desc.id = "b" + std::to_string(next_id_++);
      if (naming & 16) desc.id += "/" + in_.text(6);
    }
    static const char* const labels[] = {"person", "forklift", "robot", "pallet", ""};
    desc.label = labels[(naming >> 5) % 5];
    desc.group = (naming & 0x80) ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject;
    desc.shape = shape();
    desc.margin = in_.margin();
    const wp::BodyMotion m = motion();
    const int expected = both(both(desc.id.empty() ? 0 : 1, shapeValid(desc.shape)),
                              both(marginValid(desc.margin), motionValid(m)));
    wp::BodyHandle h;
    bool threw = false;
    try {
      h = world_.addBody(desc, m);
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    outcome("addBody " + printable(desc.id) + " " + str(desc.shape) + " margin " + str(desc.margin) + " " + str(m),
            expected, threw);
    if (threw) return;
    // A new handle never aliases a body the caller can still name.
    for (const ModelBody& b : bodies_) {
      if (b.handle == h && nameable(b)) fail("addBody returned a handle in use", str(h));
    }
    if (!world_.contains(h)) fail("addBody: handle not contained", str(h));
    if (world_.desc(h).id != desc.id) fail("addBody: desc() names another body", str(h));
    // A new body has no reach, whatever its slot's last body had (a freed slot's reach was
    // once kept: its bounds grown by it, near pairs listed beyond the pair's reaches).
    if (world_.reach(h) != 0.0) fail("addBody: a new body has a reach", str(h) + " " + str(world_.reach(h)));
    bodies_.push_back(ModelBody{h, desc, true, -1, 0.0});
    if (desc.group == wp::BodyGroup::kRobot) {
      // A reach as speed and separation gives the robot's bodies (no input bytes spent).
      const double reach = 0.5 * static_cast<double>(next_id_ % 4);
      world_.setReach(h, reach);
      bodies_.back().reach = reach;
      if (world_.reach(h) != reach) fail("reach() differs from setReach", str(h));
    }
  }

  void remove() {
    const wp::BodyHandle h = handle();
    ModelBody* b = lookup(h);
    bool threw = false;
    try {
      world_.removeBody(h);
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    // Removing a live or still nameable body works (twice is harmless); others throw.
    outcome("removeBody " + str(h), b != nullptr ? 1 : tainted_ ? -1 : 0, threw);
    if (!threw && b != nullptr && b->live) {
      b->live = false;
      b->removed_after = predicts_;
    }
  }

  void setMotion() {
    const wp::BodyHandle h = handle();
    const wp::BodyMotion m = motion();
    setMotionTo(h, m);
  }

  void setMotionTo(wp::BodyHandle h, const wp::BodyMotion& m) {
    ModelBody* b = lookup(h);
    bool threw = false;
    try {
      world_.setMotion(h, m);
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    outcome("setMotion " + str(h) + (b == nullptr ? " (not nameable)" : b->live ? " (live)" : " (removed)") +
                " " + str(m),
            both(liveExpectation(b), motionValid(m)), threw);
  }

  void setShape() {
    const wp::BodyHandle h = handle();
    const wp::Shape s = shape();
    const double margin = in_.margin();
    ModelBody* b = lookup(h);
    bool threw = false;
    try {
      world_.setShape(h, s, margin);
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    outcome("setShape " + str(h) + (b == nullptr ? " (not nameable)" : b->live ? " (live)" : " (removed)") +
                " " + str(s) + " margin " + str(margin),
            both(liveExpectation(b), both(shapeValid(s), marginValid(margin))),
            threw);
    if (!threw && b != nullptr) {
      b->desc.shape = s;
      b->desc.margin = margin;
    }
  }

  void setRules() {
    static const char* const selectors[] = {
        "*",           "group:robot", "group:object", "label:person", "label:robot",
        "label:forklift", "id:b0",    "id:b1",        "id:b2",        "id:b3",
        "group:",      "bogus",       "label:",       "",             "group:people",
        "id:"};
    const std::uint8_t b = in_.byte();
    wp::PairRules rules = (b & 1) ? wp::PairRules::allowAll() : wp::PairRules();
    const int n = (b >> 1) % 4;
    try {
      for (int i = 0; i < n; ++i) {
        const std::uint8_t s = in_.byte();
        std::string first = selectors[s & 15];
        std::string second = selectors[(s >> 4) & 15];
        if (first == "id:") first += in_.text(4);
        rules.add(first, second, in_.flag());
      }
    } catch (const std::invalid_argument&) {
      return;  // a bad selector: PairRules refused it, nothing reaches the world
    }
    world_.setRules(rules);
    rules_ = rules;
  }

  // Every live body moves along its own motion by dt (what a caller does between cycles).
  void advance() {
    const double dt = in_.flag() ? static_cast<std::int8_t>(in_.byte()) / 64.0 : in_.number();
    for (ModelBody& b : bodies_) {
      if (!b.live) continue;
      wp::BodyMotion m;
      try {
        m = world_.motion(b.handle).advanced(dt);
      } catch (const std::invalid_argument&) {
        if (!tainted_) fail("motion() of a live body threw", str(b.handle));
        continue;
      }
      setMotionTo(b.handle, m);
    }
  }

  void predict() {
    const double horizon = in_.flag() ? in_.byte() / 32.0 : in_.number();
    const int expected = std::isfinite(horizon) && horizon >= 0.0;
    if (traceMode()) std::fprintf(stderr, "calling predict %s\n", str(horizon).c_str());
    bool threw = false;
    const std::vector<wp::PairEvent>* events = nullptr;
    const bool halves = predicts_ % 2 == 1;  // predictNear then predictEvents: the same contract
    try {
      if (halves) {
        const std::vector<wp::NearPair> near = world_.predictNear(horizon);
        events = &world_.predictEvents();
        if (near.size() != world_.nearPairs().size()) fail("predictEvents changed the near pairs", "");
      } else {
        events = &world_.predict(horizon);
      }
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    outcome("predict " + str(horizon), expected, threw);
    if (threw) return;
    ++predicts_;
    check(*events, horizon);
    if (!tainted_) checkNearPairs();
  }

  // The pairs within reach: live bodies, allowed, no farther apart than their reaches, each
  // pair once; and every clearly overlapping allowed pair of moderate boxes with a reach is
  // among them at distance 0 (the oracle's separating-axis test, as checkOverlapsNow).
  void checkNearPairs() {
    std::set<PairKey> seen;
    for (const wp::NearPair& p : world_.nearPairs()) {
      const ModelBody* a = lookup(p.body_a);
      const ModelBody* b = lookup(p.body_b);
      const std::string where = str(p.body_a) + "-" + str(p.body_b) + " distance " + str(p.distance);
      if (a == nullptr || b == nullptr || !a->live || !b->live) fail("near pair of a body not live", where);
      if (!seen.insert(pairKey(p.body_a, p.body_b)).second) fail("near pair reported twice", where);
      if (!rules_.allowed(a->desc, b->desc)) fail("near pair the rules deny", where);
      const double reach = a->reach + b->reach;
      if (!(p.distance >= 0.0) || p.distance > reach * (1.0 + 1e-9) + 1e-9) {
        fail("near pair farther than the reach", where + " reach " + str(reach));
      }
    }
    if (world_.stats().near_pairs != static_cast<int>(seen.size())) fail("stats().near_pairs differs", "");
    forEachClearOverlap([&](const ModelBody& a, const ModelBody& b) {
      if (a.reach + b.reach <= 0.0) return;
      if (seen.count(pairKey(a.handle, b.handle)) == 0) {
        fail("overlapping boxes with a reach missing from the near pairs", str(a.handle) + "-" + str(b.handle));
      }
    });
  }

  // Calls visit(a, b) for every pair of live boxes of moderate size and position that the
  // rules allow and that clearly overlap now: the oracle's separating-axis test on the boxes
  // shrunk by a part in 1e6.
  template <typename Visit>
  void forEachClearOverlap(Visit visit) {
    auto moderate = [](const wp::BodyDesc& d, const wp::BodyMotion& m) {
      return d.shape.type == wp::ShapeType::kBox && d.shape.half_extents.minCoeff() >= 1e-3 &&
             d.shape.half_extents.maxCoeff() <= 1e3 && m.position.cwiseAbs().maxCoeff() <= 1e3;
    };
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const ModelBody& a = bodies_[i];
      if (!a.live || !moderate(a.desc, world_.motion(a.handle))) continue;
      const oracle::Obb oa{oracle::poseAt(world_.motion(a.handle), 0.0), a.desc.shape.half_extents * (1.0 - 1e-6)};
      for (std::size_t j = i + 1; j < bodies_.size(); ++j) {
        const ModelBody& b = bodies_[j];
        if (!b.live || !moderate(b.desc, world_.motion(b.handle))) continue;
        if (!rules_.allowed(a.desc, b.desc)) continue;
        const oracle::Obb ob{oracle::poseAt(world_.motion(b.handle), 0.0), b.desc.shape.half_extents * (1.0 - 1e-6)};
        if (oracle::overlaps(oa, ob)) visit(a, b);
      }
    }
  }

  // ---- invariants after predict ---------------------------------------------------------

  void check(const std::vector<wp::PairEvent>& events, double horizon) {
    if (traceMode()) {
      for (const wp::PairEvent& e : events) {
        std::fprintf(stderr, "  event %s-%s state %d ttc %g tts %g distance %g\n",
                     str(e.body_a).c_str(), str(e.body_b).c_str(), static_cast<int>(e.state),
                     e.time_to_contact, e.time_to_separation, e.distance);
      }
    }
    std::set<PairKey> seen;
    std::set<PairKey> active;
    std::map<PairKey, double> contact_time;       // non-END events: time_to_contact
    std::map<PairKey, std::int32_t> numbers;      // non-END events: pair number
    std::set<std::int32_t> numbers_seen;
    int contacts = 0;
    for (std::size_t i = 0; i < events.size(); ++i) {
      const wp::PairEvent& e = events[i];
      const std::string where = "event " + std::to_string(i) + " of " +
                                std::to_string(events.size()) + " " + str(e.body_a) + "-" +
                                str(e.body_b) + " horizon " + str(horizon) + " ttc " +
                                str(e.time_to_contact) + " tts " + str(e.time_to_separation) +
                                " distance " + str(e.distance) + " normal " + str(e.normal) +
                                " state " + std::to_string(static_cast<int>(e.state));
      const int state = static_cast<int>(e.state);
      if (state < 0 || state > 2) fail("unknown event state", where);
      if (std::isnan(e.time_to_contact) || std::isnan(e.time_to_separation) ||
          std::isnan(e.distance) || std::isnan(e.closing_speed) || e.point_a.hasNaN() ||
          e.point_b.hasNaN() || e.normal.hasNaN()) {
        fail("NaN in an event", where);
      }
      if (i > 0 && !(events[i - 1].time_to_contact <= e.time_to_contact)) {
        fail("events not sorted by time_to_contact", where);
      }
      const bool ended = e.state == wp::ContactState::kEnd;
      if (!ended) {
        ++contacts;
        if (!(e.time_to_contact >= -kSlack)) fail("time_to_contact < 0", where);
        if (!(e.time_to_contact <= e.time_to_separation + kSlack)) {
          fail("time_to_contact > time_to_separation", where);
        }
        if (!(e.time_to_separation <= horizon + kSlack)) fail("time_to_separation > horizon", where);
        if (!(e.distance >= 0.0)) fail("negative distance", where);
      } else {
        if (!(e.time_to_contact == std::numeric_limits<double>::infinity()) ||
            e.time_to_separation != 0.0) {
          fail("END event without time_to_contact = inf, time_to_separation = 0", where);
        }
      }
      if (e.distance > 0.0 && !(std::abs(e.normal.norm() - 1.0) <= 1e-6)) {
        fail("normal not unit length", where);
      }
      if (e.body_a == e.body_b) fail("event of a body with itself", where);
      const PairKey key = pairKey(e.body_a, e.body_b);
      if (!seen.insert(key).second) fail("pair reported twice in one predict", where);
      if (!ended) {
        active.insert(key);
        contact_time[key] = e.time_to_contact;
        numbers[key] = e.pair;
      }
      if (e.pair < 0) fail("negative pair number", where);
      if (!numbers_seen.insert(e.pair).second) fail("two events share a pair number", where);

      // Both bodies are nameable, body_a's id sorts first.
      const wp::BodyDesc* da = nullptr;
      const wp::BodyDesc* db = nullptr;
      try {
        da = &world_.desc(e.body_a);
        db = &world_.desc(e.body_b);
      } catch (const std::invalid_argument&) {
        if (!tainted_) fail("desc() throws for a body of an event", where);
      }
      if (da != nullptr && db != nullptr && db->id < da->id) fail("body_a's id sorts after body_b's", where);

      if (tainted_) continue;
      const ModelBody* ma = lookup(e.body_a);
      const ModelBody* mb = lookup(e.body_b);
      if (ma == nullptr || mb == nullptr) fail("event names a body the caller cannot name", where);
      if (da->id != ma->desc.id || db->id != mb->desc.id) fail("desc() names another body", where);
      const bool was_active = active_.count(key) != 0;
      if (ended && !was_active) fail("END for a pair not active at the previous predict", where);
      if (e.state == wp::ContactState::kBegin && was_active) fail("BEGIN for an active pair", where);
      if (was_active && numbers_.at(key) != e.pair) fail("pair number changed before the END", where);
      if (e.state == wp::ContactState::kOngoing && !was_active) {
        fail("ONGOING for a pair not active at the previous predict", where);
      }
      if (!ended && (!ma->live || !mb->live)) fail("contact predicted for a removed body", where);
      if (!ended && !rules_.allowed(ma->desc, mb->desc)) fail("contact for a pair the rules deny", where);
    }
    if (world_.stats().contacts != contacts) fail("stats().contacts differs from the events", "");

    if (!tainted_) {
      for (const PairKey& key : active_) {
        if (seen.count(key) == 0) fail("an active pair vanished without an END event", "");
      }
      if (world_.bodyCount() != liveCount()) fail("bodyCount() differs from the live bodies", "");
      for (const ModelBody& b : bodies_) {
        if (world_.contains(b.handle) != nameable(b)) {
          fail("contains() differs from the documented handle lifetime",
               str(b.handle) + (b.live ? " live" : " removed"));
        }
      }
      checkOverlapsNow(contact_time);
    }
    active_ = std::move(active);
    numbers_ = std::move(numbers);
  }

  // No false negative now: two live boxes of moderate size and position that clearly overlap
  // (the oracle's separating-axis test on boxes shrunk by a part in 1e6) must have a contact
  // event at time 0, unless the rules deny the pair.
  void checkOverlapsNow(const std::map<PairKey, double>& contact_time) {
    forEachClearOverlap([&](const ModelBody& a, const ModelBody& b) {
      const auto it = contact_time.find(pairKey(a.handle, b.handle));
      const std::string detail = str(a.handle) + "-" + str(b.handle);
      if (it == contact_time.end()) fail("overlapping boxes without a contact event", detail);
      if (it->second != 0.0) fail("overlapping boxes with time_to_contact > 0", detail);
    });
  }

  Input& in_;
  wp::WorldConfig config_;
  wp::ProximityWorld world_;
  wp::PairRules rules_;  // the rules the world uses, as the harness set them
  std::vector<ModelBody> bodies_;
  std::set<PairKey> active_;
  std::map<PairKey, std::int32_t> numbers_;  // pair numbers of the active pairs
  int predicts_ = 0;
  int next_id_ = 0;
  bool tainted_ = false;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return wp_fuzz::runHarness<Harness>(data, size);
}
