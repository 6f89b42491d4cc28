#include "verify/lyapunov.hpp"

#include <cmath>
#include <limits>

#include "verify/line_fit.hpp"
#include "verify/trace.hpp"

namespace rotleak {

namespace {

struct MeanSd {
  double mean = 0, se = 0;
};

MeanSd mean_se(const std::vector<double>& v) {
  MeanSd m;
  if (v.empty()) return m;
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(v.size());
  double ss = 0;
  for (double x : v) ss += (x - m.mean) * (x - m.mean);
  if (v.size() > 1) m.se = std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
  return m;
}

}  // namespace

namespace {

/// The Jacobi field's jump at a collision, J' -= 2 J / (rho cos(phi)) with rho the boundary's radius of curvature
/// there (positive where it focuses, negative where it disperses): that denominator rho cos(phi), or 0 on a straight
/// piece (no jump). The stadium's arcs focus with radius r; a table's arc focuses (clockwise) or disperses.
double jump_denominator(const Model<double>& model, const TraceStep<double>& s) {
  if (s.piece != Piece::right_arc && s.piece != Piece::left_arc) return 0;
  const Vec2<double> n = model.stadium.inward_normal(s.piece, s.q);
  const double cos_phi = std::abs(dot(s.v, n));
  return num_traits<double>::to_double(model.stadium.r()) * cos_phi;
}
double jump_denominator(const TableModel<double>& model, const TraceStep<double, int>& s) {
  const TablePiece<double>& p = model.table.piece(s.piece);
  if (p.kind == PieceKind::segment) return 0;
  if (p.kind == PieceKind::ellipse) {
    // radius of curvature a^2 b^2 |g|^3 with g = (x / a^2, y / b^2) from the centre, cos(phi) = |v . g| / |g|
    const Vec2<double> g = reflection_axis(p, s.q.x, s.q.y);
    const double rho_cos = p.ea2 * p.eb2 * dot(g, g) * std::abs(dot(s.v, g));
    return p.clockwise ? rho_cos : -rho_cos;
  }
  const double cos_phi = std::abs(dot(s.v, Vec2<double>{s.q.x - p.cx, s.q.y - p.cy})) * p.inv_rho;
  return (p.clockwise ? p.rho : -p.rho) * cos_phi;  // clockwise: the table inside the circle, focusing
}

template <class M>
LyapunovEstimate tangent_on(M model, const InitialDraw& draw, std::size_t collisions) {
  // the leak and t_max play no part: follow the flow for the requested collisions
  model.t_max = std::numeric_limits<double>::infinity();
  constexpr std::size_t kBatches = 20;
  const std::size_t per_batch = collisions / kBatches > 0 ? collisions / kBatches : 1;
  double J = 1, Jp = 0, t_prev = draw.tau, log_sum = 0, batch_log = 0, batch_t0 = draw.tau;
  std::vector<double> rate_t, rate_k;
  const std::size_t done = trace(model, draw, collisions, [&](const auto& s) {
    const double tau = s.t - t_prev;
    t_prev = s.t;
    J += tau * Jp;
    if (const double d = jump_denominator(model, s); d != 0) Jp -= 2 * J / d;
    const double norm = std::hypot(J, Jp);
    J /= norm;
    Jp /= norm;
    log_sum += std::log(norm);
    batch_log += std::log(norm);
    if (s.k % per_batch == 0 && rate_t.size() < kBatches) {
      rate_t.push_back(batch_log / (s.t - batch_t0));
      rate_k.push_back(batch_log / static_cast<double>(per_batch));
      batch_log = 0;
      batch_t0 = s.t;
    }
    return true;
  });
  LyapunovEstimate e;
  e.collisions = done;
  e.time = t_prev - draw.tau;
  e.per_time = log_sum / e.time;
  e.per_collision = log_sum / static_cast<double>(done);
  e.per_time_error = mean_se(rate_t).se;
  e.per_collision_error = mean_se(rate_k).se;
  e.samples = rate_t.size();
  return e;
}

}  // namespace

LyapunovEstimate tangent_lyapunov(const Scene& scene, const InitialDraw& draw, std::size_t collisions) {
  if (scene.on_table()) return tangent_on(table_model_of<double>(scene), draw, collisions);
  return tangent_on(model_of<double>(scene), draw, collisions);
}

LyapunovEstimate divergence_lyapunov(const std::vector<ShadowResult>& runs, std::size_t tier, double t_from,
                                     double t_to) {
  std::vector<double> per_t, per_k;
  std::size_t used = 0;
  for (const ShadowResult& r : runs) {
    if (tier >= r.tiers.size()) continue;
    const TierShadow& ts = r.tiers[tier];
    std::vector<double> t, k, y;
    for (std::size_t i = 0; i < ts.collisions; ++i) {
      const double time = r.truth.t[i] - r.draw.tau;
      if (time < t_from || time > t_to || !(ts.divergence[i] > 0) || ts.divergence[i] > 1e-3) continue;
      t.push_back(time);
      k.push_back(static_cast<double>(i + 1));
      y.push_back(std::log(ts.divergence[i]));
    }
    if (y.size() < 10) continue;
    per_t.push_back(least_squares(t, y).slope);
    per_k.push_back(least_squares(k, y).slope);
    used += y.size();
  }
  LyapunovEstimate e;
  const MeanSd mt = mean_se(per_t), mk = mean_se(per_k);
  e.per_time = mt.mean;
  e.per_time_error = mt.se;
  e.per_collision = mk.mean;
  e.per_collision_error = mk.se;
  e.samples = per_t.size();
  e.collisions = used;
  e.window_from = t_from;
  e.window_to = t_to;
  e.time = t_to - t_from;
  return e;
}

ClassGrowth class_growth(const std::vector<ShadowResult>& runs, std::size_t tier) {
  ClassGrowth g;
  double mupo = 0, chaotic = 0;
  for (const ShadowResult& r : runs) {
    if (tier >= r.tiers.size()) continue;
    const TierShadow& ts = r.tiers[tier];
    for (std::size_t i = 1; i < ts.collisions; ++i) {
      const double a = ts.divergence[i - 1], b = ts.divergence[i];
      if (!(a > 0) || !(b > 0) || b > 1e-3) continue;
      const double step = std::log(b) - std::log(a);
      if (r.truth.mupo[i])
        mupo += step, ++g.mupo_steps;
      else
        chaotic += step, ++g.chaotic_steps;
    }
  }
  if (g.mupo_steps) g.mupo_per_collision = mupo / static_cast<double>(g.mupo_steps);
  if (g.chaotic_steps) g.chaotic_per_collision = chaotic / static_cast<double>(g.chaotic_steps);
  return g;
}

GrowthLaw growth_law(const std::vector<double>& div, std::size_t from) {
  std::vector<double> k, lnk, y;
  for (std::size_t i = from; i < div.size(); ++i) {
    if (!(div[i] > 0) || div[i] > 1e-3) continue;
    k.push_back(static_cast<double>(i + 1));
    lnk.push_back(std::log(static_cast<double>(i + 1)));
    y.push_back(std::log(div[i]));
  }
  GrowthLaw g;
  g.points = y.size();
  if (y.size() < 3) return g;
  const LineFit p = least_squares(lnk, y), e = least_squares(k, y);
  g.power = p.slope;
  g.power_r2 = p.r2;
  g.rate = e.slope;
  g.rate_r2 = e.r2;
  return g;
}

InitialDraw bouncing_ball_draw(const Scene& scene, double p0) {
  // s of x = -0.9 d/2 on the top edge: 1 - 0.9 (d/2) / L, rounded once
  InitialDraw d;
  d.s = round_exact<double>(ExactReal::parse("1") -
                            ExactReal::parse("0.9") * scene.d / ExactReal::parse("2") /
                                (ExactReal::parse("2") * scene.d + ExactReal::parse("2") * ExactReal::pi() * scene.r));
  d.p = p0;
  d.tau = 0;
  return d;
}

LyapunovStudy lyapunov_study(const Scene& scene, const LyapunovStudyOptions& opt) {
  LyapunovStudy s;
  s.options = opt;
  const InitialConditions ic = initial_conditions(scene);
  s.tangent = tangent_lyapunov(scene, ic.draw(0), opt.tangent_collisions);
  ShadowOptions so;
  so.tiers = {opt.tier};
  so.collisions = opt.collisions;
  std::vector<std::uint64_t> ids(opt.particles);
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  const std::vector<ShadowResult> runs = shadow_many(scene, ids, so, opt.threads);
  s.divergence = divergence_lyapunov(runs, 0, opt.from, opt.to);
  s.by_class = class_growth(runs, 0);
  if (scene.on_table()) return s;  // the bouncing-ball orbit below is the stadium's (no MUPO law on another table)
  ShadowOptions bb;
  bb.tiers = {"double"};
  bb.collisions = 8000;
  const ShadowResult ball = shadow_from(scene, bouncing_ball_draw(scene, opt.mupo_p), bb);
  s.mupo_collisions = ball.tiers[0].collisions;
  s.mupo_law = growth_law(ball.tiers[0].divergence);
  return s;
}

}  // namespace rotleak
