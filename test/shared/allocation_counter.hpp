#pragma once
/// Heap allocations of a test binary. allocation_counter.cpp replaces the global operator new
/// and delete (malloc/free underneath) and counts every new; link it into the tests that prove
/// "no allocation per steady-state cycle" (test_allocations, test_joint_predictor).

namespace wp_test {

/// Global operator new / new[] calls in this process so far.
long allocationCount();

}  // namespace wp_test
