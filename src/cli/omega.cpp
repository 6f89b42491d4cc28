// rotleak omega VALUE [--terms K] [--max-den Q] [--eps E] [--digits D] [--json]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>

#include "analysis/continued_fraction.hpp"
#include "cli/commands.hpp"
#include "numeric/input.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct OmegaArgs {
  std::string value;
  long long terms = 20;
  std::string max_den = "1000";
  std::string eps;
  int digits = 30;
  int convergents = 12;
  bool json_out = false;
};

int run_omega(const OmegaArgs& a) {
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

  const CertifiedExpansion cf = certified_cf(x, static_cast<std::size_t>(a.terms));
  const std::vector<Fraction> conv = convergents(cf.terms);
  const Enclosure value = enclose_decimal(x, a.digits);
  const BestApproximations best = best_approximations(x, max_den);

  json j;
  json o;
  o["input"] = a.value;
  o["exact"] = x.text();
  o["rational"] = x.is_rational();
  o["value"] = {{"lo", value.lo}, {"hi", value.hi}, {"digits", a.digits}};
  json terms = json::array();
  for (const auto& t : cf.terms) terms.push_back(t.fits_slong_p() ? json(t.get_si()) : json(t.get_str()));
  o["cf"] = terms;
  o["certified_terms"] = cf.terms.size();
  o["expansion_complete"] = cf.complete;
  o["precision_bits"] = cf.precision_bits;
  json cv = json::array(), errs = json::array();
  for (std::size_t k = 0; k < conv.size() && k < static_cast<std::size_t>(a.convergents); ++k) {
    cv.push_back({conv[k].p.get_str(), conv[k].q.get_str()});
    const Enclosure e = signed_error(x, conv[k]);
    errs.push_back({{"p", conv[k].p.get_str()}, {"q", conv[k].q.get_str()}, {"error_lo", e.lo}, {"error_hi", e.hi}});
  }
  o["convergents"] = cv;
  o["convergent_errors"] = errs;
  json ba = json::array();
  for (const auto& f : best.list) {
    const Enclosure e = signed_error(x, f);
    ba.push_back({{"p", f.p.get_str()}, {"q", f.q.get_str()}, {"error_lo", e.lo}, {"error_hi", e.hi}});
  }
  o["best_approximations"] = {{"max_den", max_den.get_str()}, {"list", ba}, {"truncated", best.truncated}};
  json second = json::array();
  for (const auto& f : best_second_kind(cf.terms, max_den)) second.push_back({f.p.get_str(), f.q.get_str()});
  o["best_approximations_second_kind"] = second;
  json semis = json::array();
  for (std::size_t k = 1; k < cf.terms.size() && k <= static_cast<std::size_t>(a.convergents); ++k) {
    json list = json::array();
    for (const auto& f : semiconvergents(cf.terms, k)) list.push_back({f.p.get_str(), f.q.get_str()});
    if (!list.empty()) semis.push_back({{"between_convergents", {k - 1, k}}, {"list", list}, {"truncated", cf.terms[k] - 1 > 20}});
  }
  o["semiconvergents"] = semis;
  std::smatch m;
  static const std::regex liouville(R"(\s*liouville\(\s*(\d+)\s*\)\s*)");
  if (std::regex_match(a.value, m, liouville)) {
    json sums = json::array();
    for (unsigned K = 1; K <= 4; ++K) sums.push_back(liouville_partial_sum(std::stoul(m[1]), K).get_str());
    o["liouville_partial_sums"] = sums;  // S_K = sum_{k<=K} b^-(k!), exact
  }
  std::optional<Fraction> within;
  if (eps) {
    within = smallest_denominator_within(x, *eps);
    o["smallest_q_within_eps"] = within ? json{{"eps", a.eps}, {"p", within->p.get_str()}, {"q", within->q.get_str()}}
                                        : json(nullptr);
  }
  j["omega"] = o;

  if (a.json_out) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("omega = %s%s\n", x.text().c_str(), x.is_rational() ? " (rational)" : "");
  std::printf("value in [%s, %s]\n", value.lo.c_str(), value.hi.c_str());
  std::printf("continued fraction (%zu %s): [", cf.terms.size(),
              cf.complete ? "terms, complete" : (x.is_rational() ? "terms" : "certified terms"));
  for (std::size_t k = 0; k < cf.terms.size(); ++k)
    std::printf("%s%s", k == 0 ? "" : (k == 1 ? "; " : ", "), cf.terms[k].get_str().c_str());
  std::printf("]%s\n", cf.precision_bits ? (" (certified at " + std::to_string(cf.precision_bits) + " bits)").c_str() : "");
  std::printf("convergents p/q and omega - p/q (certified enclosure):\n");
  for (const auto& e : errs)
    std::printf("  %s/%s   [%s, %s]\n", e["p"].get<std::string>().c_str(), e["q"].get<std::string>().c_str(),
                e["error_lo"].get<std::string>().c_str(), e["error_hi"].get<std::string>().c_str());
  std::printf("best approximations with q <= %s%s:\n", max_den.get_str().c_str(), best.truncated ? " (list truncated)" : "");
  for (const auto& e : ba)
    std::printf("  %s/%s   [%s, %s]\n", e["p"].get<std::string>().c_str(), e["q"].get<std::string>().c_str(),
                e["error_lo"].get<std::string>().c_str(), e["error_hi"].get<std::string>().c_str());
  if (eps && within) std::printf("smallest q with |omega - p/q| < %s: %s/%s\n", a.eps.c_str(), within->p.get_str().c_str(), within->q.get_str().c_str());
  return 0;
}

}  // namespace

Command add_omega(CLI::App& app) {
  auto a = std::make_shared<OmegaArgs>();
  CLI::App* sub = app.add_subcommand("omega", "Continued fraction, convergents and best approximations of an exact omega");
  sub->add_option("value", a->value, "omega: 1008/1009, 1e-4, ln(19), 2*ln(19), sqrt(2), pi, e, golden, liouville(10), ...")->required();
  sub->add_option("--terms", a->terms, "Certified partial quotients to compute (default 20)");
  sub->add_option("--max-den", a->max_den, "Largest denominator for best approximations (default 1000)");
  sub->add_option("--eps", a->eps, "Also find the smallest q with |omega - p/q| < eps");
  sub->add_option("--digits", a->digits, "Digits of the value's certified enclosure (default 30)");
  sub->add_option("--convergents", a->convergents, "How many convergents to list with their errors (default 12)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_omega(*a); }};
}

}  // namespace rotleak::cli
