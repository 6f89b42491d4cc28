// parse_decimal (numeric/exact.hpp): a decimal literal read into an exact rational, never through double.
#include <cctype>
#include <string>

#include "numeric/exact.hpp"

namespace rotleak {

mpq_class parse_decimal(std::string_view text) {
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  std::string mantissa;
  long frac_digits = 0;
  bool seen_digit = false, seen_dot = false;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (std::isdigit(static_cast<unsigned char>(c))) {
      mantissa.push_back(c);
      seen_digit = true;
      if (seen_dot) ++frac_digits;
    } else if (c == '.' && !seen_dot) {
      seen_dot = true;
    } else {
      break;
    }
  }
  if (!seen_digit) throw ExactParseError("not a decimal number: '" + std::string(text) + "'");
  long exponent = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) eneg = text[i++] == '-';
    std::size_t ndig = 0;
    for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i, ++ndig) {
      exponent = exponent * 10 + (text[i] - '0');
      if (exponent > 100000) throw ExactParseError("decimal exponent too large (limit 1e+-100000)");
    }
    if (ndig == 0) throw ExactParseError("missing exponent digits in '" + std::string(text) + "'");
    if (eneg) exponent = -exponent;
  }
  if (i != text.size()) throw ExactParseError("not a decimal number: '" + std::string(text) + "'");
  mpz_class m(mantissa, 10);
  const long e10 = exponent - frac_digits;
  mpz_class p10;
  mpz_ui_pow_ui(p10.get_mpz_t(), 10, static_cast<unsigned long>(e10 < 0 ? -e10 : e10));
  mpq_class q = e10 >= 0 ? mpq_class(m * p10) : mpq_class(m, p10);
  q.canonicalize();
  return negative ? mpq_class(-q) : q;
}

}  // namespace rotleak
