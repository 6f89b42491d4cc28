// The AVX-512 kernel: 8 lanes a register, the same kernel as the AVX2 one (sim/kernel/simd_kernel.ipp);
// this file alone is compiled with -mavx512f -mavx512dq -mfma and runs only where the CPU has them.
#include <sleef.h>

#include <utility>
#include <xsimd/xsimd.hpp>

#include <cmath>
#include <new>

#include "geometry/formulas.hpp"
#include "geometry/table_formulas.hpp"
#include "leak/leak_formulas.hpp"
#include "numeric/atan2.hpp"
#include "numeric/sin_cos.hpp"
#include "sim/kernel/flatten.hpp"
#include "sim/kernel/simd_engine.hpp"

#ifndef ROTLEAK_SIMD512_GROUPS
#define ROTLEAK_SIMD512_GROUPS 4
#endif

namespace rotleak::simd::avx512_kernel {

namespace {
using B = xsimd::batch<double, xsimd::avx512f>;
using M = B::batch_bool_type;
constexpr int W = 8;
constexpr int G = ROTLEAK_SIMD512_GROUPS;
inline unsigned bits(const M& m) { return static_cast<unsigned>(static_cast<__mmask8>(m)); }
inline B fused_fms(const B& a, const B& b, const B& c) {
  return B(_mm512_fmsub_pd(static_cast<__m512d>(a), static_cast<__m512d>(b), static_cast<__m512d>(c)));
}
inline B sleef_atan2(const B& y, const B& x) {
  return B(Sleef_atan2d8_u35avx512f(static_cast<__m512d>(y), static_cast<__m512d>(x)));
}
using U = xsimd::batch<std::uint64_t, xsimd::avx512f>;
inline U mul_wide(const U& a, const U& b) {
  return U(_mm512_mul_epu32(static_cast<__m512i>(a), static_cast<__m512i>(b)));
}
}  // namespace

bool available() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("fma");
}

// the pack, then the kernel over it
#include "sim/kernel/simd_pack.ipp"
// the lanes and their collision step, written once for every table
#include "sim/kernel/simd_lanes.ipp"
// the stadium's part of the step
#include "sim/kernel/simd_kernel.ipp"
// and on any other table
#include "sim/kernel/simd_table.ipp"
// the draws use the kernel's pack
#include "sim/kernel/simd_draws.ipp"

}  // namespace rotleak::simd::avx512_kernel
