// rotleak omega VALUE [--terms K] [--max-den Q] [--eps E] [--digits D] [--json]
#include <cstdio>
#include <iostream>

#include "analysis/output/omega_output.hpp"
#include "cli/commands.hpp"
#include "numeric/input.hpp"

namespace rotleak::cli {

namespace {

struct OmegaArgs {
  OmegaRequest request;
  bool json_out = false;
};

int run_omega(const OmegaArgs& a) {
  const OmegaReport r = compute_omega(a.request);
  if (a.json_out)
    std::cout << omega_json(r, a.request.eps).dump(2) << "\n";
  else
    std::fputs(omega_text(r, a.request.eps).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_omega(CLI::App& app) {
  auto a = std::make_shared<OmegaArgs>();
  CLI::App* sub =
      app.add_subcommand("omega", "Continued fraction, convergents and best approximations of an exact omega");
  sub->add_option("value", a->request.value,
                  "omega: 1008/1009, 1e-4, ln(19), 2*ln(19), sqrt(2), pi, e, golden, liouville(10), ...")
      ->required();
  sub->add_option("--terms", a->request.terms, "Certified partial quotients to compute (default 20)");
  sub->add_option("--max-den", a->request.max_den, "Largest denominator for best approximations (default 1000)");
  sub->add_option("--eps", a->request.eps, "Also find the smallest q with |omega - p/q| < eps");
  sub->add_option("--digits", a->request.digits, "Digits of the value's certified enclosure (default 30)");
  sub->add_option("--convergents", a->request.convergents,
                  "How many convergents to list with their errors (default 12)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_omega(*a); }};
}

}  // namespace rotleak::cli
