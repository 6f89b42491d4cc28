#include "numeric/exact.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <utility>

#include "numeric/ellipse_exact.hpp"

namespace rotleak {

struct ExactReal::Node {
  enum class Kind { rational, pi, e, golden, ln, sqrt, acos, liouville, ellipse_quarter, add, sub, mul, div, neg };
  Kind kind = Kind::rational;
  mpq_class q;             // value when kind == rational
  unsigned long base = 0;  // liouville base
  std::shared_ptr<const Node> a, b;
};

namespace {

using Node = ExactReal::Node;
using NodePtr = std::shared_ptr<const Node>;
using Kind = Node::Kind;

NodePtr make_rational(mpq_class q) {
  auto n = std::make_shared<Node>();
  n->kind = Kind::rational;
  q.canonicalize();
  n->q = std::move(q);
  return n;
}

NodePtr make_node(Kind k, NodePtr a = nullptr, NodePtr b = nullptr) {
  auto n = std::make_shared<Node>();
  n->kind = k;
  n->a = std::move(a);
  n->b = std::move(b);
  return n;
}

bool is_rat(const NodePtr& n) { return n->kind == Kind::rational; }

// Exact folding of rational sub-expressions keeps rationals rational (so "1008/1009" is a rational).
NodePtr fold_binary(Kind k, NodePtr a, NodePtr b) {
  if (is_rat(a) && is_rat(b)) {
    switch (k) {
      case Kind::add:
        return make_rational(a->q + b->q);
      case Kind::sub:
        return make_rational(a->q - b->q);
      case Kind::mul:
        return make_rational(a->q * b->q);
      case Kind::div:
        if (sgn(b->q) == 0) throw ExactParseError("division by zero");
        return make_rational(a->q / b->q);
      default:
        break;
    }
  }
  if (k == Kind::div && is_rat(b) && sgn(b->q) == 0) throw ExactParseError("division by zero");
  return make_node(k, std::move(a), std::move(b));
}

NodePtr fold_sqrt(NodePtr a) {
  if (is_rat(a)) {
    if (sgn(a->q) < 0) throw ExactParseError("sqrt of a negative number");
    const mpz_class& num = a->q.get_num();
    const mpz_class& den = a->q.get_den();
    if (mpz_perfect_square_p(num.get_mpz_t()) && mpz_perfect_square_p(den.get_mpz_t())) {
      mpz_class rn, rd;
      mpz_sqrt(rn.get_mpz_t(), num.get_mpz_t());
      mpz_sqrt(rd.get_mpz_t(), den.get_mpz_t());
      return make_rational(mpq_class(rn, rd));
    }
  }
  return make_node(Kind::sqrt, std::move(a));
}

NodePtr fold_acos(NodePtr a) {
  if (is_rat(a)) {
    if (a->q > 1 || a->q < -1) throw ExactParseError("acos of a number outside [-1, 1]");
    if (a->q == 1) return make_rational(mpq_class(0));
    if (a->q == -1) return make_node(Kind::pi);
  }
  return make_node(Kind::acos, std::move(a));
}

/// The quarter perimeter of the ellipse with semi-axes a, b > 0: pi a / 2 where a == b (both rational).
NodePtr fold_ellipse_quarter(NodePtr a, NodePtr b) {
  if (is_rat(a) && sgn(a->q) <= 0) throw ExactParseError("ellipse_quarter of a semi-axis <= 0");
  if (is_rat(b) && sgn(b->q) <= 0) throw ExactParseError("ellipse_quarter of a semi-axis <= 0");
  if (is_rat(a) && is_rat(b) && a->q == b->q) return make_node(Kind::mul, make_node(Kind::pi), make_rational(a->q / 2));
  return make_node(Kind::ellipse_quarter, std::move(a), std::move(b));
}

NodePtr fold_ln(NodePtr a) {
  if (is_rat(a)) {
    if (sgn(a->q) <= 0) throw ExactParseError("ln of a number <= 0");
    if (a->q == 1) return make_rational(mpq_class(0));
  }
  return make_node(Kind::ln, std::move(a));
}

class Parser {
 public:
  explicit Parser(std::string_view text) : s_(text) {}

  NodePtr parse_all() {
    skip();
    if (pos_ == s_.size()) throw ExactParseError("empty value");
    NodePtr n = expr();
    skip();
    if (pos_ != s_.size()) fail("unexpected '" + std::string(1, s_[pos_]) + "'");
    return n;
  }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
  // Bounds that keep parsing and evaluation off the end of the stack (both recurse): parentheses,
  // signs and function calls nested at most kMaxNesting deep, at most kMaxOperations irrational
  // nodes (a chain pi+pi+...+pi is a tree as deep as it is long).
  static constexpr int kMaxNesting = 200;
  static constexpr int kMaxOperations = 2000;
  int nesting_ = 0, operations_ = 0;

  /// Counts one level of nesting for the duration of a scope.
  struct Nest {
    Parser& p;
    explicit Nest(Parser& parser) : p(parser) {
      if (++p.nesting_ > kMaxNesting)
        throw ExactParseError("nested deeper than " + std::to_string(kMaxNesting) +
                              " levels (parentheses, signs, functions)");
    }
    ~Nest() { --p.nesting_; }
  };
  NodePtr counted(NodePtr n) {
    if (!is_rat(n) && ++operations_ > kMaxOperations)
      throw ExactParseError("more than " + std::to_string(kMaxOperations) + " operations on irrational values");
    return n;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw ExactParseError(what + " at position " + std::to_string(pos_ + 1) +
                          "; expected a rational (1008/1009), a decimal (1e-4) or pi, e, golden, "
                          "ln(..), sqrt(..), acos(..), liouville(b), ellipse_quarter(a, b) combined with + - * / ( )");
  }
  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  NodePtr expr() {
    NodePtr n = term();
    for (;;) {
      if (eat('+'))
        n = counted(fold_binary(Kind::add, n, term()));
      else if (eat('-'))
        n = counted(fold_binary(Kind::sub, n, term()));
      else
        return n;
    }
  }
  NodePtr term() {
    NodePtr n = unary();
    for (;;) {
      if (eat('*'))
        n = counted(fold_binary(Kind::mul, n, unary()));
      else if (eat('/'))
        n = counted(fold_binary(Kind::div, n, unary()));
      else
        return n;
    }
  }
  NodePtr unary() {
    if (eat('-')) {
      Nest nest(*this);
      NodePtr a = unary();
      if (is_rat(a)) return make_rational(-a->q);
      return counted(make_node(Kind::neg, a));
    }
    if (eat('+')) {
      Nest nest(*this);
      return unary();
    }
    return primary();
  }
  NodePtr primary() {
    skip();
    if (pos_ >= s_.size()) fail("value ends too early");
    const char c = s_[pos_];
    if (c == '(') {
      ++pos_;
      Nest nest(*this);
      NodePtr n = expr();
      if (!eat(')')) fail("missing ')'");
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c))) return named();
    // a non-ASCII character is quoted whole (its UTF-8 continuation bytes with it), not as a lone byte
    std::size_t len = 1;
    while ((static_cast<unsigned char>(c) & 0x80) && pos_ + len < s_.size() &&
           (static_cast<unsigned char>(s_[pos_ + len]) & 0xC0) == 0x80)
      ++len;
    fail("unexpected '" + std::string(s_.substr(pos_, len)) + "'");
  }
  NodePtr number() {
    const std::size_t start = pos_;
    auto digits = [&] {
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    };
    digits();
    if (pos_ < s_.size() && s_[pos_] == '.') {
      ++pos_;
      digits();
    }
    // An exponent only when followed by digits: "2e" is not a number, and "e" alone is Euler's e.
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      std::size_t k = pos_ + 1;
      if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
      if (k < s_.size() && std::isdigit(static_cast<unsigned char>(s_[k]))) {
        pos_ = k;
        digits();
      }
    }
    try {
      return make_rational(parse_decimal(s_.substr(start, pos_ - start)));
    } catch (const ExactParseError& e) {
      pos_ = start;
      fail(e.what());
    }
  }
  NodePtr named() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    const std::string name(s_.substr(start, pos_ - start));
    if (name == "pi") return make_node(Kind::pi);
    if (name == "e") return make_node(Kind::e);
    if (name == "golden") return make_node(Kind::golden);
    if (name == "ellipse_quarter") {
      if (!eat('(')) fail("'ellipse_quarter' needs two arguments in parentheses");
      Nest nest(*this);
      NodePtr a = expr();
      if (!eat(',')) fail("'ellipse_quarter' needs two arguments, a and b");
      NodePtr b = expr();
      if (!eat(')')) fail("missing ')'");
      return counted(fold_ellipse_quarter(a, b));
    }
    if (name == "ln" || name == "log" || name == "sqrt" || name == "acos" || name == "liouville") {
      if (!eat('(')) fail("'" + name + "' needs an argument in parentheses");
      Nest nest(*this);
      NodePtr arg = expr();
      if (!eat(')')) fail("missing ')'");
      if (name == "sqrt") return counted(fold_sqrt(arg));
      if (name == "acos") return counted(fold_acos(arg));
      if (name == "liouville") {
        if (!is_rat(arg) || arg->q.get_den() != 1 || arg->q < 2 || !arg->q.get_num().fits_ulong_p())
          throw ExactParseError("liouville(b) needs an integer base b >= 2");
        auto n = std::make_shared<Node>();
        n->kind = Kind::liouville;
        n->base = arg->q.get_num().get_ui();
        return n;
      }
      return counted(fold_ln(arg));
    }
    pos_ = start;
    fail("unknown name '" + name + "'");
  }
};

// Enclosure of the tail sum_{k>K} b^(-k!) <= 2 b^(-(K+1)!), with K the first index whose next term
// is below 2^-(prec+4).
void enclose_liouville(mpfi_t out, unsigned long base, mpfr_prec_t prec) {
  const double log2b = std::log2(static_cast<double>(base));
  unsigned K = 1;
  double next_fact = 2.0;  // (K+1)!
  while (next_fact * log2b < static_cast<double>(prec) + 4.0) {
    ++K;
    next_fact *= static_cast<double>(K + 1);
  }
  mpq_class lo = liouville_partial_sum(base, K);
  mpz_class pow;
  mpz_ui_pow_ui(pow.get_mpz_t(), base, static_cast<unsigned long>(next_fact));
  mpq_class hi = lo + mpq_class(mpz_class(2), pow);
  hi.canonicalize();
  mpfi_interv_q(out, lo.get_mpq_t(), hi.get_mpq_t());
}

// Returns false when the enclosure cannot be formed at this precision (a divisor or a logarithm's
// argument not yet separated from zero); the caller then retries with more bits.
/// A leaf's enclosure (a rational or a constant); false when n is not a leaf.
bool enclose_leaf(const Node& n, mpfi_t out, mpfr_prec_t prec) {
  switch (n.kind) {
    case Kind::rational:
      mpfi_set_q(out, n.q.get_mpq_t());
      return true;
    case Kind::pi:
      mpfi_const_pi(out);
      return true;
    case Kind::e:
      mpfi_set_ui(out, 1);
      mpfi_exp(out, out);
      return true;
    case Kind::golden:
      mpfi_set_ui(out, 5);
      mpfi_sqrt(out, out);
      mpfi_add_ui(out, out, 1);
      mpfi_div_ui(out, out, 2);
      return true;
    case Kind::liouville:
      enclose_liouville(out, n.base, prec);
      return true;
    default:
      return false;
  }
}

/// An operation's enclosure from its operands' a and b; false where it cannot be decided at this precision
/// (a divisor or a logarithm's argument not away from 0, a square root's argument straddling 0).
bool enclose_operation(Kind kind, mpfi_t out, mpfi_t a, mpfi_t b) {
  switch (kind) {
    case Kind::neg:
      mpfi_neg(out, a);
      return true;
    case Kind::add:
      mpfi_add(out, a, b);
      return true;
    case Kind::sub:
      mpfi_sub(out, a, b);
      return true;
    case Kind::mul:
      mpfi_mul(out, a, b);
      return true;
    case Kind::div:
      if (mpfi_has_zero(b)) return false;
      mpfi_div(out, a, b);
      return true;
    case Kind::ln:
      if (!mpfi_is_strictly_pos(a)) return false;
      mpfi_log(out, a);
      return true;
    case Kind::sqrt:
      if (mpfi_is_strictly_neg(a)) throw std::domain_error("sqrt of a negative value");
      if (!mpfi_is_nonneg(a)) return false;
      mpfi_sqrt(out, a);
      return true;
    case Kind::ellipse_quarter: {
      // semi-axes decided > 0 (one enclosed <= 0 is an error), then Carlson's integrals on intervals at the same
      // precision (numeric/carlson.hpp: a rigorous enclosure, no series)
      if (mpfi_is_nonpos(a) > 0 || mpfi_is_nonpos(b) > 0)
        throw std::domain_error("ellipse_quarter of a semi-axis <= 0");
      if (!mpfi_is_strictly_pos(a) || !mpfi_is_strictly_pos(b)) return false;
      enclose_ellipse_quarter(out, a, b);
      return true;
    }
    case Kind::acos: {
      // [-1, 1] decided: an enclosure past an end either proves the value outside (an error) or needs more bits
      if (mpfr_cmp_si(&a->right, -1) < 0 || mpfr_cmp_si(&a->left, 1) > 0)
        throw std::domain_error("acos of a value outside [-1, 1]");
      if (mpfr_cmp_si(&a->left, -1) < 0 || mpfr_cmp_si(&a->right, 1) > 0) return false;
      mpfi_acos(out, a);
      return true;
    }
    default:
      return false;
  }
}

bool enclose_node(const Node& n, mpfi_t out, mpfr_prec_t prec) {
  mpfi_set_prec(out, prec);
  if (enclose_leaf(n, out, prec)) return true;
  mpfi_t a, b;
  mpfi_init2(a, prec);
  mpfi_init2(b, prec);
  bool ok = enclose_node(*n.a, a, prec);
  if (ok && n.b) ok = enclose_node(*n.b, b, prec);
  try {
    if (ok) ok = enclose_operation(n.kind, out, a, b);
  } catch (...) {
    mpfi_clear(a);
    mpfi_clear(b);
    throw;
  }
  mpfi_clear(a);
  mpfi_clear(b);
  return ok;
}

std::string node_text(const Node& n) {
  switch (n.kind) {
    case Kind::rational:
      return n.q.get_str();
    case Kind::pi:
      return "pi";
    case Kind::e:
      return "e";
    case Kind::golden:
      return "golden";
    case Kind::liouville:
      return "liouville(" + std::to_string(n.base) + ")";
    case Kind::ln:
      return "ln(" + node_text(*n.a) + ")";
    case Kind::sqrt:
      return "sqrt(" + node_text(*n.a) + ")";
    case Kind::acos:
      return "acos(" + node_text(*n.a) + ")";
    case Kind::ellipse_quarter:
      return "ellipse_quarter(" + node_text(*n.a) + "," + node_text(*n.b) + ")";
    case Kind::neg:
      return "-(" + node_text(*n.a) + ")";
    case Kind::add:
      return "(" + node_text(*n.a) + "+" + node_text(*n.b) + ")";
    case Kind::sub:
      return "(" + node_text(*n.a) + "-" + node_text(*n.b) + ")";
    case Kind::mul:
      return "(" + node_text(*n.a) + "*" + node_text(*n.b) + ")";
    case Kind::div:
      return "(" + node_text(*n.a) + "/" + node_text(*n.b) + ")";
  }
  return "?";
}

constexpr mpfr_prec_t kMaxWorkingBits = mpfr_prec_t(1) << 16;

}  // namespace

mpq_class liouville_partial_sum(unsigned long base, unsigned K) {
  mpq_class sum(0);
  unsigned long fact = 1;
  for (unsigned k = 1; k <= K; ++k) {
    if (fact > std::numeric_limits<unsigned long>::max() / k)
      throw std::overflow_error("liouville_partial_sum: k! overflows");
    fact *= k;
    mpz_class pow;
    mpz_ui_pow_ui(pow.get_mpz_t(), base, fact);
    sum += mpq_class(mpz_class(1), pow);
  }
  sum.canonicalize();
  return sum;
}

ExactReal::ExactReal() : node_(make_rational(mpq_class(0))) {}
ExactReal::ExactReal(std::shared_ptr<const Node> n) : node_(std::move(n)) {}

ExactReal ExactReal::parse(std::string_view text) { return ExactReal(Parser(text).parse_all()); }
ExactReal ExactReal::rational(const mpq_class& q) { return ExactReal(make_rational(q)); }
ExactReal ExactReal::pi() { return ExactReal(make_node(Kind::pi)); }
ExactReal ExactReal::sqrt(const ExactReal& x) { return ExactReal(fold_sqrt(x.node_)); }
ExactReal ExactReal::acos(const ExactReal& x) { return ExactReal(fold_acos(x.node_)); }
ExactReal ExactReal::ellipse_quarter(const ExactReal& a, const ExactReal& b) {
  return ExactReal(fold_ellipse_quarter(a.node_, b.node_));
}

bool ExactReal::is_rational() const { return is_rat(node_); }

const mpq_class& ExactReal::as_rational() const {
  if (!is_rational()) throw std::logic_error("ExactReal::as_rational on " + text());
  return node_->q;
}

std::string ExactReal::text() const { return node_text(*node_); }

void ExactReal::enclose(mpfi_t out, mpfr_prec_t prec) const {
  // at least the precision asked for (the continued fraction asks for more than kMaxWorkingBits
  // when it needs 10^4 terms: that once failed as "a singularity")
  const mpfr_prec_t most = std::max(prec, kMaxWorkingBits);
  for (mpfr_prec_t p = prec; p <= most; p *= 2)
    if (enclose_node(*node_, out, p)) return;
  throw std::domain_error("cannot enclose " + text() + " away from a singularity (tried up to " + std::to_string(most) +
                          " bits)");
}

void ExactReal::round(mpfr_t out, mpfr_rnd_t rnd) const {
  if (is_rational()) {
    mpfr_set_q(out, node_->q.get_mpq_t(), rnd);
    return;
  }
  const mpfr_prec_t target = mpfr_get_prec(out);
  mpfi_t box;
  mpfi_init2(box, target);
  mpfr_t lo, hi, end;
  mpfr_inits2(target, lo, hi, static_cast<mpfr_ptr>(nullptr));
  mpfr_init2(end, target);
  bool done = false;
  // up to a few times the target: a tier of 65536 bits once started above kMaxWorkingBits and never tried
  const mpfr_prec_t most = std::max(kMaxWorkingBits, 4 * target);
  for (mpfr_prec_t wp = target + 32; wp <= most && !done; wp *= 2) {
    if (!enclose_node(*node_, box, wp)) continue;
    mpfr_set_prec(end, wp);
    mpfi_get_left(end, box);
    mpfr_set(lo, end, rnd);
    mpfi_get_right(end, box);
    mpfr_set(hi, end, rnd);
    if (mpfr_equal_p(lo, hi)) {
      mpfr_set(out, lo, MPFR_RNDN);  // same precision: exact copy
      done = true;
    }
  }
  mpfr_clears(lo, hi, end, static_cast<mpfr_ptr>(nullptr));
  mpfi_clear(box);
  if (!done) throw std::domain_error("cannot round " + text() + " correctly (an exact tie or zero?)");
}

double ExactReal::to_double() const {
  mpfr_t x;
  mpfr_init2(x, 53);
  round(x);
  const double d = mpfr_get_d(x, MPFR_RNDN);
  mpfr_clear(x);
  return d;
}

int ExactReal::sign() const {
  if (is_rational()) return sgn(node_->q);
  mpfi_t box;
  mpfi_init2(box, 64);
  int s = 2;
  for (mpfr_prec_t wp = 64; wp <= kMaxWorkingBits && s == 2; wp *= 2) {
    if (!enclose_node(*node_, box, wp)) continue;
    if (mpfi_is_strictly_pos(box))
      s = 1;
    else if (mpfi_is_strictly_neg(box))
      s = -1;
  }
  mpfi_clear(box);
  if (s == 2) throw std::domain_error("cannot decide the sign of " + text());
  return s;
}

ExactReal operator+(const ExactReal& a, const ExactReal& b) {
  return ExactReal(fold_binary(Kind::add, a.node_, b.node_));
}
ExactReal operator-(const ExactReal& a, const ExactReal& b) {
  return ExactReal(fold_binary(Kind::sub, a.node_, b.node_));
}
ExactReal operator*(const ExactReal& a, const ExactReal& b) {
  return ExactReal(fold_binary(Kind::mul, a.node_, b.node_));
}
ExactReal operator/(const ExactReal& a, const ExactReal& b) {
  return ExactReal(fold_binary(Kind::div, a.node_, b.node_));
}
ExactReal operator-(const ExactReal& a) {
  if (a.is_rational()) return ExactReal::rational(-a.as_rational());
  return ExactReal(make_node(Kind::neg, a.node_));
}

mpz_class floor_exact(const ExactReal& x) {
  mpz_class k;
  if (x.is_rational()) {
    const mpq_class& q = x.as_rational();
    mpz_fdiv_q(k.get_mpz_t(), q.get_num_mpz_t(), q.get_den_mpz_t());
    return k;
  }
  for (mpfr_prec_t bits = 64; bits <= kMaxWorkingBits; bits *= 2) {
    mpfi_t box;
    mpfi_init2(box, bits);
    x.enclose(box, bits);
    mpz_class lo, hi;
    mpfr_get_z(lo.get_mpz_t(), &box->left, MPFR_RNDD);
    mpfr_get_z(hi.get_mpz_t(), &box->right, MPFR_RNDD);
    mpfi_clear(box);
    if (lo == hi) return lo;
  }
  throw std::domain_error("cannot decide the integer part of " + x.text());
}

}  // namespace rotleak
