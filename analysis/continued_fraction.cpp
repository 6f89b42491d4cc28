#include "analysis/continued_fraction.hpp"

#include <mpfi.h>

#include <algorithm>
#include <stdexcept>

namespace rotleak {

std::vector<mpz_class> cf_of_rational(const mpq_class& q, std::size_t max_terms) {
  std::vector<mpz_class> out;
  mpz_class p = q.get_num(), d = q.get_den(), a, r;
  while (d != 0 && (max_terms == 0 || out.size() < max_terms)) {
    mpz_fdiv_qr(a.get_mpz_t(), r.get_mpz_t(), p.get_mpz_t(), d.get_mpz_t());
    out.push_back(a);
    p = d;
    d = r;
  }
  return out;
}

mpq_class rational_of_cf(const std::vector<mpz_class>& terms) {
  if (terms.empty()) throw std::invalid_argument("rational_of_cf: no terms");
  const std::vector<Fraction> c = convergents(terms);
  return c.back().value();
}

std::vector<Fraction> convergents(const std::vector<mpz_class>& terms) {
  std::vector<Fraction> out;
  out.reserve(terms.size());
  mpz_class p1 = 1, q1 = 0, p2 = 0, q2 = 1;  // p_{k-1}, q_{k-1}, p_{k-2}, q_{k-2}
  for (const mpz_class& a : terms) {
    mpz_class p = a * p1 + p2, q = a * q1 + q2;
    p2 = p1;
    q2 = q1;
    p1 = p;
    q1 = q;
    out.push_back({p, q});
  }
  return out;
}

std::vector<Fraction> semiconvergents(const std::vector<mpz_class>& terms, std::size_t k, std::size_t max_count) {
  std::vector<Fraction> out;
  if (k == 0 || k >= terms.size()) return out;
  const std::vector<Fraction> c =
      convergents(std::vector<mpz_class>(terms.begin(), terms.begin() + static_cast<long>(k)));
  const Fraction prev = c[k - 1], prev2 = k >= 2 ? c[k - 2] : Fraction{1, 0};
  for (mpz_class j = 1; j < terms[k] && out.size() < max_count; ++j)
    out.push_back({prev2.p + j * prev.p, prev2.q + j * prev.q});
  return out;
}

std::vector<Fraction> best_second_kind(const std::vector<mpz_class>& terms, const mpz_class& max_den) {
  std::vector<Fraction> out;
  for (const Fraction& f : convergents(terms))
    if (f.q <= max_den) out.push_back(f);
  if (terms.size() > 1 && terms[1] == 1 && !out.empty()) out.erase(out.begin());
  return out;
}

namespace {

mpq_class to_q(mpfr_srcptr x) {
  mpq_class q;
  mpfr_get_q(q.get_mpq_t(), x);
  return q;
}

}  // namespace

std::vector<mpz_class> cf_common_prefix(const mpq_class& lo, const mpq_class& hi, std::size_t want) {
  std::vector<mpz_class> out;
  mpz_class p1 = lo.get_num(), d1 = lo.get_den(), p2 = hi.get_num(), d2 = hi.get_den(), a1, a2, r1, r2;
  while (out.size() < want && d1 != 0 && d2 != 0) {
    mpz_fdiv_qr(a1.get_mpz_t(), r1.get_mpz_t(), p1.get_mpz_t(), d1.get_mpz_t());
    mpz_fdiv_qr(a2.get_mpz_t(), r2.get_mpz_t(), p2.get_mpz_t(), d2.get_mpz_t());
    if (a1 != a2 || r1 == 0 || r2 == 0) break;
    out.push_back(a1);
    p1 = d1;
    d1 = r1;
    p2 = d2;
    d2 = r2;
  }
  return out;
}

CertifiedExpansion certified_cf(const ExactReal& x, std::size_t terms, long min_bits) {
  CertifiedExpansion out;
  if (x.is_rational()) {
    out.terms = cf_of_rational(x.as_rational(), terms);
    out.complete = out.terms.size() < terms || cf_of_rational(x.as_rational(), terms + 1).size() == out.terms.size();
    return out;
  }
  // Typical numbers need ~3.4 bits per quotient (Levy's constant); start a little above that.
  long prec = std::max(min_bits, 64 + 4 * static_cast<long>(terms));
  mpfi_t box;
  mpfi_init2(box, prec);
  mpfr_t end;
  mpfr_init2(end, prec);
  for (; prec <= (1L << 22); prec *= 2) {
    x.enclose(box, prec);
    mpfr_set_prec(end, mpfi_get_prec(box));
    mpfi_get_left(end, box);
    const mpq_class lo = to_q(end);
    mpfi_get_right(end, box);
    const mpq_class hi = to_q(end);
    out.terms = cf_common_prefix(lo, hi, terms);
    if (out.terms.size() >= terms) {
      out.precision_bits = prec;
      break;
    }
  }
  mpfr_clear(end);
  mpfi_clear(box);
  if (out.terms.size() < terms)
    throw std::domain_error("cannot certify " + std::to_string(terms) + " partial quotients of " + x.text());
  return out;
}

namespace {

// Lazily extended certified expansion.
class Expansion {
 public:
  explicit Expansion(const ExactReal& x) : x_(x) {}
  /// Term k, or nullopt when x is rational with fewer terms.
  const mpz_class* term(std::size_t k) {
    while (k >= cf_.terms.size() && !cf_.complete) {
      want_ = std::max(want_ * 2, k + 1);
      cf_ = certified_cf(x_, want_);
      if (x_.is_rational() && cf_.terms.size() < want_) cf_.complete = true;
    }
    return k < cf_.terms.size() ? &cf_.terms[k] : nullptr;
  }

 private:
  ExactReal x_;
  CertifiedExpansion cf_;
  std::size_t want_ = 16;
};

ExactReal rat(const Fraction& f) { return ExactReal::rational(f.value()); }

// Certified: is x strictly closer to a than to b?
bool closer(const ExactReal& x, const Fraction& a, const Fraction& b) {
  const mpq_class va = a.value(), vb = b.value();
  if (va == vb) return false;
  // |x - a| < |x - b|  <=>  2x (b - a) < b^2 - a^2  <=>  (b - a) (2x - a - b) < 0
  const int s = (ExactReal::parse("2") * x - ExactReal::rational(va + vb)).sign();
  return sgn(vb - va) * s < 0;
}

// Certified: |x - f| < eps?
bool within(const ExactReal& x, const Fraction& f, const ExactReal& eps) {
  const ExactReal diff = x - rat(f);
  const int side = diff.sign();
  if (side == 0) return true;
  return (side > 0 ? eps - diff : eps + diff).sign() > 0;
}

Fraction semi(const Fraction& prev, const Fraction& cur, const mpz_class& j) {
  return {prev.p + j * cur.p, prev.q + j * cur.q};
}

// Smallest j in [lo, hi] with pred(j) true, pred monotone (false..false true..true); hi if none... caller checks.
template <class Pred>
mpz_class first_true(mpz_class lo, mpz_class hi, Pred pred) {
  while (lo < hi) {
    mpz_class mid = (lo + hi) / 2;
    if (pred(mid))
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

}  // namespace

BestApproximations best_approximations(const ExactReal& x, const mpz_class& max_den, std::size_t max_count) {
  BestApproximations out;
  Expansion cf(x);
  Fraction prev{1, 0}, prev2{0, 1};  // convergents k-1, k-2
  auto accept = [&](const Fraction& f) {
    if (!out.list.empty() && out.list.back().q == f.q)
      out.list.back() = f;  // same q, closer
    else
      out.list.push_back(f);
    if (out.list.size() > max_count) {
      out.list.pop_back();
      out.truncated = true;
    }
  };
  for (std::size_t k = 0;; ++k) {
    const mpz_class* a = cf.term(k);
    if (!a) {
      out.expansion_exhausted = true;
      break;
    }
    // run of semiconvergents between convergent k-1 and k: (p_{k-2} + j p_{k-1}) / (q_{k-2} + j q_{k-1}), j < a_k
    if (k >= 1 && *a > 1) {
      const Fraction& best = out.list.back();
      mpz_class j_max = *a - 1;
      if (prev.q > 0) {
        const mpz_class cap = (max_den - prev2.q) / prev.q;
        if (cap < j_max) j_max = cap;
      }
      if (j_max >= 1 && closer(x, semi(prev2, prev, j_max), best)) {
        const mpz_class j0 =
            first_true(mpz_class(1), j_max, [&](const mpz_class& j) { return closer(x, semi(prev2, prev, j), best); });
        for (mpz_class j = j0; j <= j_max && !out.truncated; ++j) accept(semi(prev2, prev, j));
      }
    }
    const Fraction conv{*a * prev.p + prev2.p, *a * prev.q + prev2.q};
    if (conv.q > max_den || out.truncated) break;
    if (out.list.empty() || closer(x, conv, out.list.back())) accept(conv);
    prev2 = prev;
    prev = conv;
  }
  return out;
}

std::optional<Fraction> smallest_denominator_within(const ExactReal& x, const ExactReal& eps) {
  if (eps.sign() <= 0) throw std::invalid_argument("eps must be > 0");
  Expansion cf(x);
  Fraction prev{1, 0}, prev2{0, 1};
  for (std::size_t k = 0;; ++k) {
    const mpz_class* a = cf.term(k);
    if (!a) return std::nullopt;
    if (k >= 1 && *a > 1 && within(x, semi(prev2, prev, *a - 1), eps)) {
      const mpz_class j =
          first_true(mpz_class(1), *a - 1, [&](const mpz_class& jj) { return within(x, semi(prev2, prev, jj), eps); });
      // below convergent k-1's own denominator nothing qualified, so this is the smallest
      return semi(prev2, prev, j);
    }
    const Fraction conv{*a * prev.p + prev2.p, *a * prev.q + prev2.q};
    if (within(x, conv, eps)) {
      // at q = 1 the other neighbour may also qualify; the smaller q wins and both have q = 1
      return conv;
    }
    prev2 = prev;
    prev = conv;
  }
}

namespace {

std::string decimal(mpfr_srcptr v, int digits, mpfr_rnd_t rnd) {
  if (mpfr_zero_p(v)) return "0";
  char* s = nullptr;
  mpfr_asprintf(&s, "%.*R*e", digits - 1, rnd, v);
  std::string out(s);
  mpfr_free_str(s);
  return out;
}

}  // namespace

DecimalEnclosure enclose_decimal(const ExactReal& x, int digits) {
  const mpfr_prec_t bits = static_cast<mpfr_prec_t>(digits * 3.33 + 16);
  mpfr_t lo, hi;
  mpfr_inits2(bits, lo, hi, static_cast<mpfr_ptr>(nullptr));
  DecimalEnclosure e;
  if (x.is_rational() && sgn(x.as_rational()) == 0) {
    e.lo = e.hi = "0";
  } else {
    x.round(lo, MPFR_RNDD);
    x.round(hi, MPFR_RNDU);
    e.lo = decimal(lo, digits, MPFR_RNDD);
    e.hi = decimal(hi, digits, MPFR_RNDU);
    e.approx = mpfr_get_d(lo, MPFR_RNDN);
  }
  mpfr_clears(lo, hi, static_cast<mpfr_ptr>(nullptr));
  return e;
}

DecimalEnclosure signed_error(const ExactReal& x, const Fraction& f, int digits) {
  return enclose_decimal(x - ExactReal::rational(f.value()), digits);
}

}  // namespace rotleak
