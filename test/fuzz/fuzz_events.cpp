// libFuzzer harness over the event tracker (event_tracker.hpp) alone: cycles of reports whose
// times to contact the input chooses, so that the events' order is sometimes coherent (times
// shrinking by a cycle, the last order's insertion sort and merge), sometimes scrambled (most
// keys far from their last place: the radix sort), with ties at +0 and -0, a few negative
// times, +infinity and denormals.
//
// Input: byte 0 sets the number of pairs (8 to 263), byte 1 the tracker's initial capacity
// (1 to 64: the pool grows within a run); then one cycle after another until the input ends: a
// byte that calls clear() when it is 0xFF, then one byte per pair: bits 0-1 say whether the pair
// is reported and how its time is chosen (0 not reported; 1 its last time less a cycle plus a
// small step from bits 2-7; 2 a fresh time from the next two bytes, 0 to 4 s; 3 a special value
// picked by bits 2-4: +0, -0, +infinity, a denormal, the last time again, a jump of bits 5-7
// half-seconds, or a small negative time).
//
// Checks, after every cycle: the events are exactly the reported pairs (BEGIN when the pair was
// not reported in the cycle before, else ONGOING) and one END (+infinity) for each pair reported
// in the cycle before and not in this one (none after clear()), each once, in the order of a
// full sort by (time, body a, body b) with -0 taken for +0; every event's time is the reported
// one.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "fuzz_input.hpp"
#include "workspace_proximity/event_tracker.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr double kCycle = 1.0 / 30.0;  // s
constexpr double kInf = std::numeric_limits<double>::infinity();

// Pair i's bodies: a few distinct first bodies (ties on the first body), unique second ones.
int bodyA(int i) { return (i * 37) % 17; }
int bodyB(int i) { return 100 + i; }

double specialTime(std::uint8_t op, double last) {
  switch ((op >> 2) & 7) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return kInf;
    case 3: return std::numeric_limits<double>::denorm_min() * (1 + (op >> 5));
    case 4: return last;
    case 5: return last + 0.5 * (op >> 5);
    default: return -1e-4 * (op >> 5);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  wp_fuzz::Input in(data, size);
  const int pairs = 8 + in.byte();
  wp::EventTracker tracker(1 + in.byte() % 64);
  std::vector<double> last(static_cast<std::size_t>(pairs), 1.0);  // last time reported
  std::vector<char> was(static_cast<std::size_t>(pairs), 0);        // reported last cycle
  std::vector<char> now(static_cast<std::size_t>(pairs), 0);
  using Row = std::tuple<double, int, int, int>;  // time (+0 for -0), a, b, state
  std::vector<Row> expected, got;
  for (int cycle = 0; !in.empty() && cycle < 4096; ++cycle) {
    if (in.byte() == 0xFF) {
      tracker.clear();
      std::fill(was.begin(), was.end(), 0);
    }
    tracker.beginCycle();
    expected.clear();
    for (int i = 0; i < pairs; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      const std::uint8_t op = in.byte();
      now[k] = 0;
      double t = 0.0;
      switch (op & 3) {
        case 0: break;
        case 1: t = last[k] - kCycle + ((op >> 2) - 32) / 256.0; break;
        case 2: t = in.u16() / 16384.0; break;
        default: t = specialTime(op, last[k]); break;
      }
      if ((op & 3) == 0 || std::isnan(t)) {
        if (was[k]) expected.emplace_back(kInf, bodyA(i), bodyB(i), static_cast<int>(wp::ContactState::kEnd));
        continue;
      }
      now[k] = 1;
      last[k] = t;
      wp::PairEvent e;
      e.body_a = wp::BodyHandle{bodyA(i), 0};
      e.body_b = wp::BodyHandle{bodyB(i), 0};
      e.time_to_contact = t;
      e.time_to_separation = t;
      tracker.report(static_cast<std::uint64_t>(i), e);
      const wp::ContactState state = was[k] ? wp::ContactState::kOngoing : wp::ContactState::kBegin;
      expected.emplace_back(t + 0.0, bodyA(i), bodyB(i), static_cast<int>(state));
    }
    tracker.endCycle();
    std::sort(expected.begin(), expected.end(), [](const Row& x, const Row& y) {
      return std::make_tuple(std::get<0>(x), std::get<1>(x), std::get<2>(x)) <
             std::make_tuple(std::get<0>(y), std::get<1>(y), std::get<2>(y));
    });
    got.clear();
    for (const wp::PairEvent& e : tracker.events()) {
      got.emplace_back(e.time_to_contact + 0.0, e.body_a.index, e.body_b.index, static_cast<int>(e.state));
    }
    if (got != expected) {
      std::string detail = "cycle " + std::to_string(cycle) + (tracker.radixSorted() ? " (radix)" : "") +
                           ": " + std::to_string(got.size()) + " events, " +
                           std::to_string(expected.size()) + " expected";
      for (std::size_t j = 0; j < std::max(got.size(), expected.size()); ++j) {
        if (j < got.size() && j < expected.size() && got[j] == expected[j]) continue;
        if (j < got.size()) {
          detail += "; first difference at " + std::to_string(j) + ": got " + wp_fuzz::str(std::get<0>(got[j])) +
                    " " + std::to_string(std::get<1>(got[j])) + "-" + std::to_string(std::get<2>(got[j]));
        }
        break;
      }
      wp_fuzz::fail("events differ from a full sort of the reports", detail);
    }
    was.swap(now);
  }
  return 0;
}
