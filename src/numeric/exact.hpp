// Exact inputs: rationals and closed-form irrationals, kept exact and rounded once into a tier.
#pragma once

#include <gmpxx.h>
#include <mpfi.h>
#include <mpfr.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rotleak {

/// Raised for text that is not a valid exact value; what() is one line saying why.
class ExactParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A real number known exactly: a GMP rational, or an expression over rationals with the named
/// constants pi, e, golden and the functions ln, sqrt, acos, liouville. Rational sub-expressions are folded
/// exactly; anything else is evaluated on demand by MPFI at any precision, so every rounding into a
/// finite type is certified (correctly rounded, see round()).
class ExactReal {
 public:
  /// Parses e.g. "1008/1009", "1e-4", "0.01", "-3", "ln(19)", "2*ln(19)", "sqrt(2)", "pi", "e",
  /// "golden", "liouville(10)". Decimals are read as exact rationals, never through double.
  static ExactReal parse(std::string_view text);
  static ExactReal rational(const mpq_class& q);
  static ExactReal pi();
  /// sqrt(x) (x >= 0) and acos(x) (x in [-1, 1]): folded exactly where they are rational (a perfect square; acos(1) =
  /// 0, acos(-1) = pi); a rational outside the domain throws ExactParseError, an irrational one std::domain_error once
  /// enclosed.
  static ExactReal sqrt(const ExactReal& x);
  static ExactReal acos(const ExactReal& x);
  /// The quarter perimeter of the ellipse with semi-axes a, b > 0, int_0^(pi/2) sqrt(a^2 cos^2 t + b^2 sin^2 t) dt
  /// (parsed as "ellipse_quarter(a, b)"; pi a / 2 where a == b): enclosed by Carlson's integrals on intervals
  /// (numeric/carlson.hpp).
  static ExactReal ellipse_quarter(const ExactReal& a, const ExactReal& b);

  ExactReal();  ///< zero

  bool is_rational() const;
  /// The exact rational value; throws std::logic_error unless is_rational().
  const mpq_class& as_rational() const;
  /// Canonical spelling, parseable by parse() back to the same value.
  std::string text() const;

  /// Certified enclosure computed with working precision `prec` bits (out is re-initialised to prec).
  void enclose(mpfi_t out, mpfr_prec_t prec) const;
  /// Rounds the exact value into `out` at out's own precision with mode rnd, correctly: the working
  /// precision grows until both ends of the enclosure round to the same number (Ziv's strategy).
  /// Throws std::domain_error when that cannot be decided (the value is, e.g., an exact tie that is
  /// not a rational expression) below 2^20 bits.
  void round(mpfr_t out, mpfr_rnd_t rnd = MPFR_RNDN) const;
  double to_double() const;
  /// Sign of the value: -1, 0, +1 (certified; throws like round() when undecidable).
  int sign() const;

  friend ExactReal operator+(const ExactReal& a, const ExactReal& b);
  friend ExactReal operator-(const ExactReal& a, const ExactReal& b);
  friend ExactReal operator*(const ExactReal& a, const ExactReal& b);
  friend ExactReal operator/(const ExactReal& a, const ExactReal& b);
  friend ExactReal operator-(const ExactReal& a);

  struct Node;

 private:
  explicit ExactReal(std::shared_ptr<const Node> n);
  std::shared_ptr<const Node> node_;
};

/// Exact rational partial sum sum_{k=1..K} b^(-k!) of the Liouville number with base b.
mpq_class liouville_partial_sum(unsigned long base, unsigned K);

/// floor(x), exactly: by integer division for rationals, for other values from enclosures at rising
/// precision until both ends agree. Throws std::domain_error when no working precision decides it.
mpz_class floor_exact(const ExactReal& x);

/// Reads a decimal literal ("12", "-0.01", "1e-4", "2.5E+3") into an exact rational; throws
/// ExactParseError on anything else (including nan and inf).
mpq_class parse_decimal(std::string_view text);

}  // namespace rotleak
