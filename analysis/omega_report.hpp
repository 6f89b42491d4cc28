// Everything `rotleak omega` says about one exact omega: its certified value and continued
// fraction, convergents and best approximations with certified errors, semiconvergents, Liouville
// partial sums, and the smallest denominator within eps. analysis/output/omega_output.hpp renders it.
#pragma once

#include <gmpxx.h>

#include <optional>
#include <string>
#include <vector>

#include "analysis/continued_fraction.hpp"
#include "numeric/exact.hpp"

namespace rotleak {

struct OmegaReportOptions {
  std::size_t terms = 20;        ///< certified partial quotients
  mpz_class max_den = 1000;      ///< largest denominator of the best approximations
  int digits = 30;               ///< digits of the value's enclosure
  std::size_t convergents = 12;  ///< convergents listed with their errors (and semiconvergent runs)
  std::optional<ExactReal> eps;  ///< also the smallest q with |omega - p/q| < eps
};

struct Approximation {
  Fraction f;
  DecimalEnclosure error;  ///< certified enclosure of omega - p/q
};

struct SemiconvergentRun {
  std::size_t k = 0;  ///< between convergents k-1 and k
  std::vector<Fraction> list;
  bool truncated = false;
};

struct OmegaReport {
  std::string input;  ///< as the user wrote it
  ExactReal x;
  OmegaReportOptions options;
  DecimalEnclosure value;
  CertifiedExpansion cf;
  std::vector<Approximation> convergents, best;
  bool best_truncated = false;
  std::vector<Fraction> second_kind;
  std::vector<SemiconvergentRun> semiconvergents;
  std::vector<std::string> liouville_partial_sums;  ///< S_K = sum_{k<=K} b^-(k!), exact, for liouville(b)
  std::optional<Fraction> within_eps;
};

OmegaReport omega_report(const std::string& input, const ExactReal& x, const OmegaReportOptions& options);

}  // namespace rotleak
