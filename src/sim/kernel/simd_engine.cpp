// The AVX2 kernel (4 lanes a register; this file alone is compiled with -mavx2 -mfma) and the entry
// points that choose the kernel for the width the KernelScene asks for. The kernel itself is
// sim/kernel/simd_kernel.ipp, shared with the AVX-512 one (sim/kernel/simd_avx512.cpp).
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

#ifndef ROTLEAK_SIMD_GROUPS
#define ROTLEAK_SIMD_GROUPS 4
#endif

namespace rotleak::simd {

namespace avx512_kernel {  // sim/kernel/simd_avx512.cpp
bool available();
Pause run_kernel(const KernelScene& S, KernelState& state, Exchange& x);
Pause run_table_kernel(const KernelScene& S, KernelState& state, Exchange& x);
void rough_kernel(double r, double r_over_L, const double* ay, const double* ax, double* out, std::size_t n);
void cell_kernel(const KernelScene& S, const double* t, double* out, std::size_t n);
void probe_kernel(const KernelScene& S, const Probe* points, ProbeResult* out, std::size_t n);
double flights_kernel(const KernelScene& S, const Start* starts, std::uint64_t steps);
int pack_size();
void birkhoff_kernel(const KernelScene& S, const double* s, const double* p, Start* out, std::size_t n);
void flow_kernel(const KernelScene& S, const double* u, double* vx, double* vy, std::size_t n);
void uniform_kernel(const KernelScene& S, std::uint64_t seed, double window, std::uint64_t first, std::size_t n,
                    Start* out);
}  // namespace avx512_kernel

namespace avx2_kernel {
namespace {
using B = xsimd::batch<double, xsimd::avx2>;
using M = B::batch_bool_type;
constexpr int W = 4;
constexpr int G = ROTLEAK_SIMD_GROUPS;
inline unsigned bits(const M& m) { return static_cast<unsigned>(_mm256_movemask_pd(static_cast<__m256d>(m))); }
inline B fused_fms(const B& a, const B& b, const B& c) {
  return B(_mm256_fmsub_pd(static_cast<__m256d>(a), static_cast<__m256d>(b), static_cast<__m256d>(c)));
}
inline B sleef_atan2(const B& y, const B& x) {
  return B(Sleef_atan2d4_u35avx2(static_cast<__m256d>(y), static_cast<__m256d>(x)));
}
using U = xsimd::batch<std::uint64_t, xsimd::avx2>;
inline U mul_wide(const U& a, const U& b) {
  return U(_mm256_mul_epu32(static_cast<__m256i>(a), static_cast<__m256i>(b)));
}
}  // namespace
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
}  // namespace avx2_kernel

bool available() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

int widest_lanes() { return avx512_kernel::available() ? 8 : available() ? 4 : 0; }

bool lanes_available(int lanes) { return lanes == 4 ? available() : lanes == 8 ? avx512_kernel::available() : false; }

Pause run(const KernelScene& S, KernelState& state, Exchange& x) {
  if (S.table && S.lanes == 8) return avx512_kernel::run_table_kernel(S, state, x);
  if (S.table) return avx2_kernel::run_table_kernel(S, state, x);
  if (S.lanes == 8) return avx512_kernel::run_kernel(S, state, x);
  return avx2_kernel::run_kernel(S, state, x);
}

void time_cells(const KernelScene& S, const double* t, double* out, std::size_t n) {
  if (S.lanes == 8)
    avx512_kernel::cell_kernel(S, t, out, n);
  else
    avx2_kernel::cell_kernel(S, t, out, n);
}

void probe(const KernelScene& S, const Probe* points, ProbeResult* out, std::size_t n) {
  if (S.lanes == 8)
    avx512_kernel::probe_kernel(S, points, out, n);
  else
    avx2_kernel::probe_kernel(S, points, out, n);
}

void rough_arc_s(int lanes, double r, double r_over_L, const double* ay, const double* ax, double* out, std::size_t n) {
  if (lanes == 8)
    avx512_kernel::rough_kernel(r, r_over_L, ay, ax, out, n);
  else
    avx2_kernel::rough_kernel(r, r_over_L, ay, ax, out, n);
}

double flights_only(const KernelScene& S, const Start* starts, std::uint64_t steps) {
  return S.lanes == 8 ? avx512_kernel::flights_kernel(S, starts, steps) : avx2_kernel::flights_kernel(S, starts, steps);
}

void birkhoff_states(const KernelScene& S, const double* s, const double* p, Start* out, std::size_t n) {
  if (S.lanes == 8)
    avx512_kernel::birkhoff_kernel(S, s, p, out, n);
  else
    avx2_kernel::birkhoff_kernel(S, s, p, out, n);
}

void flow_directions(const KernelScene& S, const double* u, double* vx, double* vy, std::size_t n) {
  if (S.lanes == 8)
    avx512_kernel::flow_kernel(S, u, vx, vy, n);
  else
    avx2_kernel::flow_kernel(S, u, vx, vy, n);
}

void uniform_starts(const KernelScene& S, std::uint64_t seed, double window, std::uint64_t first, std::size_t n,
                    Start* out) {
  if (S.lanes == 8)
    avx512_kernel::uniform_kernel(S, seed, window, first, n, out);
  else
    avx2_kernel::uniform_kernel(S, seed, window, first, n, out);
}

int pack_lanes(int lanes) { return lanes == 8 ? avx512_kernel::pack_size() : avx2_kernel::pack_size(); }

}  // namespace rotleak::simd
