#include "geometry/table_spec.hpp"

#include <mpfi.h>

#include <stdexcept>

namespace rotleak {

namespace {

ExactReal num(const char* text) { return ExactReal::parse(text); }

/// Whether an exact value is zero: exactly for a rational, else within 2^-200 of it (an enclosure at 320 bits):
/// sign() cannot decide an irrational expression that is exactly zero.
bool is_zero(const ExactReal& x) {
  if (x.is_rational()) return x.as_rational() == 0;
  mpfi_t e;
  mpfi_init2(e, 320);
  x.enclose(e, 320);
  mpfr_t m;
  mpfr_init2(m, 320);
  mpfi_mag(m, e);
  const bool zero = mpfr_cmp_d(m, 0x1p-200) < 0;
  mpfr_clear(m);
  mpfi_clear(e);
  return zero;
}

/// The sign of x (0 where is_zero).
int sign_of(const ExactReal& x) { return is_zero(x) ? 0 : x.sign(); }

[[noreturn]] void bad(const TableSpec& t, const std::string& what) {
  throw std::invalid_argument("table " + (t.name.empty() ? std::string("custom") : t.name) + ": " + what);
}

/// Works out piece p's angle (an arc, an ellipse) and length, checks it (its radius, its ends on its circle, an
/// ellipse's semi-axes and that it is alone in its loop of `count` pieces), and returns its part of the loop's
/// integral of x dy - y dx (Green's theorem: docs/model.md, "Tables").
ExactReal measure_piece(const TableSpec& t, PieceSpec& p, int count, const std::string& piece) {
  const ExactReal two_pi = num("2") * ExactReal::pi();
  const ExactReal dx = p.bx - p.ax, dy = p.by - p.ay;
  if (p.kind == PieceKind::ellipse) {
    if (sign_of(p.ea) <= 0 || sign_of(p.eb) <= 0)
      bad(t, piece + " is an ellipse with semi-axes " + p.ea.text() + ", " + p.eb.text() + ": both must be > 0");
    if (count != 1) bad(t, piece + " is an ellipse: it must be alone in its loop");
    p.span = two_pi;
    p.length = num("4") * ExactReal::ellipse_quarter(p.ea, p.eb);
    const ExactReal twice_area = two_pi * p.ea * p.eb;  // the loop's integral of x dy - y dx, unsigned
    return p.clockwise ? -twice_area : twice_area;
  }
  if (p.kind == PieceKind::segment) {
    if (is_zero(dx) && is_zero(dy)) bad(t, piece + " is a segment of length 0");
    p.length = ExactReal::sqrt(dx * dx + dy * dy);
    return p.ax * p.by - p.ay * p.bx;
  }
  if (sign_of(p.rho) <= 0) bad(t, piece + " has a radius " + p.rho.text() + ", not > 0");
  const ExactReal fx = p.ax - p.cx, fy = p.ay - p.cy, gx = p.bx - p.cx, gy = p.by - p.cy;
  const ExactReal r2 = p.rho * p.rho;
  if (!is_zero(fx * fx + fy * fy - r2) || !is_zero(gx * gx + gy * gy - r2))
    bad(t, piece + "'s ends do not lie on its circle (centre (" + p.cx.text() + ", " + p.cy.text() + "), radius " +
               p.rho.text() + ")");
  if (p.full) {
    p.span = two_pi;
  } else {
    // the angle from f to g in the direction of travel: at most a half turn when g lies that way of f
    const int cr = sign_of(fx * gy - fy * gx);  // > 0: g anticlockwise of f
    const ExactReal c = ExactReal::acos((fx * gx + fy * gy) / r2);
    if (cr == 0 && is_zero(dx) && is_zero(dy)) bad(t, piece + " is an arc of angle 0 (a whole circle is circle())");
    const bool short_way = cr == 0 || (cr < 0) == p.clockwise;
    p.span = short_way ? c : two_pi - c;
  }
  p.length = p.rho * p.span;
  const ExactReal signed_span = p.clockwise ? -p.span : p.span;
  return (p.cx * dy - p.cy * dx) + r2 * signed_span;
}

}  // namespace

void TableSpec::begin_loop(const ExactReal& origin) {
  if (static_cast<int>(loops.size()) == kMaxTableLoops)
    bad(*this, "more than " + std::to_string(kMaxTableLoops) + " loops (the outer boundary and " +
                   std::to_string(kMaxTableLoops - 1) + " scatterers at most)");
  loops.push_back({static_cast<int>(pieces.size()), 0, origin, ExactReal()});
}

void TableSpec::segment(const ExactReal& ax, const ExactReal& ay, const ExactReal& bx, const ExactReal& by) {
  if (loops.empty()) bad(*this, "a piece before the first loop");
  if (static_cast<int>(pieces.size()) == kMaxTablePieces)
    bad(*this, "more than " + std::to_string(kMaxTablePieces) + " pieces");
  PieceSpec p;
  p.kind = PieceKind::segment;
  p.loop = static_cast<int>(loops.size()) - 1;
  p.ax = ax, p.ay = ay, p.bx = bx, p.by = by;
  pieces.push_back(p);
  ++loops.back().count;
}

void TableSpec::arc(const ExactReal& cx, const ExactReal& cy, const ExactReal& rho, const ExactReal& ax,
                    const ExactReal& ay, const ExactReal& bx, const ExactReal& by, bool clockwise) {
  segment(ax, ay, bx, by);
  PieceSpec& p = pieces.back();
  p.kind = PieceKind::arc;
  p.cx = cx, p.cy = cy, p.rho = rho, p.clockwise = clockwise;
}

void TableSpec::circle(const ExactReal& cx, const ExactReal& cy, const ExactReal& rho, bool clockwise) {
  arc(cx, cy, rho, cx, cy + rho, cx, cy + rho, clockwise);
  pieces.back().full = true;
}

void TableSpec::ellipse(const ExactReal& cx, const ExactReal& cy, const ExactReal& a, const ExactReal& b,
                        bool clockwise) {
  if (loops.empty() || loops.back().count != 0) bad(*this, "an ellipse must be alone in its loop");
  segment(cx, cy + b, cx, cy + b);
  PieceSpec& p = pieces.back();
  p.kind = PieceKind::ellipse;
  p.cx = cx, p.cy = cy, p.ea = a, p.eb = b, p.clockwise = clockwise, p.full = true;
}

void TableSpec::finish() {
  if (loops.empty()) bad(*this, "no boundary");
  ExactReal area2;  // -2 area: the sum over every loop of the integral of x dy - y dx
  perimeter = ExactReal();
  for (std::size_t k = 0; k < loops.size(); ++k) {
    LoopSpec& loop = loops[k];
    const std::string which = k == 0 ? "the outer boundary" : "scatterer " + std::to_string(k);
    if (loop.count == 0) bad(*this, which + " has no piece");
    ExactReal length, turn;  // turn: the loop's integral of x dy - y dx
    for (int i = loop.first; i < loop.first + loop.count; ++i) {
      PieceSpec& p = pieces[static_cast<std::size_t>(i)];
      const PieceSpec& next = pieces[static_cast<std::size_t>(i + 1 < loop.first + loop.count ? i + 1 : loop.first)];
      const std::string piece = which + ", piece " + std::to_string(i - loop.first + 1);
      if (!is_zero(p.bx - next.ax) || !is_zero(p.by - next.ay))
        bad(*this, piece + " ends at (" + p.bx.text() + ", " + p.by.text() + ") where the next piece does not start");
      turn = turn + measure_piece(*this, p, loop.count, piece);
    }
    for (int i = loop.first; i < loop.first + loop.count; ++i)
      length = length + pieces[static_cast<std::size_t>(i)].length;
    loop.length = length;
    const int orientation = sign_of(turn);  // > 0: anticlockwise
    if (k == 0 && orientation >= 0) bad(*this, "the outer boundary must run clockwise (the table on its right)");
    if (k > 0 && orientation <= 0) bad(*this, which + " must run anticlockwise (the table on its right)");
    if (sign_of(loop.origin) < 0 || sign_of(loop.origin - pieces[static_cast<std::size_t>(loop.first)].length) >= 0)
      bad(*this, which + "'s origin " + loop.origin.text() + " is not on its first piece");
    area2 = area2 + turn;
    perimeter = perimeter + length;
  }
  area = -(area2 / num("2"));
  if (sign_of(area) <= 0) bad(*this, "the scatterers cover the whole table (area <= 0)");
}

TableSpec stadium_table(const ExactReal& d, const ExactReal& r) {
  TableSpec t;
  t.name = "stadium";
  t.params = {{"d", d}, {"r", r}};
  const ExactReal h = d / num("2"), z;
  t.begin_loop(h);
  t.segment(-h, r, h, r);
  t.arc(h, z, r, h, r, h, -r, true);
  t.segment(h, -r, -h, -r);
  t.arc(-h, z, r, -h, -r, -h, r, true);
  t.finish();
  return t;
}

TableSpec circle_table(const ExactReal& rho) {
  TableSpec t;
  t.name = "circle";
  t.params = {{"radius", rho}};
  t.begin_loop();
  t.circle(ExactReal(), ExactReal(), rho, true);
  t.finish();
  return t;
}

TableSpec ellipse_table(const ExactReal& a, const ExactReal& b) {
  TableSpec t;
  t.name = "ellipse";
  t.params = {{"a", a}, {"b", b}};
  if (sign_of(a) <= 0 || sign_of(b) <= 0) bad(t, "needs a > 0 and b > 0 (a " + a.text() + ", b " + b.text() + ")");
  t.begin_loop();
  t.ellipse(ExactReal(), ExactReal(), a, b, true);
  t.finish();
  return t;
}

TableSpec mushroom_table(const ExactReal& R, const ExactReal& w, const ExactReal& h) {
  TableSpec t;
  t.name = "mushroom";
  t.params = {{"radius", R}, {"stem_width", w}, {"stem_height", h}};
  if (sign_of(w) <= 0 || sign_of(w - num("2") * R) > 0 || sign_of(h) <= 0)
    bad(t, "needs 0 < stem_width <= 2 radius and stem_height > 0 (radius " + R.text() + ", stem_width " + w.text() +
               ", stem_height " + h.text() + ")");
  const ExactReal z, hw = w / num("2");
  t.begin_loop(R * ExactReal::pi() / num("2"));  // the cap's top
  t.arc(z, z, R, -R, z, R, z, true);
  if (sign_of(R - hw) > 0) t.segment(R, z, hw, z);
  t.segment(hw, z, hw, -h);
  t.segment(hw, -h, -hw, -h);
  t.segment(-hw, -h, -hw, z);
  if (sign_of(R - hw) > 0) t.segment(-hw, z, -R, z);
  t.finish();
  return t;
}

TableSpec sinai_table(const ExactReal& a, const ExactReal& rho) {
  TableSpec t;
  t.name = "sinai";
  t.params = {{"side", a}, {"radius", rho}};
  const ExactReal h = a / num("2"), z;
  if (sign_of(rho) <= 0 || sign_of(h - rho) <= 0)
    bad(t, "needs 0 < radius < side / 2 (side " + a.text() + ", radius " + rho.text() + ")");
  t.begin_loop(h);
  t.segment(-h, h, h, h);
  t.segment(h, h, h, -h);
  t.segment(h, -h, -h, -h);
  t.segment(-h, -h, -h, h);
  t.begin_loop();
  t.circle(z, z, rho, false);
  t.finish();
  return t;
}

TableSpec annulus_table(const ExactReal& R, const ExactReal& rho, const ExactReal& delta) {
  TableSpec t;
  t.name = "annulus";
  t.params = {{"radius", R}, {"inner_radius", rho}, {"offset", delta}};
  const ExactReal z;
  const ExactReal reach = sign_of(delta) < 0 ? rho - delta : rho + delta;
  if (sign_of(rho) <= 0 || sign_of(R - reach) <= 0)
    bad(t, "needs inner_radius > 0 and |offset| + inner_radius < radius (radius " + R.text() + ", inner_radius " +
               rho.text() + ", offset " + delta.text() + ")");
  t.begin_loop();
  t.circle(z, z, R, true);
  t.begin_loop();
  t.circle(delta, z, rho, false);
  t.finish();
  return t;
}

TableSpec lemon_table(const ExactReal& R, const ExactReal& delta) {
  TableSpec t;
  t.name = "lemon";
  t.params = {{"radius", R}, {"distance", delta}};
  if (sign_of(delta) <= 0 || sign_of(num("2") * R - delta) <= 0)
    bad(t, "needs 0 < distance < 2 radius (radius " + R.text() + ", distance " + delta.text() + ")");
  const ExactReal z, c = delta / num("2");
  const ExactReal h = ExactReal::sqrt(R * R - c * c);
  t.begin_loop();
  t.arc(-c, z, R, z, h, z, -h, true);  // the right side: an arc of the left disc's circle
  t.arc(c, z, R, z, -h, z, h, true);
  t.finish();
  return t;
}

TableSpec lorentz_table(const ExactReal& r) {
  TableSpec t;
  t.name = "lorentz";
  t.params = {{"radius", r}};
  const ExactReal half = num("1/2");
  if (sign_of(r) <= 0 || sign_of(half - r) <= 0) bad(t, "needs 0 < radius < 1/2 (radius " + r.text() + ")");
  // the triangle (-1/2, 0), (0, h), (1/2, 0), h = sqrt(3)/2, less a disc of radius r about each vertex: each corner
  // an arc of that disc run anticlockwise about its centre (dispersing), each side the segment between two discs
  const ExactReal z, h = ExactReal::sqrt(num("3")) / num("2"), rx = r / num("2"), ry = r * h;
  t.begin_loop(r * ExactReal::pi() / num("6"));  // the top arc's midpoint
  t.arc(z, h, r, -rx, h - ry, rx, h - ry, false);
  t.segment(rx, h - ry, half - rx, ry);
  t.arc(half, z, r, half - rx, ry, half - r, z, false);
  t.segment(half - r, z, r - half, z);
  t.arc(-half, z, r, r - half, z, rx - half, ry, false);
  t.segment(rx - half, ry, -rx, h - ry);
  t.finish();
  return t;
}

namespace {

/// Whether sides i and j of a polygon, on one line, overlap (share a point): their ranges along x, or along y for a
/// vertical line.
bool collinear_overlap(const std::vector<std::pair<ExactReal, ExactReal>>& v, std::size_t i, std::size_t j) {
  const std::size_t n = v.size();
  const bool vertical = sign_of(v[i].first - v[(i + 1) % n].first) == 0;
  const auto coord = [&](std::size_t k) { return vertical ? v[k % n].second : v[k % n].first; };
  const auto lo_hi = [&](std::size_t k) {
    const ExactReal a = coord(k), b = coord(k + 1);
    return sign_of(a - b) <= 0 ? std::pair{a, b} : std::pair{b, a};
  };
  const auto [a0, a1] = lo_hi(i);
  const auto [b0, b1] = lo_hi(j);
  return sign_of(a1 - b0) >= 0 && sign_of(b1 - a0) >= 0;
}

}  // namespace

TableSpec polygon_table(const std::vector<std::pair<ExactReal, ExactReal>>& vertices) {
  TableSpec t;
  t.name = "polygon";
  const std::size_t n = vertices.size();
  if (n < 3 || n > static_cast<std::size_t>(kMaxTablePieces))
    bad(t, std::to_string(n) + " vertices; a polygon needs 3 to " + std::to_string(kMaxTablePieces));
  for (std::size_t i = 0; i < n; ++i) {
    t.params.push_back({"x" + std::to_string(i + 1), vertices[i].first});
    t.params.push_back({"y" + std::to_string(i + 1), vertices[i].second});
  }
  // a simple polygon: no two sides that do not share a vertex meet (a crossing would leave the inside undefined)
  const auto side = [&](std::size_t i, std::size_t j) {  // where vertex j lies from side i: the sign of a cross product
    const auto& a = vertices[i];
    const auto& b = vertices[(i + 1) % n];
    const auto& c = vertices[j % n];
    return sign_of((b.first - a.first) * (c.second - a.second) - (b.second - a.second) * (c.first - a.first));
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // the first and the last side share vertex 1
      const int s1 = side(i, j), s2 = side(i, j + 1), s3 = side(j, i), s4 = side(j, i + 1);
      if (s1 == 0 && s2 == 0 && s3 == 0 && s4 == 0 && !collinear_overlap(vertices, i, j)) continue;
      if (s1 * s2 <= 0 && s3 * s4 <= 0)
        bad(t, "sides " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
                   " meet: the vertices must make a simple polygon");
    }
  t.begin_loop();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = vertices[i];
    const auto& b = vertices[(i + 1) % n];
    t.segment(a.first, a.second, b.first, b.second);
  }
  t.finish();
  return t;
}

const std::vector<TableKind>& table_kinds() {
  static const std::vector<TableKind> kinds = {
      {"stadium", {"d", "r"}, [](const std::vector<ExactReal>& v) { return stadium_table(v[0], v[1]); }},
      {"circle", {"radius"}, [](const std::vector<ExactReal>& v) { return circle_table(v[0]); }},
      {"ellipse", {"a", "b"}, [](const std::vector<ExactReal>& v) { return ellipse_table(v[0], v[1]); }},
      {"mushroom",
       {"radius", "stem_width", "stem_height"},
       [](const std::vector<ExactReal>& v) { return mushroom_table(v[0], v[1], v[2]); }},
      {"sinai", {"side", "radius"}, [](const std::vector<ExactReal>& v) { return sinai_table(v[0], v[1]); }},
      {"annulus",
       {"radius", "inner_radius", "offset"},
       [](const std::vector<ExactReal>& v) { return annulus_table(v[0], v[1], v[2]); }},
      {"lemon", {"radius", "distance"}, [](const std::vector<ExactReal>& v) { return lemon_table(v[0], v[1]); }},
      {"lorentz", {"radius"}, [](const std::vector<ExactReal>& v) { return lorentz_table(v[0]); }},
      {"polygon", {}, nullptr},
  };
  return kinds;
}

const TableKind* find_table_kind(const std::string& name) {
  for (const TableKind& k : table_kinds())
    if (k.name == name) return &k;
  return nullptr;
}

}  // namespace rotleak
