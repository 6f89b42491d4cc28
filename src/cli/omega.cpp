// rotleak omega VALUE [--terms K] [--max-den Q] [--eps E] [--digits D] [--json]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/omega_output.hpp"
#include "numeric/input.hpp"

namespace rotleak::cli {

namespace {

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

  OmegaReportOptions opt;
  opt.terms = static_cast<std::size_t>(a.terms);
  opt.max_den = max_den;
  opt.digits = a.digits;
  opt.convergents = static_cast<std::size_t>(a.convergents < 0 ? 0 : a.convergents);
  opt.eps = eps;
  OmegaReport r;
  try {
    r = omega_report(a.value, x, opt);
  } catch (const std::domain_error& e) {  // beyond what the certified expansion can reach
    throw InputError("omega", "\"" + a.value + "\"", e.what());
  }
  if (a.json_out)
    std::cout << omega_json(r, a.eps).dump(2) << "\n";
  else
    std::fputs(omega_text(r, a.eps).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_omega(CLI::App& app) {
  auto a = std::make_shared<OmegaArgs>();
  CLI::App* sub =
      app.add_subcommand("omega", "Continued fraction, convergents and best approximations of an exact omega");
  sub->add_option("value", a->value,
                  "omega: 1008/1009, 1e-4, ln(19), 2*ln(19), sqrt(2), pi, e, golden, liouville(10), ...")
      ->required();
  sub->add_option("--terms", a->terms, "Certified partial quotients to compute (default 20)");
  sub->add_option("--max-den", a->max_den, "Largest denominator for best approximations (default 1000)");
  sub->add_option("--eps", a->eps, "Also find the smallest q with |omega - p/q| < eps");
  sub->add_option("--digits", a->digits, "Digits of the value's certified enclosure (default 30)");
  sub->add_option("--convergents", a->convergents, "How many convergents to list with their errors (default 12)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_omega(*a); }};
}

}  // namespace rotleak::cli
