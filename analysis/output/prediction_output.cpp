#include "analysis/output/prediction_output.hpp"

#include <cmath>
#include <cstdlib>

#include "io/text.hpp"

namespace rotleak {

json prediction_json(const TailPrediction& p) {
  json cands = json::array();
  for (const LatticeTail& l : p.candidates)
    cands.push_back({{"rational", l.rational},
                     {"Q", l.Q},
                     {"eps", l.eps},
                     {"amplitude", l.amplitude},
                     {"free_fraction", l.free_fraction},
                     {"crossing", std::isfinite(l.crossing) ? json(l.crossing) : json(nullptr)},
                     {"end", nullable(l.end)},
                     {"forms", l.forms}});
  return {{"forms", p.forms},
          {"amplitude", p.amplitude},
          {"amplitude_error", p.amplitude * kModelAmplitudeError},
          {"end", nullable(p.end)},
          {"half", nullable(p.half)},
          {"rational", p.rational.empty() ? json(nullptr) : json(p.rational)},
          {"Q", p.Q},
          {"eps", p.eps},
          {"crossing", std::isfinite(p.crossing) ? json(p.crossing) : json(nullptr)},
          {"kappa0", p.kappa0},
          {"free_fraction", p.free_fraction},
          {"regime", p.regime},
          {"note", p.note},
          {"candidates", cands},
          {"curve", p.curve.empty() ? json(nullptr) : json(p.curve)}};
}

json prediction_document(const Scene& scene, const TailPrediction& p) {
  json doc = prediction_json(p);
  doc["scene"] = {{"d", scene.d_text},         {"r", scene.r_text},         {"width", scene.width_text},
                  {"start", scene.start_text}, {"omega", scene.omega_text}, {"t_max", scene.t_max}};
  return doc;
}

std::string prediction_text(const TailPrediction& p) {
  std::string out;
  appendf(out, "tail     : %s (regime %s)\n", p.forms ? "forms" : "none", p.regime.c_str());
  if (!p.rational.empty()) {
    appendf(out, "C        = %.4g +- %.2g (model)   (P ~ C / t from the lattice of 2 r omega = %s, Q = %lld)\n",
            p.amplitude, p.amplitude * kModelAmplitudeError, p.rational.c_str(), p.Q);
    if (p.end) appendf(out, "end      : t ~ %.4g (t P at a tenth of C; half by t ~ %.4g)\n", *p.end, *p.half);
    if (std::isfinite(p.crossing))
      appendf(out, "crossing : t ~ %.4g (C / t = exp(-kappa0 t), kappa0 = %.4g)\n", p.crossing, p.kappa0);
  }
  appendf(out, "note     : %s\n", p.note.c_str());
  return out;
}

std::string prediction_check(const TailPrediction& p, const TailAmplitude& m, const TailClass& k) {
  // a tail is seen when the class is not none (unresolved: seen, its weight not resolved)
  const bool seen = k.tail != "none";
  std::string out;
  if (!p.forms)
    return seen ? "a tail measured where the model predicts none (" + p.note + ")" : "no tail, as predicted";
  if (!seen) {
    appendf(out, "predicted a tail (C = %.4g, 2 r omega = %s), none measured", p.amplitude, p.rational.c_str());
    return out;
  }
  std::string ends;
  if (p.end && k.tail_end)
    appendf(ends, "; end: measured %.4g, predicted %.4g (t P at a tenth of C)", *k.tail_end, *p.end);
  if (!m.value) {
    // from = 0: P never stood 100 x above the fit where resolved, so there is no height to quote either
    std::string height;
    if (m.from > 0)
      appendf(height, "t P = %.3g at t = %g", m.height, m.from);
    else
      height = "P never exceeds 100 x the fit where resolved";
    appendf(out, "%s %s tail, as predicted (no flat t P to compare C with: %s, model C = %.4g)%s",
            std::string("aeiou").find(k.tail[0]) == std::string::npos ? "a" : "an", k.tail.c_str(), height.c_str(),
            p.amplitude, ends.c_str());
    return out;
  }
  const double model = p.amplitude * kModelAmplitudeError;
  const double err = std::sqrt(m.std_error * m.std_error + m.drift * m.drift + model * model);
  const double z = (*m.value - p.amplitude) / err;
  appendf(out, "predicted C = %.4g (2 r omega = %s), measured %.4g: %+.1f errors (model's %.0f%% included)%s",
          p.amplitude, p.rational.c_str(), *m.value, z, 100 * kModelAmplitudeError, ends.c_str());
  return (std::abs(z) <= 2 ? "tail as predicted: " : "tail NOT as predicted: ") + out;
}

}  // namespace rotleak
