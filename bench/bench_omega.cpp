// Timings of the exact omega toolkit: certified partial quotients, long rational
// expansions, and the MUPO covering at N ~ 3162 and N ~ 10^6.
#include <benchmark/benchmark.h>

#include "analysis/continued_fraction.hpp"
#include "analysis/covering.hpp"

using namespace rotleak;

static void BM_certified_cf_ln19_40_terms(benchmark::State& state) {
  const ExactReal x = ExactReal::parse("ln(19)");
  for (auto _ : state) benchmark::DoNotOptimize(certified_cf(x, 40));
}
BENCHMARK(BM_certified_cf_ln19_40_terms)->Unit(benchmark::kMillisecond);

// A rational with 10^5-digit numerator and denominator (seeded), first 10^4 partial quotients.
static void BM_rational_1e5_digits_1e4_terms(benchmark::State& state) {
  gmp_randclass rng(gmp_randinit_default);
  rng.seed(1);
  mpz_class ten;
  mpz_ui_pow_ui(ten.get_mpz_t(), 10, 99999);
  mpq_class q(ten + rng.get_z_range(ten * 9), ten + rng.get_z_range(ten * 9));
  q.canonicalize();
  for (auto _ : state) {
    const auto terms = cf_of_rational(q, 10000);
    if (terms.size() != 10000 || rational_of_cf(terms) == q)
      state.SkipWithError("expected 10^4 terms of a longer expansion");
    benchmark::DoNotOptimize(terms);
  }
}
BENCHMARK(BM_rational_1e5_digits_1e4_terms)->Unit(benchmark::kMillisecond);

static void covering(benchmark::State& state, const char* omega, const char* delta) {
  CoveringInput in;
  in.omega = ExactReal::parse(omega);
  in.delta = ExactReal::parse(delta);
  std::uint64_t n = 0;
  for (auto _ : state) n = mupo_covering(in).N;
  state.SetLabel(std::string("omega = ") + omega + ", N = " + std::to_string(n));
}
BENCHMARK_CAPTURE(covering, rational_1e7, "2/3", "1e-7")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(covering, irrational_1e7, "ln(19)", "1e-7")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(covering, rational_1e12, "100/101", "1e-12")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(covering, irrational_1e12, "ln(19)", "1e-12")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
