// The Lyapunov exponent two independent ways, and divergence growth by orbit class.
//  1. Tangent dynamics: a Jacobi field (J, J') carried along a long double trajectory of the flow:
//     flight tau: J += tau J'; reflection on an arc of radius r at angle phi to the normal:
//     J' -= 2 J / (r cos phi) (the mirror equation; straight edges leave J' alone).
//  2. Shadow divergence: the slope in t of the ensemble mean of ln(divergence from the truth).
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "verify/shadow.hpp"

namespace rotleak {

struct LyapunovEstimate {
  double per_time = 0, per_time_error = 0;
  double per_collision = 0, per_collision_error = 0;
  double time = 0;             ///< total time (tangent) or fit window length (divergence)
  std::size_t collisions = 0;  ///< collisions used
  std::size_t samples = 0;     ///< batches (tangent) or particles (divergence)
  double window_from = 0, window_to = 0;
};

/// Along one trajectory of `collisions` collisions (leak ignored), 20 batch means for the error.
LyapunovEstimate tangent_lyapunov(const Scene& scene, const InitialDraw& draw, std::size_t collisions);

/// From shadow runs (tier `tier` against the truth): per particle the least-squares slope of
/// ln(divergence) against t and against k over [t_from, t_to] (collisions with divergence < 1e-3
/// only), averaged; error = s.d. / sqrt(particles).
LyapunovEstimate divergence_lyapunov(const std::vector<ShadowResult>& runs, std::size_t tier, double t_from,
                                     double t_to);

/// Mean increase of ln(divergence) per collision, before saturation, split by the truth's class of
/// the collision (MUPO phase or chaotic).
struct ClassGrowth {
  double mupo_per_collision = 0, chaotic_per_collision = 0;
  std::size_t mupo_steps = 0, chaotic_steps = 0;
};
ClassGrowth class_growth(const std::vector<ShadowResult>& runs, std::size_t tier);

/// Which law a divergence series follows, from collision `from` on (before 1e-3): the power law
/// ln d = a + z ln k against the exponential ln d = a + rate k, each with its R^2.
struct GrowthLaw {
  double power = 0, power_r2 = 0;
  double rate = 0, rate_r2 = 0;
  std::size_t points = 0;
  bool polynomial() const { return power_r2 > rate_r2; }
};
GrowthLaw growth_law(const std::vector<double>& divergence, std::size_t from = 10);

/// A bouncing-ball (MUPO) orbit: from the top edge at x = -0.9 d/2, Birkhoff p = p0 > 0 small.
InitialDraw bouncing_ball_draw(const Scene& scene, double p0);

struct LyapunovStudyOptions {
  std::string tier = "float128";                  ///< tier whose divergence from the truth is fitted
  std::size_t particles = 200, collisions = 100;  ///< shadow runs and their length
  std::size_t tangent_collisions = 2000000;
  double from = 10, to = 150;  ///< fit window, in time since creation
  double mupo_p = 1e-4;        ///< p0 of the bouncing-ball orbit followed in double
  int threads = 0;
};

/// The exponent both ways, the growth by class, and the growth law of one bouncing-ball orbit.
struct LyapunovStudy {
  LyapunovStudyOptions options;
  LyapunovEstimate tangent, divergence;
  ClassGrowth by_class;
  std::size_t mupo_collisions = 0;
  GrowthLaw mupo_law;
  double relative_difference() const { return std::abs(divergence.per_time - tangent.per_time) / tangent.per_time; }
};
LyapunovStudy lyapunov_study(const Scene& scene, const LyapunovStudyOptions& options);

}  // namespace rotleak
