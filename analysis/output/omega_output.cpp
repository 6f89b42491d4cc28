#include "analysis/output/omega_output.hpp"

#include "io/text.hpp"
#include "numeric/input.hpp"

namespace rotleak {

namespace {

json approximation_json(const Approximation& a) {
  return {{"p", a.f.p.get_str()}, {"q", a.f.q.get_str()}, {"error_lo", a.error.lo}, {"error_hi", a.error.hi}};
}

void approximation_lines(std::string& out, const std::vector<Approximation>& list) {
  for (const auto& a : list)
    appendf(out, "  %s/%s   [%s, %s]\n", a.f.p.get_str().c_str(), a.f.q.get_str().c_str(), a.error.lo.c_str(),
            a.error.hi.c_str());
}

}  // namespace

json omega_json(const OmegaReport& r, const std::string& eps_text) {
  json o;
  o["input"] = r.input;
  o["exact"] = r.x.text();
  o["rational"] = r.x.is_rational();
  o["value"] = {{"lo", r.value.lo}, {"hi", r.value.hi}, {"digits", r.options.digits}};
  json terms = json::array();
  for (const auto& t : r.cf.terms) terms.push_back(t.fits_slong_p() ? json(t.get_si()) : json(t.get_str()));
  o["cf"] = terms;
  o["certified_terms"] = r.cf.terms.size();
  o["expansion_complete"] = r.cf.complete;
  o["precision_bits"] = r.cf.precision_bits;
  json cv = json::array(), errs = json::array();
  for (const auto& a : r.convergents) {
    cv.push_back({a.f.p.get_str(), a.f.q.get_str()});
    errs.push_back(approximation_json(a));
  }
  o["convergents"] = cv;
  o["convergent_errors"] = errs;
  json ba = json::array();
  for (const auto& a : r.best) ba.push_back(approximation_json(a));
  o["best_approximations"] = {{"max_den", r.options.max_den.get_str()}, {"list", ba}, {"truncated", r.best_truncated}};
  json second = json::array();
  for (const auto& f : r.second_kind) second.push_back({f.p.get_str(), f.q.get_str()});
  o["best_approximations_second_kind"] = second;
  json semis = json::array();
  for (const auto& run : r.semiconvergents) {
    json list = json::array();
    for (const auto& f : run.list) list.push_back({f.p.get_str(), f.q.get_str()});
    semis.push_back({{"between_convergents", {run.k - 1, run.k}}, {"list", list}, {"truncated", run.truncated}});
  }
  o["semiconvergents"] = semis;
  if (!r.liouville_partial_sums.empty()) o["liouville_partial_sums"] = r.liouville_partial_sums;
  if (r.options.eps)
    o["smallest_q_within_eps"] =
        r.within_eps ? json{{"eps", eps_text}, {"p", r.within_eps->p.get_str()}, {"q", r.within_eps->q.get_str()}}
                     : json(nullptr);
  json j;
  j["omega"] = o;
  return j;
}

std::string omega_text(const OmegaReport& r, const std::string& eps_text) {
  std::string out;
  appendf(out, "omega = %s%s\n", r.x.text().c_str(), r.x.is_rational() ? " (rational)" : "");
  appendf(out, "value in [%s, %s]\n", r.value.lo.c_str(), r.value.hi.c_str());
  appendf(out, "continued fraction (%zu %s): [", r.cf.terms.size(),
          r.cf.complete ? "terms, complete" : (r.x.is_rational() ? "terms" : "certified terms"));
  for (std::size_t k = 0; k < r.cf.terms.size(); ++k)
    appendf(out, "%s%s", k == 0 ? "" : (k == 1 ? "; " : ", "), r.cf.terms[k].get_str().c_str());
  appendf(out, "]%s\n",
          r.cf.precision_bits ? (" (certified at " + std::to_string(r.cf.precision_bits) + " bits)").c_str() : "");
  appendf(out, "convergents p/q and omega - p/q (certified enclosure):\n");
  approximation_lines(out, r.convergents);
  appendf(out, "best approximations with q <= %s%s:\n", r.options.max_den.get_str().c_str(),
          r.best_truncated ? " (list truncated)" : "");
  approximation_lines(out, r.best);
  if (r.options.eps && r.within_eps)
    appendf(out, "smallest q with |omega - p/q| < %s: %s/%s\n", eps_text.c_str(), r.within_eps->p.get_str().c_str(),
            r.within_eps->q.get_str().c_str());
  return out;
}

OmegaReport compute_omega(const OmegaRequest& a) {
  const ExactReal x = parse_exact_input("omega", a.value);
  if (a.terms < 1 || a.terms > 1000000) throw InputError("--terms", std::to_string(a.terms), "must be in [1, 10^6]");
  if (a.digits < 1 || a.digits > 100000) throw InputError("--digits", std::to_string(a.digits), "must be in [1, 10^5]");
  mpz_class max_den;
  if (max_den.set_str(a.max_den, 10) != 0 || max_den < 1)
    throw InputError("--max-den", a.max_den, "must be an integer >= 1");
  std::optional<ExactReal> eps;
  if (!a.eps.empty()) {
    eps = parse_exact_input("--eps", a.eps);
    if (eps->sign() <= 0) throw InputError("--eps", a.eps, "must be > 0");
  }
  OmegaReportOptions opt;
  opt.terms = static_cast<std::size_t>(a.terms);
  opt.max_den = max_den;
  opt.digits = a.digits;
  opt.convergents = static_cast<std::size_t>(a.convergents < 0 ? 0 : a.convergents);
  opt.eps = eps;
  try {
    return omega_report(a.value, x, opt);
  } catch (const std::domain_error& e) {  // beyond what the certified expansion can reach
    throw InputError("omega", "\"" + a.value + "\"", e.what());
  }
}

}  // namespace rotleak
