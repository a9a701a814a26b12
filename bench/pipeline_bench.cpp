// Pipeline benchmark: the robot-cell scene through the whole core (swept bounds,
// sweep-and-prune, pair rules, contact window, narrow phase, event tracking), with the time
// per cycle split by stage. Writes a markdown table to stdout (and --out FILE).
//
// Scene (wp_test::RobotCell, test/shared/scenes.hpp): an arm of L link boxes (L/6 chains of 6 links) turning about the base at 0.8 rad/s
// (each link with the matching linear and angular velocity), plus N tracked objects (people
// 0.5 x 0.5 x 1.8 m, every tenth a 2.4 x 1.2 x 2.0 m forklift) walking at 0.3-1.5 m/s in a
// 16 m square around it, bouncing at the walls, margins 0.2 / 0.3 / 0.02 m. 30 Hz steps.
// Second table: the node's load as scripts/bench-node makes it (load_generator's walkers: N
// upright boxes, people 0.5 x 0.5 x 1.8 m and every tenth a 2.4 x 1.2 x 2.0 m forklift, at
// 0.3-1.5 m/s in a square of side 3 sqrt(N) m, the node's label margins 0.2 / 0.3 m, no
// robot), horizon 2 s: the node's predict stage without ROS.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "scenes.hpp"  // test/shared: the robot cell
#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/cycle_runner.hpp"
#include "workspace_proximity/rules/cycle_timing.hpp"
#include "workspace_proximity/rules/joint_predictor.hpp"
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/rules/track_growth.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

struct Result {
  int links, objects;
  double horizon;
  double median_us, p99_us;
  double stage_us[5];  // bounds, broad, axis, narrow, events (means)
  double pairs, candidates, contacts, queries;
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

// The shipped config's person label (config/proximity_monitor.yaml): margin 0.2 m plus
// position_error 0.05 m, growing with velocity_error 0.3 m/s, max_accel 4 m/s^2, max_speed 2 m/s.
wp::LabelSettings shippedPerson() {
  wp::LabelSettings person;
  person.margin = 0.20;
  person.position_error = 0.05;
  person.velocity_error = 0.3;
  person.max_accel = 4.0;
  person.max_speed = 2.0;
  return person;
}

// load_generator's walkers (src/tools/load_generator.cpp) as the node turns them into bodies.
// With `growth`, people get the shipped person label as the node gives it (TrackTable::advance:
// margin + position_error, the growth of a track measured `age` seconds before the cycle; the
// node's timer cycles see ages of 0 to one input period, so the ages cycle through that range).
class NodeWalkers {
 public:
  NodeWalkers(wp::ProximityWorld* world, int count, bool growth = false, std::uint32_t seed = 11)
      : world_(world), half_(1.5 * std::sqrt(static_cast<double>(count))), growth_(growth) {
    wp_test::Rng rng(seed);
    for (int i = 0; i < count; ++i) {
      const bool forklift = i % 10 == 0;
      const double heading = rng.uniform(0, 2 * M_PI), speed = rng.uniform(0.3, 1.5);
      Walker w;
      w.position = Eigen::Vector3d(rng.uniform(-half_, half_), rng.uniform(-half_, half_),
                                   forklift ? 1.0 : 0.9);
      w.velocity = Eigen::Vector3d(speed * std::cos(heading), speed * std::sin(heading), 0.0);
      w.handle = world->addBody({"walker_" + std::to_string(i), forklift ? "forklift" : "person",
                                 wp::BodyGroup::kObject,
                                 wp::Shape::box(forklift ? Eigen::Vector3d(1.2, 0.6, 1.0)
                                                         : Eigen::Vector3d(0.25, 0.25, 0.9)),
                                 forklift ? 0.3 : (growth ? wp::trackMargin(person_) : 0.2)},
                                wp::BodyMotion());
      w.person = !forklift;
      walkers_.push_back(w);
    }
  }
  void step(double dt) {
    for (Walker& w : walkers_) {
      w.position += w.velocity * dt;
      for (int k = 0; k < 2; ++k) {
        if (std::abs(w.position[k]) > half_) w.velocity[k] = -w.velocity[k];
      }
      wp::BodyMotion m;
      m.position = w.position;
      m.linear_velocity = w.velocity;
      world_->setMotion(w.handle, m);
      if (growth_ && w.person) {
        const double age = (1.0 / 30.0) * ((steps_ * 7 + (&w - walkers_.data())) % 8) / 8.0;
        world_->setGrowth(w.handle, wp::trackGrowth(person_, w.velocity.norm(), age));
      }
    }
    ++steps_;
  }

 private:
  struct Walker {
    Eigen::Vector3d position, velocity;
    wp::BodyHandle handle;
    bool person = false;
  };
  wp::ProximityWorld* world_;
  double half_;
  bool growth_;
  const wp::LabelSettings person_ = shippedPerson();
  int steps_ = 0;
  std::vector<Walker> walkers_;
};

template <class Scene>
Result measure(wp::ProximityWorld& world, Scene&& step, double horizon, int cycles) {
  std::vector<double> total;
  Result r{0, 0, horizon, 0, 0, {0, 0, 0, 0, 0}, 0, 0, 0, 0};
  const int warmup = 30;
  for (int c = 0; c < warmup + cycles; ++c) {
    step(c);
    const auto start = std::chrono::steady_clock::now();
    world.predict(horizon);
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    if (c < warmup) continue;
    const wp::WorldStats& s = world.stats();
    total.push_back(us);
    const double stages[5] = {double(s.ns_bounds), double(s.ns_broad), double(s.ns_axis),
                              double(s.ns_narrow), double(s.ns_events)};
    for (int k = 0; k < 5; ++k) r.stage_us[k] += stages[k] / 1e3 / cycles;
    r.pairs += double(s.broad_pairs) / cycles;
    r.candidates += double(s.axis_candidates) / cycles;
    r.contacts += double(s.contacts) / cycles;
    r.queries += double(s.narrow_iterations) / cycles;
  }
  r.median_us = percentile(total, 0.5);
  r.p99_us = percentile(total, 0.99);
  return r;
}

Result run(int links, int objects, double horizon, int cycles) {
  wp::WorldConfig config;
  config.time_pair_stages = true;  // the stage split is what this benchmark reports
  wp::ProximityWorld world(config);
  wp_test::RobotCell cell(&world, links, objects);
  Result r = measure(world, [&](int c) { cell.step(c / 30.0, 1.0 / 30.0); }, horizon, cycles);
  r.links = links;
  r.objects = objects;
  return r;
}

Result runWalkers(int count, bool growth, double horizon, int cycles, bool stage_timers) {
  wp::WorldConfig config;
  config.time_pair_stages = stage_timers;
  wp::ProximityWorld world(config);
  NodeWalkers walkers(&world, count, growth);
  Result r = measure(world, [&](int) { walkers.step(1.0 / 30.0); }, horizon, cycles);
  r.objects = count;
  return r;
}

// The node's rules layer without ROS, fed as scripts/bench-node feeds the node:
// load_generator's walkers (same seed, cell 3 sqrt(N) m, boxes centred at z = 0, frame
// "world") as one array per 30 Hz step, each cycle at the next step's instant (the timer
// trigger: arrays are up to one period old), default parameters (what the node runs when no
// configuration is loaded: every label the default's margin 0.1 m, no growth) or the shipped
// person label. Times: the monitor's own stage laps (input: expiry, extrapolation, growth;
// predict: ProximityWorld::predict; then the report, status and SSM verdict), medians.
struct MonitorResult {
  double ingest_ms, input_ms, predict_ms, predict_p99_ms, report_ms;
  double events;
};

MonitorResult runMonitor(int count, bool shipped_person, bool ignore_people, int cycles) {
  wp::MonitorParams params;
  if (shipped_person) params.labels["person"] = shippedPerson();
  if (ignore_people) params.ignore_pairs.emplace_back("label:person", "label:person");
  wp::Monitor monitor(params, {}, {"/tracked_objects"}, false, nullptr);
  std::mt19937 rng(0);
  const double cell = std::round(30.0 * std::sqrt(static_cast<double>(count))) / 10.0;
  std::uniform_real_distribution<double> pos(-cell / 2, cell / 2), dir(0, 2 * M_PI), speed(0.3, 1.5);
  struct W { double x, y, vx, vy; };
  std::vector<W> walkers(static_cast<std::size_t>(count));
  for (W& w : walkers) {
    const double a = dir(rng), s = speed(rng);
    w = W{pos(rng), pos(rng), s * std::cos(a), s * std::sin(a)};
  }
  std::vector<std::string> ids;
  std::vector<wp::BoxObservation> boxes(walkers.size());
  for (std::size_t i = 0; i < walkers.size(); ++i) ids.push_back("walker_" + std::to_string(i));
  for (std::size_t i = 0; i < walkers.size(); ++i) {
    boxes[i].id = ids[i];
    boxes[i].label = i % 10 == 0 ? "forklift" : "person";
    boxes[i].dimensions = i % 10 == 0 ? Eigen::Vector3d(2.4, 1.2, 2.0) : Eigen::Vector3d(0.5, 0.5, 1.8);
  }
  wp::CycleRunner warm(&monitor), runner(&monitor);
  wp::CycleTiming scratch, arrival;
  const wp::Stamp period = 33333333;  // ns
  wp::Stamp now = 1000000000;
  double events = 0;
  std::vector<double> predict, report;  // ms per measured cycle
  const int warmup = 30;
  for (int c = 0; c < warmup + cycles; ++c) {
    for (std::size_t i = 0; i < walkers.size(); ++i) {
      W& w = walkers[i];
      w.x += w.vx / 30.0;
      w.y += w.vy / 30.0;
      if (std::abs(w.x) > cell / 2) w.vx = -w.vx;
      if (std::abs(w.y) > cell / 2) w.vy = -w.vy;
      boxes[i].position = Eigen::Vector3d(w.x, w.y, 0.0);
      boxes[i].linear_velocity = Eigen::Vector3d(w.vx, w.vy, 0.0);
    }
    // Published at a random point of the period, used at the next tick.
    const wp::Stamp stamp = now + period * ((c * 7) % 8) / 8;
    {
      wp::StageClock clock(c < warmup ? &scratch : &arrival);
      monitor.noteReceipt(0, stamp);
      monitor.ingest(0, stamp, stamp, Eigen::Isometry3d::Identity(), boxes);
      clock.lap(wp::CycleStage::kArrival);
    }
    now += period;
    // The node's cycle runner (reset, failure, timing) without a feed or outputs: kContacts is
    // the report, status and SSM (no message here). The warm-up cycles' times are not read.
    (c < warmup ? warm : runner).run(now, nullptr, nullptr);
    if (c >= warmup) {
      events += static_cast<double>(monitor.report().events->size()) / cycles;
      // ProximityWorld::predict is two laps (predictNear, predictEvents) with the status and
      // the SSM verdict between them; the report is those and the events' levels.
      const wp::CycleTiming& t = runner.timing();
      predict.push_back(t.last(wp::CycleStage::kNear) + t.last(wp::CycleStage::kPredict));
      report.push_back(t.last(wp::CycleStage::kSsm) + t.last(wp::CycleStage::kSafety) +
                       t.last(wp::CycleStage::kReport) + t.last(wp::CycleStage::kContacts));
    }
  }
  const wp::CycleTiming& timing = runner.timing();
  return MonitorResult{arrival.percentile(wp::CycleStage::kArrival, 0.5),
                       timing.percentile(wp::CycleStage::kInput, 0.5), percentile(predict, 0.5),
                       percentile(predict, 0.99), percentile(report, 0.5), events};
}

// The robot cell's arm as joints: one continuous joint about z per chain of 6 links (the
// chain's link turns with it); each link body sits on its chain's link at its radius and height.
class CellArm : public wp::KinematicModel {
 public:
  explicit CellArm(int chains) {
    root_ = "base";
    for (int c = 0; c < chains; ++c) {
      joints_.push_back({"chain_" + std::to_string(c), wp::JointType::kContinuous, false, 0.0, 0.0});
      links_.push_back({"chain_link_" + std::to_string(c), {c}, {0.0}, 0.0});
    }
  }
  void forward(const double* q, Eigen::Isometry3d* poses) const override {
    for (std::size_t c = 0; c < links_.size(); ++c) {
      poses[c] = Eigen::Isometry3d(Eigen::AngleAxisd(q[c], Eigen::Vector3d::UnitZ()));
    }
  }
};

// The same cell with the arm predicted from its joints: every cycle each chain's joint reading
// (position and velocity 0.8 rad/s) goes to the JointPredictor, whose keyframed paths (spaced by
// its arc bound, ~joint_path_tolerance 0.01 m, at most 16 segments) go to the core with setPath.
// `joints` false: the same links set with their constant twist (setMotion), as from tf. The
// time per cycle includes posing the arm.
class ArmCell {
 public:
  ArmCell(int links, int objects, bool joints)
      : joints_(joints), cell_(&world_, 0, objects),  // the objects only; the arm is added here
        chains_(std::max(1, links / 6)),
        predictor_(std::make_shared<CellArm>(chains_), wp::JointPredictorParams()) {
    for (int i = 0; i < links; ++i) {
      const int chain = i / 6, k = i % 6;
      Link l{wp::BodyHandle(), 0.25 + 0.25 * k, 0.5 + 0.2 * chain, 2 * M_PI * chain / chains_};
      const wp::Shape shape = wp::Shape::box({0.13, 0.06, 0.06});
      l.handle = world_.addBody({"link_" + std::to_string(i), "robot", wp::BodyGroup::kRobot, shape, 0.02},
                                wp::BodyMotion());
      Eigen::Isometry3d offset(Eigen::AngleAxisd(l.phase, Eigen::Vector3d::UnitZ()));
      offset.translation() = offset.linear() * Eigen::Vector3d(l.radius, 0, l.height);
      predictor_.addBody(chain, offset, shape.boundingRadius());
      arm_.push_back(l);
    }
  }
  // One cycle at t (s); returns its time in µs (arm posing and prediction).
  double cycle(double t, double horizon) {
    cell_.step(t, 1.0 / 30.0);
    const auto start = std::chrono::steady_clock::now();
    if (joints_) {
      const wp::Stamp now = wp::nanoseconds(100.0 + t);
      for (int j = 0; j < chains_; ++j) {
        predictor_.observe(j, now, std::remainder(wp_test::RobotCell::kOmega * t, 2 * M_PI),
                           wp_test::RobotCell::kOmega);
      }
      predictor_.predict(now, horizon, wp::BodyMotion());
      for (std::size_t i = 0; i < arm_.size(); ++i) {
        const wp::JointBodyPath& path = predictor_.body(static_cast<int>(i));
        world_.setPath(arm_[i].handle, path.segments.data(), static_cast<int>(path.segments.size()));
      }
    } else {
      for (const Link& l : arm_) {
        world_.setMotion(l.handle, wp_test::turningLink(t, l.radius, l.height, wp_test::RobotCell::kOmega, l.phase));
      }
    }
    world_.predict(horizon);
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  }
  const wp::WorldStats& stats() const { return world_.stats(); }
  int segments() const { return predictor_.segmentCount(); }

 private:
  struct Link {
    wp::BodyHandle handle;
    double radius, height, phase;
  };
  bool joints_;
  wp::ProximityWorld world_;
  wp_test::RobotCell cell_;
  int chains_;
  wp::JointPredictor predictor_;
  std::vector<Link> arm_;
};

struct ArmResult {
  Result twist, joint;
  double ratio_median = 0.0;  // median over cycles of joint / twist time (paired cycles)
  double segments = 0.0;
};

// Both cells stepped in the same loop, cycle by cycle (alternating which goes first), so that
// load from other processes falls on both alike; the ratio is the median of paired cycles.
ArmResult runArm(int links, int objects, double horizon, int cycles) {
  ArmCell twist(links, objects, false), joint(links, objects, true);
  std::vector<double> tt, jt, ratio;
  ArmResult r;
  r.twist = Result{links, objects, horizon, 0, 0, {0, 0, 0, 0, 0}, 0, 0, 0, 0};
  r.joint = r.twist;
  const int warmup = 30;
  for (int c = 0; c < warmup + cycles; ++c) {
    const double t = c / 30.0;
    double a, b;
    if (c % 2 == 0) {
      a = twist.cycle(t, horizon);
      b = joint.cycle(t, horizon);
    } else {
      b = joint.cycle(t, horizon);
      a = twist.cycle(t, horizon);
    }
    if (c < warmup) continue;
    tt.push_back(a);
    jt.push_back(b);
    ratio.push_back(b / a);
    r.twist.pairs += double(twist.stats().broad_pairs) / cycles;
    r.joint.pairs += double(joint.stats().broad_pairs) / cycles;
    r.twist.contacts += double(twist.stats().contacts) / cycles;
    r.joint.contacts += double(joint.stats().contacts) / cycles;
    r.segments += double(joint.segments()) / cycles;
  }
  r.twist.median_us = percentile(tt, 0.5);
  r.twist.p99_us = percentile(tt, 0.99);
  r.joint.median_us = percentile(jt, 0.5);
  r.joint.p99_us = percentile(jt, 0.99);
  r.ratio_median = percentile(ratio, 0.5);
  return r;
}

// The monitor-layer table (appended to `md`).
void monitorTable(std::ostringstream& md, int cycles, int monitor_count) {
  md << "\n## The node's rules layer (no ROS), fed as scripts/bench-node feeds the node\n\n"
     << "load_generator's walkers (same seed, cell 3 sqrt(N) m) as one array per 30 Hz step, each "
        "cycle at the next step's instant (arrays up to one period old), through Monitor::ingest "
        "and the cycle runner (Monitor::cycle): the node's input and predict stages without ROS (predict = "
        "ProximityWorld::predict; report = the event report, status and SSM verdict, the "
        "first part of the node's contacts stage). labels: \"defaults\" = no "
        "configuration loaded, as scripts/bench-node runs the node (every label the default's "
        "margin 0.1 m, no growth); \"shipped person\" = config/proximity_monitor.yaml's person "
        "label (margin 0.25 m growing by R(s) = min(0.3 s + 2 s², (2 + |v|) s)), so at a 2 s "
        "horizon every person pairs with everyone within several metres; \"person-person "
        "ignored\" adds ignore_pairs [label:person, label:person] (only pairs with a forklift "
        "are predicted: there is no robot in this scene). Medians over the cycles; arrival = "
        "Monitor::ingest of one array.\n\n"
     << "| objects | labels | arrival median ms | input median ms | predict median ms | predict p99 ms | report median ms | events |\n"
     << "|---:|---|---:|---:|---:|---:|---:|---:|\n";
  // 0: defaults, 1: the shipped person label, 2: the same with person-person pairs ignored.
  for (int labels = 0; labels < 3; ++labels) {
    for (int count : {100, 1000}) {
      if (monitor_count > 0 && (count != monitor_count || labels != 0)) continue;
      const MonitorResult r = runMonitor(count, labels > 0, labels == 2, cycles);
      static const char* const kLabels[] = {"defaults", "shipped person",
                                            "shipped person, person-person ignored"};
      char line[256];
      std::snprintf(line, sizeof line, "| %d | %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.0f |\n",
                    count, kLabels[labels], r.ingest_ms, r.input_ms, r.predict_ms,
                    r.predict_p99_ms, r.report_ms, r.events);
      md << line;
      std::fputs(line, stderr);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  int cycles = 600;
  bool joints_only = false;  // only the joint-space rows (issue 10)
  bool walkers_only = false;  // only the node's load (issue 14)
  bool growth_only = false;   // only its rows with the shipped person growth (profiling)
  bool monitor_only = false;  // only the rules layer's rows (profiling)
  int monitor_count = 0;      // --count N: only N objects there
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") cycles = 150;
    else if (a == "--joints-only") joints_only = true;
    else if (a == "--walkers") walkers_only = true;
    else if (a == "--growth") walkers_only = growth_only = true;
    else if (a == "--monitor") monitor_only = true;
    else if (a == "--count" && i + 1 < argc) monitor_count = std::atoi(argv[++i]);
  }
  std::ostringstream md;
  if (monitor_only) {
    monitorTable(md, cycles, monitor_count);
    std::fputs(md.str().c_str(), stdout);
    return 0;
  }
  const bool cell_rows = !joints_only && !walkers_only;
  if (cell_rows) {
    md << "# Pipeline benchmark (robot cell through the whole core)\n\n"
       << "Per cycle, after 30 warm-up cycles, " << cycles << " cycles each. Stage times are "
        "means; the stage timers themselves cost a little.\n\n"
       << "| links | objects | horizon s | median µs | p99 µs | bounds | broad | axis TOI | narrow | "
        "events | broad pairs | candidates | contacts | distance queries |\n"
       << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  }
  for (int links : {30, 60}) {
    if (!cell_rows) break;
    for (int objects : {10, 100, 200}) {
      for (double horizon : {0.0, 0.5, 2.0}) {
        const Result r = run(links, objects, horizon, cycles);
        char line[512];
        std::snprintf(line, sizeof line,
                      "| %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.0f | "
                      "%.0f | %.0f | %.0f |\n",
                      r.links, r.objects, r.horizon, r.median_us, r.p99_us, r.stage_us[0],
                      r.stage_us[1], r.stage_us[2], r.stage_us[3], r.stage_us[4], r.pairs,
                      r.candidates, r.contacts, r.queries);
        md << line;
        std::fputs(line, stderr);
      }
    }
  }
  if (!joints_only) {
    md << "\n## The node's load: load_generator's walkers, horizon 2 s\n\n"
       << "What `scripts/bench-node` feeds the node (no robot; see the top of pipeline_bench.cpp), "
          "through the core alone. predict = median of ProximityWorld::predict per cycle without "
          "the per-pair stage timers, as the node runs it; the stage split (means) comes from a "
          "second run with them. people: \"constant\" = margin 0.2 m and constant velocity; "
          "\"growth\" = the shipped person label as the node applies it (margin 0.25 m growing "
          "with velocity_error 0.3 m/s, max_accel 4 m/s², max_speed 2 m/s; track ages 0–33 ms), "
          "what the node runs with the shipped config.\n\n"
       << "| objects | people | predict median µs | predict p99 µs | bounds | broad | axis TOI | "
          "narrow | events | broad pairs | candidates | contacts | distance queries |\n"
       << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (bool growth : {false, true}) {
      if (growth_only && !growth) continue;
      for (int count : {100, 1000, 2000}) {
        if (growth && count > 1000) continue;  // 0.1 s a cycle: the point is made at 1 000
        const Result plain = runWalkers(count, growth, 2.0, cycles, false);
        const Result r = runWalkers(count, growth, 2.0, cycles, true);
        char line[512];
        std::snprintf(line, sizeof line,
                      "| %d | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.0f | %.0f | "
                      "%.0f | %.0f |\n",
                      count, growth ? "growth" : "constant", plain.median_us, plain.p99_us,
                      r.stage_us[0], r.stage_us[1], r.stage_us[2], r.stage_us[3], r.stage_us[4],
                      r.pairs, r.candidates, r.contacts, r.queries);
        md << line;
        std::fputs(line, stderr);
      }
    }
  }
  if (!joints_only && !growth_only) monitorTable(md, cycles, 0);
  // The arm from its joints (issue 10): cost per cycle, arm posing included, against the same
  // arm as constant twists.
  if (!walkers_only) {
    md << "\n## Robot cell with joint-space prediction\n\n"
     << "The arm posed every cycle (included in the time): constant twists per link (setMotion, "
        "as from tf) or the JointPredictor's keyframed paths from the chains' joint readings "
        "(setPath; ~joint_path_tolerance 0.01 m, at most 16 segments). Target: joint-space at "
        "most 1.5x the constant twist at 60 links + 200 objects, H = 2 s.\n\n"
     << "| links | objects | horizon s | constant twist median µs | p99 µs | joint-space median µs "
        "| p99 µs | ratio of medians | median paired ratio | segments | broad pairs twist / joint | contacts twist / joint |\n"
     << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  }
  for (int objects : {100, 200}) {
    if (walkers_only) break;
    for (double horizon : {0.5, 2.0}) {
      const ArmResult a = runArm(60, objects, horizon, cycles);
      char line[512];
      std::snprintf(line, sizeof line,
                    "| 60 | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %.1f | %.0f / %.0f | %.1f / %.1f |\n",
                    objects, horizon, a.twist.median_us, a.twist.p99_us, a.joint.median_us,
                    a.joint.p99_us, a.joint.median_us / a.twist.median_us, a.ratio_median, a.segments,
                    a.twist.pairs, a.joint.pairs, a.twist.contacts, a.joint.contacts);
      md << line;
      std::fputs(line, stderr);
    }
  }
  std::fputs(md.str().c_str(), stdout);
  if (!out.empty()) std::ofstream(out) << md.str();
  return 0;
}
