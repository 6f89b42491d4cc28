// Orbit codes: the piece of each bounce, cyclically ("T", "R", "B", "L": top edge, right arc, bottom edge, left
// arc), enumerated one per class of rotation and reversal, and their symmetries (docs/model.md, "Periodic
// orbits").
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "geometry/stadium.hpp"
#include "numeric/tiers.hpp"

namespace rotleak {

using OrbitCode = std::vector<Piece>;

/// "TRBL" -> code; throws InputError (key `key`) naming the letters allowed, a code shorter than 2 or longer
/// than 64, or two bounces in a row on one straight edge (no orbit reflects twice off a line in a row).
OrbitCode parse_orbit_code(const std::string& text, const std::string& key = "--code");
std::string orbit_code_text(const OrbitCode& code);

/// The codes of period n, one per class under rotation and reversal (the smallest spelling of the class,
/// letters ordered T < R < B < L), with no two cyclically adjacent bounces on one straight edge.
std::vector<OrbitCode> orbit_codes(int n);

inline bool straight_piece(Piece p) { return p == Piece::top || p == Piece::bottom; }
OrbitCode rotated(const OrbitCode& c, std::size_t k);
OrbitCode reversed(const OrbitCode& c);
/// The smallest shift m > 0 with c rotated by m equal to c (c.size() when none smaller).
std::size_t code_period(const OrbitCode& c);
/// k with reversed(c) == rotated(c, k), or -1.
long reversal_shift(const OrbitCode& c);

/// Values moved as rotated() moves the code: element i of the result is v[i + k].
template <class T>
std::vector<T> rotated_values(const std::vector<T>& v, std::size_t k) {
  std::vector<T> r(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) r[i] = v[(i + k) % v.size()];
  return r;
}

/// The orbit run backwards, as a zero of the same code when reversed(code) == rotated(code, k): bounce i
/// of the reversed orbit is bounce n - 1 - i of this one (the same point, the same u), on piece
/// reversed(code)[i] = code[i + k]; so bounce j of the code is the reversed orbit's bounce j - k.
template <class T>
std::vector<T> reversed_values(const std::vector<T>& v, std::size_t k) {
  return rotated_values(std::vector<T>(v.rbegin(), v.rend()), (v.size() - k) % v.size());
}

/// The orbit (code, u) mirrored in x (right and left arcs swap; x -> -x on an edge, the same angle on an
/// arc) and/or in y (top and bottom swap; the same x on an edge, angle -> -angle on an arc), spelled
/// canonically (the smallest rotation of it or of its reverse, the values moved alike).
std::pair<OrbitCode, std::vector<Mpfr>> mirror_orbit(const OrbitCode& code, const std::vector<Mpfr>& u, bool mx,
                                                     bool my);

}  // namespace rotleak
