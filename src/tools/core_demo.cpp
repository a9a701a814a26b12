// Command-line demo of the core: a built-in robot cell (a two-link arm turning about its base,
// two people and a forklift crossing the cell, a static shelf) stepped at a fixed rate. Each
// cycle every body's pose and velocity are set, the world predicts contacts within the
// horizon, and the events are printed, earliest first.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scenes.hpp"  // test/shared: the motions of the scene
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

struct Options {
  int cycles = 120;
  double rate = 10.0;    // Hz
  double horizon = 2.0;  // s
  bool quiet = false;    // only BEGIN and END lines
};

void usage() {
  std::printf(
      "usage: core_demo [--cycles N] [--rate HZ] [--horizon S] [--quiet]\n"
      "  Steps a built-in robot cell and prints predicted contact events.\n");
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](double* out) {
      if (i + 1 >= argc) return false;
      char* end = nullptr;
      *out = std::strtod(argv[++i], &end);
      return end != nullptr && *end == '\0' && std::isfinite(*out);
    };
    double v = 0.0;
    if (a == "--cycles" && value(&v) && v >= 1) {
      o->cycles = static_cast<int>(v);
    } else if (a == "--rate" && value(&v) && v > 0) {
      o->rate = v;
    } else if (a == "--horizon" && value(&v) && v >= 0) {
      o->horizon = v;
    } else if (a == "--quiet") {
      o->quiet = true;
    } else {
      return false;
    }
  }
  return true;
}

const char* stateName(wp::ContactState s) {
  switch (s) {
    case wp::ContactState::kBegin:
      return "BEGIN  ";
    case wp::ContactState::kOngoing:
      return "ONGOING";
    case wp::ContactState::kEnd:
      return "END    ";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parse(argc, argv, &opt)) {
    usage();
    return 2;
  }

  wp::ProximityWorld world;
  auto add = [&](const std::string& id, const std::string& label, wp::BodyGroup group,
                 const wp::Shape& shape, double margin, const wp::BodyMotion& m) {
    return world.addBody(wp::BodyDesc{id, label, group, shape, margin}, m);
  };
  const double omega = 0.6;  // rad/s, the arm's yaw rate
  const wp::BodyHandle base = add("arm_base", "robot", wp::BodyGroup::kRobot,
                                  wp::Shape::cylinder(0.25, 0.8), 0.05, wp::BodyMotion());
  world.setMotion(base, [] {
    wp::BodyMotion m;
    m.position = Eigen::Vector3d(0, 0, 0.4);
    return m;
  }());
  const wp::BodyHandle upper =
      add("arm_upper", "robot", wp::BodyGroup::kRobot, wp::Shape::box({0.6, 0.1, 0.1}), 0.05,
          wp_test::turningLink(0, 0.6, 0.9, omega));
  const wp::BodyHandle tool = add("arm_tool", "robot", wp::BodyGroup::kRobot,
                                  wp::Shape::sphere(0.15), 0.05, wp_test::turningLink(0, 1.3, 0.9, omega));
  const wp::BodyHandle alice = add("person_alice", "person", wp::BodyGroup::kObject,
                                   wp::Shape::box({0.25, 0.25, 0.9}), 0.2, wp::BodyMotion());
  const wp::BodyHandle bob = add("person_bob", "person", wp::BodyGroup::kObject,
                                 wp::Shape::capsule(0.25, 1.3), 0.2, wp::BodyMotion());
  const wp::BodyHandle forklift = add("forklift_1", "forklift", wp::BodyGroup::kObject,
                                      wp::Shape::box({1.2, 0.6, 1.0}), 0.3, wp::BodyMotion());
  wp::BodyMotion shelf_pose;
  shelf_pose.position = Eigen::Vector3d(-2.5, 0.0, 1.0);
  add("shelf_1", "shelf", wp::BodyGroup::kObject, wp::Shape::box({0.4, 1.5, 1.0}), 0.0, shelf_pose);

  std::printf("workspace_proximity core demo: %d cycles at %.1f Hz, horizon %.2f s\n", opt.cycles,
              opt.rate, opt.horizon);
  std::printf("bodies: arm_base, arm_upper, arm_tool (robot); person_alice, person_bob, "
              "forklift_1, shelf_1 (objects)\n\n");

  int begins = 0, ends = 0;
  for (int cycle = 0; cycle < opt.cycles; ++cycle) {
    const double t = cycle / opt.rate;
    world.setMotion(upper, wp_test::turningLink(t, 0.6, 0.9, omega));
    world.setMotion(tool, wp_test::turningLink(t, 1.3, 0.9, omega));
    // The tool sphere sits at the end of the upper link: radius 1.3 m from the base.
    world.setMotion(alice, wp_test::shuttle(t, {4.5, 1.0, 0.9}, {1.2, 0.6, 0.9}, 8.0));
    wp::BodyMotion bob_m = wp_test::shuttle(t, {-1.0, -4.0, 0.9}, {-0.6, -1.2, 0.9}, 6.0);
    world.setMotion(bob, bob_m);
    world.setMotion(forklift, wp_test::shuttle(t, {2.0, 6.0, 1.0}, {2.0, -6.0, 1.0}, 10.0));

    const std::vector<wp::PairEvent>& events = world.predict(opt.horizon);
    bool header = false;
    for (const wp::PairEvent& e : events) {
      if (e.state == wp::ContactState::kBegin) ++begins;
      if (e.state == wp::ContactState::kEnd) ++ends;
      if (opt.quiet && e.state == wp::ContactState::kOngoing) continue;
      if (!header) {
        std::printf("t = %5.2f s  (%zu events)\n", t, events.size());
        header = true;
      }
      const std::string& a = world.desc(e.body_a).id;
      const std::string& b = world.desc(e.body_b).id;
      if (e.state == wp::ContactState::kEnd) {
        std::printf("  %s %-13s <-> %-13s no longer predicted\n", stateName(e.state), a.c_str(),
                    b.c_str());
      } else {
        std::printf(
            "  %s %-13s <-> %-13s contact in %5.2f s (%3.0f%% of horizon), until %5.2f s, "
            "distance %5.2f m, closing %5.2f m/s\n",
            stateName(e.state), a.c_str(), b.c_str(), e.time_to_contact,
            opt.horizon > 0 ? 100.0 * e.time_to_contact / opt.horizon : 0.0,
            e.time_to_separation, e.distance, e.closing_speed);
      }
    }
  }
  const wp::WorldStats& s = world.stats();
  std::printf("\n%d BEGIN and %d END events over %d cycles; last cycle: %d bodies, %d broad-phase "
              "pairs, %d after rules, %d after per-axis time of impact, %d contacts\n",
              begins, ends, opt.cycles, s.bodies, s.broad_pairs, s.allowed_pairs,
              s.axis_candidates, s.contacts);
  return 0;
}
