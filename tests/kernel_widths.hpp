// The vectorised kernel's widths this CPU runs, for the tests that run each one.
#pragma once

#include <cstdio>
#include <vector>

#include "sim/kernel/simd_engine.hpp"

namespace rotleak::test {

/// The kernels this CPU runs (4: AVX2, 8: AVX-512), each to be checked; a width it lacks is said skipped.
inline std::vector<int> kernel_widths() {
  std::vector<int> w;
  for (int lanes : {4, 8}) {
    if (simd::lanes_available(lanes))
      w.push_back(lanes);
    else
      std::printf("[ skipped  ] the %d-lane kernel: this CPU does not run it\n", lanes);
  }
  return w;
}

}  // namespace rotleak::test
