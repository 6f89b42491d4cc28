// Bit-identity of two runs of one scene: every tally (the estimator's exact sums too) and every particle's escape
// record. What the engine tests
// share (tests/test_table_runs.cpp: the kernel against the scalar core on every table; tests/test_gpu.cpp: the GPU
// engine against it). A failure counts the particles that differ, the escape's s apart from the rest (it alone
// takes the atan2 of an arc hit, where two libraries' functions once differed).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "sim/engine/engine.hpp"

namespace rotleak::test {

inline void expect_same_run(const RunResult& a, const RunResult& b, const std::string& what) {
  EXPECT_EQ(a.tally.collisions, b.tally.collisions) << what;
  EXPECT_EQ(a.tally.escaped, b.tally.escaped) << what;
  EXPECT_EQ(a.tally.survived, b.tally.survived) << what;
  EXPECT_EQ(a.tally.stuck, b.tally.stuck) << what;
  EXPECT_EQ(a.tally.escapes_per_bin, b.tally.escapes_per_bin) << what;
  EXPECT_EQ(a.tally.escapes_by_leak, b.tally.escapes_by_leak) << what;
  EXPECT_EQ(a.tally.collision_density, b.tally.collision_density) << what;
  EXPECT_TRUE(a.tally.collision_density_w == b.tally.collision_density_w) << what << ": the weighted f_c";
  EXPECT_TRUE(a.tally.estimator == b.tally.estimator) << what << ": the survival estimator's sums";
  ASSERT_EQ(a.records.size(), b.records.size()) << what;
  std::size_t differ = 0, s_differ = 0, first = a.records.size();
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    const EscapeRecord &x = a.records[i], &y = b.records[i];
    const bool other = x.t != y.t || x.collisions != y.collisions || x.fate != y.fate || x.leak != y.leak;
    differ += other;
    s_differ += x.s != y.s;
    if ((other || x.s != y.s) && first == a.records.size()) first = i;
  }
  EXPECT_EQ(differ, 0u) << what << ": particles whose time, collisions, fate or leak differ (the first: " << first
                        << ")";
  EXPECT_EQ(s_differ, 0u) << what << ": particles whose escape's s differs (the first: " << first << ")";
}

}  // namespace rotleak::test
