// Continued fractions of exact values: exact for rationals, certified for irrationals (the common
// prefix of the expansions of both ends of an MPFI enclosure; the set of reals sharing a prefix is
// an interval, so the prefix holds for every number inside). Convergents, semiconvergents, best
// approximations of both kinds, and certified errors.
#pragma once

#include <gmpxx.h>

#include <optional>
#include <string>
#include <vector>

#include "numeric/exact.hpp"

namespace rotleak {

/// Partial quotients [a0; a1, a2, ...] of a rational by Euclid; at most max_terms (0: all).
std::vector<mpz_class> cf_of_rational(const mpq_class& q, std::size_t max_terms = 0);

/// The rational [a0; a1, ..., an].
mpq_class rational_of_cf(const std::vector<mpz_class>& terms);

struct CertifiedExpansion {
  std::vector<mpz_class> terms;  ///< partial quotients, all certified
  bool complete = false;         ///< the value is rational and this is its whole expansion
  long precision_bits = 0;       ///< working precision that certified them (0 for rationals)
};

/// The partial quotients certified by the enclosure [lo, hi] (at most `want`): Euclid on both ends in lockstep; a
/// quotient is certified when both ends have it and neither expansion ends there (a rational whose expansion
/// ends at a_k is an end of the cylinder interval of a_0..a_k, not inside it). certified_cf's step, exposed for
/// the tests (enclosures it must refuse to go on in).
std::vector<mpz_class> cf_common_prefix(const mpq_class& lo, const mpq_class& hi, std::size_t want);

/// At least `terms` certified partial quotients of x (fewer only when x is a rational whose whole
/// expansion is shorter). The working precision starts near what the terms need and doubles until
/// enough are certified; throws std::domain_error beyond 2^22 bits. `min_bits` forces a higher start.
CertifiedExpansion certified_cf(const ExactReal& x, std::size_t terms, long min_bits = 0);

struct Fraction {
  mpz_class p, q;
  std::string text() const { return p.get_str() + "/" + q.get_str(); }
  mpq_class value() const { return mpq_class(p, q); }
};

/// Convergents p_k / q_k of an expansion.
std::vector<Fraction> convergents(const std::vector<mpz_class>& terms);

/// Semiconvergents between convergents k-1 and k: (p_{k-2} + j p_{k-1}) / (q_{k-2} + j q_{k-1}) for
/// j = 1..a_k - 1 (at most max_count of them, from j = 1).
std::vector<Fraction> semiconvergents(const std::vector<mpz_class>& terms, std::size_t k, std::size_t max_count = 20);

/// Best approximations of the second kind (|q x - p| smaller than for every smaller q) with q <= max_den:
/// the convergents, less c_0 when a_1 = 1 (then c_1 = (a_0 + 1)/1 has the same q and is closer).
std::vector<Fraction> best_second_kind(const std::vector<mpz_class>& terms, const mpz_class& max_den);

/// Best approximations of the first kind with denominator <= max_den, increasing in q (each closer
/// to x than every fraction with a smaller denominator). All are convergents or semiconvergents;
/// runs of semiconvergents are bisected on the exact comparison, so huge partial quotients cost
/// log(a) comparisons. At most `max_count` are listed (`truncated` says so).
struct BestApproximations {
  std::vector<Fraction> list;
  bool truncated = false;
  bool expansion_exhausted = false;  ///< x is rational and was reached before max_den
};
BestApproximations best_approximations(const ExactReal& x, const mpz_class& max_den, std::size_t max_count = 1000);

/// Smallest q for which some p has |x - p/q| < eps (eps > 0), with that p; nullopt when x is
/// rational and no such fraction other than x itself exists below the denominator of x (it is then x).
std::optional<Fraction> smallest_denominator_within(const ExactReal& x, const ExactReal& eps);

/// Certified enclosure of x - p/q, as two decimal strings with `digits` significant digits,
/// rounded outward.
struct DecimalEnclosure {
  std::string lo, hi;
  double approx = 0;
};
DecimalEnclosure signed_error(const ExactReal& x, const Fraction& f, int digits = 6);
/// Certified enclosure of an exact value itself.
DecimalEnclosure enclose_decimal(const ExactReal& x, int digits);

}  // namespace rotleak
