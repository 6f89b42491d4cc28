#include "analysis/omega_report.hpp"

#include <regex>

namespace rotleak {

OmegaReport omega_report(const std::string& input, const ExactReal& x, const OmegaReportOptions& opt) {
  OmegaReport r{input, x,  opt, enclose_decimal(x, opt.digits), certified_cf(x, opt.terms), {}, {}, false, {},
                {},    {}, {}};
  const std::vector<Fraction> conv = convergents(r.cf.terms);
  for (std::size_t k = 0; k < conv.size() && k < opt.convergents; ++k)
    r.convergents.push_back({conv[k], signed_error(x, conv[k])});
  const BestApproximations best = best_approximations(x, opt.max_den);
  for (const auto& f : best.list) r.best.push_back({f, signed_error(x, f)});
  r.best_truncated = best.truncated;
  r.second_kind = best_second_kind(r.cf.terms, opt.max_den);
  for (std::size_t k = 1; k < r.cf.terms.size() && k <= opt.convergents; ++k) {
    SemiconvergentRun run{k, semiconvergents(r.cf.terms, k), r.cf.terms[k] - 1 > 20};
    if (!run.list.empty()) r.semiconvergents.push_back(std::move(run));
  }
  std::smatch m;
  static const std::regex liouville(R"(\s*liouville\(\s*(\d+)\s*\)\s*)");
  if (std::regex_match(input, m, liouville))
    for (unsigned K = 1; K <= 4; ++K)
      r.liouville_partial_sums.push_back(liouville_partial_sum(std::stoul(m[1]), K).get_str());
  if (opt.eps) r.within_eps = smallest_denominator_within(x, *opt.eps);
  return r;
}

}  // namespace rotleak
