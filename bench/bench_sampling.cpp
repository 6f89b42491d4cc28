// Efficiency of importance sampling: the same scene run with ensemble.sampling = uniform
// and = mupo in this one process; at the times where P(t) ~ 1e-4, 1e-6, 1e-8 (located on the mupo
// curve), the work-normalised variance ratio
//     gain = (var_uniform * time_uniform) / (var_mupo * time_mupo).
// var_uniform is the binomial P (1 - P) / N_uniform at that P (exact for uniform sampling, and the
// only estimate where a uniform run of this size has no survivor left); var_mupo is the squared
// standard error of the weighted estimate, at least the Poisson error of the exponential part that
// only the uniform component carries (fits.cpp's alpha_p_err). Writes a CSV of both curves for
// python3 -m rotleak.plot.sampling (PYTHONPATH=build/python). Reports, never fails on time.
// Usage: bench_sampling [OUT.csv] [--uniform N] [--mupo N] [--t-max T]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "analysis/fits.hpp"
#include "io/scene_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/tally/survival.hpp"

using namespace rotleak;

namespace {

struct Measured {
  SurvivalCurve curve;
  KappaFit kappa;
  double seconds = 0;
};

Measured run(const Scene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult r = run_ensemble(scene, RunOptions{});
  Measured m;
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.curve = survival_curve(scene, r.tally);
  m.kappa = fit_kappa(m.curve, scene.kappa_window.from, scene.kappa_window.to);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  std::string csv;
  std::uint64_t n_uniform = 10000000, n_mupo = 10000000;
  double t_max = 4e7;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--uniform") && i + 1 < argc)
      n_uniform = std::stoull(argv[++i]);
    else if (!std::strcmp(argv[i], "--mupo") && i + 1 < argc)
      n_mupo = std::stoull(argv[++i]);
    else if (!std::strcmp(argv[i], "--t-max") && i + 1 < argc)
      t_max = std::stod(argv[++i]);
    else
      csv = argv[i];
  }
  // The stationary s_L = 0 scene: its tail P ~ 1.4e-4 (2500 / t) reaches 1e-8 near t = 4e7. A coarse
  // grid (dt = 50) keeps the tallies small; kappa on [0, 1000].
  const std::string text =
      std::string("[leak]\nwidth = \"0.01\"\nstart = \"0\"\n[run]\nfast_forward = true\nt_max = ") +
      std::to_string(t_max) + "\n[observe]\nsurvival_dt = 50\n[fit]\nkappa_window = [0, 1000]\n";
  Scene uniform = parse_scene(text, {"ensemble.particles=" + std::to_string(n_uniform), "ensemble.seed=21"}, "bench");
  Scene mupo = parse_scene(
      text, {"ensemble.particles=" + std::to_string(n_mupo), "ensemble.seed=22", "ensemble.sampling=mupo"}, "bench");
  std::fprintf(stderr, "bench_sampling: uniform %llu particles ...\n", static_cast<unsigned long long>(n_uniform));
  const Measured u = run(uniform);
  std::fprintf(stderr, "bench_sampling: mupo %llu particles ...\n", static_cast<unsigned long long>(n_mupo));
  const Measured m = run(mupo);

  std::printf(
      "s_L = 0 stationary, t_max = %g, fast-forward on, 2 threads; uniform %llu particles in %.1f s, mupo "
      "(eps = 0.5, |p| in [1e-12, 0.05]) %llu particles in %.1f s\n\n",
      t_max, static_cast<unsigned long long>(n_uniform), u.seconds, static_cast<unsigned long long>(n_mupo), m.seconds);
  std::printf("| P level | t | P (mupo) | rel. error mupo | rel. error uniform | uniform survivors | gain |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (double level : {1e-4, 1e-6, 1e-8}) {
    std::size_t i = 0;
    while (i + 1 < m.curve.t.size() && m.curve.P(i) > level) ++i;
    if (m.curve.P(i) > level || m.curve.effective(i) < 10) {
      std::printf("| %g | - | not reached or not resolved by the mupo run (t_max %g) | | | | |\n", level, t_max);
      continue;
    }
    const double P = m.curve.P(i), n_u = static_cast<double>(n_uniform);
    const double fit = m.kappa.ok ? std::exp(m.kappa.log_amplitude - m.kappa.value * m.curve.t[i]) : 0.0;
    const double err_m = std::max(m.curve.P_err(i), std::sqrt(m.curve.max_weight * fit / static_cast<double>(n_mupo)));
    const double var_u = P * (1 - P) / n_u, var_m = err_m * err_m;
    const double gain = (var_u * u.seconds) / (var_m * m.seconds);
    std::printf("| %g | %g | %.3g | %.2g | %.2g | %llu | %.3g |\n", level, m.curve.t[i], P, err_m / P,
                std::sqrt(var_u) / P, static_cast<unsigned long long>(u.curve.survivors[i]), gain);
  }
  if (!csv.empty()) {
    std::ofstream out(csv);
    out.precision(17);
    out << "t,P_uniform,err_uniform,survivors_uniform,P_mupo,err_mupo,effective_mupo\n";
    double next = 0;  // every grid point up to t = 2000, then 200 per decade
    for (std::size_t i = 0; i < m.curve.t.size(); ++i) {
      if (m.curve.t[i] > 2000 && m.curve.t[i] < next) continue;
      next = m.curve.t[i] * std::pow(10.0, 1.0 / 200);
      out << m.curve.t[i] << ',' << u.curve.P(i) << ',' << u.curve.P_err(i) << ',' << u.curve.survivors[i] << ','
          << m.curve.P(i) << ',' << m.curve.P_err(i) << ',' << m.curve.effective(i) << '\n';
    }
    std::fprintf(stderr, "bench_sampling: wrote %s\n", csv.c_str());
  }
  return 0;
}
