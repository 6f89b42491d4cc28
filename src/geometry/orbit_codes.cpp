#include "geometry/orbit_codes.hpp"

#include <algorithm>
#include <cctype>
#include <iterator>

#include "numeric/input.hpp"

namespace rotleak {

namespace {

constexpr char kLetters[] = {'T', 'R', 'B', 'L'};

/// No two cyclically adjacent bounces on one straight edge.
bool admissible(const OrbitCode& c) {
  for (std::size_t i = 0; i < c.size(); ++i)
    if (straight_piece(c[i]) && c[i] == c[(i + 1) % c.size()]) return false;
  return true;
}

bool canonical(const OrbitCode& c) {
  const OrbitCode r = reversed(c);
  for (std::size_t k = 0; k < c.size(); ++k)
    if (rotated(c, k) < c || rotated(r, k) < c) return false;
  return true;
}

void enumerate(OrbitCode& c, std::size_t at, std::vector<OrbitCode>& out) {
  if (at == c.size()) {
    if (straight_piece(c.back()) && c.back() == c.front()) return;
    if (canonical(c)) out.push_back(c);
    return;
  }
  for (int p = 0; p < 4; ++p) {
    c[at] = static_cast<Piece>(p);
    if (at > 0 && straight_piece(c[at]) && c[at] == c[at - 1]) continue;
    if (at > 0 && c[at] < c[0]) continue;  // a rotation starting here would be smaller
    enumerate(c, at + 1, out);
  }
}

}  // namespace

OrbitCode rotated(const OrbitCode& c, std::size_t k) {
  OrbitCode r(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) r[i] = c[(i + k) % c.size()];
  return r;
}
OrbitCode reversed(const OrbitCode& c) { return OrbitCode(c.rbegin(), c.rend()); }

std::size_t code_period(const OrbitCode& c) {
  for (std::size_t m = 1; m < c.size(); ++m)
    if (c.size() % m == 0 && rotated(c, m) == c) return m;
  return c.size();
}

long reversal_shift(const OrbitCode& c) {
  const OrbitCode r = reversed(c);
  for (std::size_t k = 0; k < c.size(); ++k)
    if (rotated(c, k) == r) return static_cast<long>(k);
  return -1;
}

OrbitCode parse_orbit_code(const std::string& text, const std::string& key) {
  OrbitCode c;
  for (char ch : text) {
    const char* at = std::find(std::begin(kLetters), std::end(kLetters),
                               static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
    if (at == std::end(kLetters))
      throw InputError(key, text, "letters T (top edge), R (right arc), B (bottom edge), L (left arc)");
    c.push_back(static_cast<Piece>(at - std::begin(kLetters)));
  }
  if (c.size() < 2) throw InputError(key, text, "at least 2 bounces");
  if (c.size() > 64) throw InputError(key, text, "at most 64 bounces");
  if (!admissible(c))
    throw InputError(key, text, "no two bounces in a row (cyclically) on one straight edge: TT and BB have no orbit");
  return c;
}

std::string orbit_code_text(const OrbitCode& code) {
  std::string s;
  for (Piece p : code) s += kLetters[static_cast<int>(p)];
  return s;
}

std::vector<OrbitCode> orbit_codes(int n) {
  std::vector<OrbitCode> out;
  if (n < 2) return out;
  OrbitCode c(static_cast<std::size_t>(n));
  enumerate(c, 0, out);
  return out;
}

std::pair<OrbitCode, std::vector<Mpfr>> mirror_orbit(const OrbitCode& c, const std::vector<Mpfr>& u, bool mx, bool my) {
  const std::size_t n = c.size();
  OrbitCode m(n);
  std::vector<Mpfr> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    Piece p = c[i];
    v[i] = u[i];
    if (straight_piece(p)) {
      if (my) p = p == Piece::top ? Piece::bottom : Piece::top;
      if (mx) v[i] = -v[i];
    } else {
      if (mx) p = p == Piece::right_arc ? Piece::left_arc : Piece::right_arc;
      if (my) v[i] = -v[i];
    }
    m[i] = p;
  }
  OrbitCode best = m;
  std::vector<Mpfr> best_v = v;
  const OrbitCode rm = reversed(m);
  const std::vector<Mpfr> rv(v.rbegin(), v.rend());
  for (std::size_t k = 0; k < n; ++k) {
    if (rotated(m, k) < best) best = rotated(m, k), best_v = rotated_values(v, k);
    if (rotated(rm, k) < best) best = rotated(rm, k), best_v = rotated_values(rv, k);
  }
  return {best, best_v};
}

}  // namespace rotleak
