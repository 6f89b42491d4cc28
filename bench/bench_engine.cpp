// Cost per collision of the generic core in each tier, on the same particle ids in one process.
// Reports collisions/s (items_per_second); compare tiers by their ratio, never by absolute times.
#include <benchmark/benchmark.h>

#include "numeric/mpfr_fixed.hpp"
#include "sim/model/particle.hpp"

using namespace rotleak;

template <class R>
static void BM_collisions(benchmark::State& state) {
  const Model<R> model(ExactReal::parse("2"), ExactReal::parse("1"), ExactReal::parse("0.01"), ExactReal::parse("0"),
                       ExactReal::parse(state.range(0) ? "2/3" : "0"), 2000);
  const InitialConditions ic(1, InitKind::birkhoff, 4, 1, 1);
  NoCollisionObserver<R> none;
  std::uint64_t id = 0, collisions = 0;
  for (auto _ : state) {
    const ParticleEnd e = run_particle(model, initial_state(model.stadium, ic.draw(id++)), none);
    collisions += e.collisions;
    benchmark::DoNotOptimize(e);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(collisions));
  state.SetLabel(num_traits<R>::name() + (state.range(0) ? ", omega = 2/3" : ", stationary s_L = 0"));
}

BENCHMARK_TEMPLATE(BM_collisions, float)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_collisions, double)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_collisions, long double)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_collisions, mpfr256)->Arg(0)->Arg(1);

BENCHMARK_MAIN();
