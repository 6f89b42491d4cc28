// ROTLEAK_KERNEL_FLATTEN, the attribute of the kernel's collision step (lane_step, sim/kernel/simd_lanes.ipp) and
// flights_kernel: [[gnu::flatten]], every call inlined into the one hot loop (docs/performance.md, "Why the kernel is
// written as it is"), but nothing under AddressSanitizer: there each inlined call keeps its own poisoned stack slots,
// and the flattened kernel ran the sanitized tests hundreds of times slower than the Release build and took a quarter
// of an hour to compile. Sanitized builds check memory, not inlining.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define ROTLEAK_KERNEL_FLATTEN
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ROTLEAK_KERNEL_FLATTEN
#endif
#endif
#ifndef ROTLEAK_KERNEL_FLATTEN
#define ROTLEAK_KERNEL_FLATTEN [[gnu::flatten]]
#endif
