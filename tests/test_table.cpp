// Tables as data (geometry/table_spec.hpp, geometry/table.hpp): each standard table's exact area and length
// against its closed form, the stadium built as a table against the stadium engine's own geometry bit for bit,
// every table's flights staying on its boundary, and the mean free path pi A / |boundary| from flights drawn
// from the billiard map's invariant measure (uniform in s and p = sin theta), which holds for any table.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "geometry/stadium.hpp"
#include "geometry/table.hpp"
#include "leak/leak.hpp"
#include "leak/table_leak.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"
#include "tiers.hpp"

using namespace rotleak;
using rotleak::test::as_double;
using rotleak::test::eps_times;

namespace {

ExactReal q(const char* text) { return ExactReal::parse(text); }

struct Standard {
  std::string name;
  std::function<TableSpec()> make;
  double area, perimeter;  ///< closed forms, in double
};

/// The perimeter of the ellipse with semi-axes a, b: int_0^(2 pi) sqrt(a^2 cos^2 t + b^2 sin^2 t) dt by the
/// trapezoid rule on 4096 points (for a periodic analytic integrand its error falls geometrically: below 1e-18 here).
double ellipse_perimeter(double a, double b) {
  constexpr int n = 4096;
  long double sum = 0;
  for (int k = 0; k < n; ++k) {
    const long double t = 2 * M_PIl * k / n;
    sum += std::sqrt(a * a * std::cos(t) * std::cos(t) + b * b * std::sin(t) * std::sin(t));
  }
  return static_cast<double>(sum * 2 * M_PIl / n);
}

/// Each standard table with its area and boundary length from the closed forms (written here, not taken from
/// the table's own sums).
std::vector<Standard> standard_tables() {
  const double pi = M_PI;
  const double lemon_half = std::acos(0.6 / 2);  // R = 1, distance 0.6: the half angle of each arc
  return {
      {"stadium", [] { return stadium_table(q("2"), q("1")); }, 2 * 1 * 2 + pi, 2 * 2 + 2 * pi},
      {"stadium_thin", [] { return stadium_table(q("1/10"), q("3/2")); }, 2 * 1.5 * 0.1 + pi * 2.25, 0.2 + 3 * pi},
      {"circle", [] { return circle_table(q("3/2")); }, pi * 2.25, 3 * pi},
      // the perimeter by the trapezoid rule over a whole period, spectrally accurate for a smooth periodic integrand
      {"ellipse", [] { return ellipse_table(q("2"), q("1")); }, pi * 2, ellipse_perimeter(2, 1)},
      {"ellipse_tall", [] { return ellipse_table(q("1/2"), q("3/2")); }, pi * 0.75, ellipse_perimeter(0.5, 1.5)},
      {"mushroom", [] { return mushroom_table(q("1"), q("1/2"), q("1")); }, pi / 2 + 0.5, pi + 2 * 0.75 + 2 + 0.5},
      {"sinai", [] { return sinai_table(q("2"), q("1/2")); }, 4 - pi / 4, 8 + pi},
      {"annulus", [] { return annulus_table(q("1"), q("3/10"), q("2/5")); }, pi * (1 - 0.09), 2 * pi * 1.3},
      {"lemon", [] { return lemon_table(q("1"), q("3/5")); }, 2 * lemon_half - 0.3 * std::sqrt(4 - 0.36),
       4 * lemon_half},
      // the unit triangle less three 60-degree sectors of radius 9/20; its sides less two radii, its arcs a sixth of
      // a circle each
      {"lorentz", [] { return lorentz_table(q("9/20")); }, std::sqrt(3.0) / 4 - pi * 0.45 * 0.45 / 2,
       3 * (1 - 0.9) + pi * 0.45},
      {"polygon",
       [] {
         return polygon_table({{q("0"), q("0")}, {q("0"), q("2")}, {q("3"), q("1")}, {q("2"), q("-1")}});
       },
       // shoelace of (0,0) (0,2) (3,1) (2,-1), clockwise
       0.5 * std::abs(0 * 2 - 0 * 0 + 0 * 1 - 3 * 2 + 3 * -1 - 2 * 1 + 2 * 0 - 0 * -1),
       2 + std::sqrt(10.0) + std::sqrt(5.0) + std::sqrt(5.0)},
  };
}

}  // namespace

TEST(Table, EachStandardTablesAreaAndLengthAreItsClosedForm) {
  for (const Standard& s : standard_tables()) {
    SCOPED_TRACE(s.name);
    const TableSpec t = s.make();
    EXPECT_NEAR(t.area.to_double(), s.area, 1e-14 * s.area);
    EXPECT_NEAR(t.perimeter.to_double(), s.perimeter, 1e-14 * s.perimeter);
    double sum = 0;
    for (const LoopSpec& l : t.loops) sum += l.length.to_double();
    EXPECT_NEAR(sum, s.perimeter, 1e-14 * s.perimeter);
  }
}

TEST(Table, BadTablesAreRefusedNamingWhatIsWrong) {
  auto says = [](const std::function<void()>& f, const std::string& words) {
    try {
      f();
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  says([] { mushroom_table(q("1"), q("3"), q("1")); }, "table mushroom: needs 0 < stem_width <= 2 radius");
  says([] { sinai_table(q("1"), q("1/2")); }, "table sinai: needs 0 < radius < side / 2");
  says([] { annulus_table(q("1"), q("1/2"), q("1/2")); }, "table annulus: needs inner_radius > 0 and |offset|");
  says([] { lemon_table(q("1"), q("2")); }, "table lemon: needs 0 < distance < 2 radius");
  says([] { ellipse_table(q("0"), q("1")); }, "table ellipse: needs a > 0 and b > 0 (a 0, b 1)");
  says(
      [] {
        TableSpec t;
        t.begin_loop();
        t.segment(q("0"), q("0"), q("1"), q("0"));
        t.ellipse(q("0"), q("0"), q("2"), q("1"), true);
      },
      "table custom: an ellipse must be alone in its loop");
  says([] { lorentz_table(q("1/2")); }, "table lorentz: needs 0 < radius < 1/2 (radius 1/2)");
  says([] { polygon_table({{q("0"), q("0")}, {q("1"), q("1")}}); }, "table polygon: 2 vertices; a polygon needs 3");
  // anticlockwise vertices: the table would lie on the left
  says(
      [] {
        polygon_table({{q("0"), q("0")}, {q("1"), q("0")}, {q("0"), q("1")}});
      },
      "the outer boundary must run clockwise");
  says(
      [] {
        TableSpec t;
        t.name = "open";
        t.begin_loop();
        t.segment(q("0"), q("0"), q("0"), q("1"));
        t.segment(q("0"), q("1"), q("1"), q("1"));
        t.finish();
      },
      "table open: the outer boundary, piece 2 ends at (1, 1) where the next piece does not start");
  says(
      [] {
        TableSpec t;
        t.begin_loop();
        t.arc(q("0"), q("0"), q("1"), q("0"), q("1"), q("1"), q("1"), true);
        t.segment(q("1"), q("1"), q("0"), q("1"));
        t.finish();
      },
      "piece 1's ends do not lie on its circle");
  says(
      [] {
        TableSpec t = circle_table(q("1"));
        t.begin_loop();
        t.circle(q("0"), q("0"), q("1/2"), true);
        t.finish();
      },
      "scatterer 1 must run anticlockwise");
}

// A table holds kMaxTableLoops = 8 loops, the outer boundary and 7 scatterers: a square of side 8 with 7 discs is built
// and runs its boundary coordinate over all of them; an 8th disc is refused, naming the limit. A limit of 7 (mutant
// tests/mutants/table-loops-seven.patch, drawn by scripts/mutate.py) refused the table at its last disc.
TEST(Table, EightLoopsAreATableAndANinthIsRefused) {
  const auto square_with = [](int discs) {
    TableSpec t;
    t.begin_loop(q("4"));
    t.segment(q("-4"), q("4"), q("4"), q("4"));
    t.segment(q("4"), q("4"), q("4"), q("-4"));
    t.segment(q("4"), q("-4"), q("-4"), q("-4"));
    t.segment(q("-4"), q("-4"), q("-4"), q("4"));
    for (int k = 0; k < discs; ++k) {
      t.begin_loop();
      t.circle(ExactReal::parse(std::to_string(k - 3)), q("0"), q("1/10"), false);
    }
    t.finish();
    return t;
  };
  const Table<double> eight(square_with(kMaxTableLoops - 1));
  ASSERT_EQ(eight.loops(), kMaxTableLoops);
  EXPECT_NEAR(eight.loop_offset(kMaxTableLoops - 1), 32 + 6 * (2 * M_PI / 10), 1e-12);
  const auto [loop, s] = eight.loop_s(eight.boundary_share(kMaxTableLoops - 1, 0.5));
  EXPECT_EQ(loop, kMaxTableLoops - 1);
  EXPECT_NEAR(s, 0.5, 1e-12);
  try {
    square_with(kMaxTableLoops);
    ADD_FAILURE() << "a table of " << kMaxTableLoops + 1 << " loops was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("more than 8 loops (the outer boundary and 7 scatterers at most)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Table, AcosIsExactWhereItCanBeAndParsesBack) {
  EXPECT_TRUE(ExactReal::acos(q("1")).is_rational());
  EXPECT_EQ(ExactReal::acos(q("-1")).text(), "pi");
  const ExactReal a = ExactReal::parse("acos(3/10)");
  EXPECT_EQ(ExactReal::parse(a.text()).to_double(), a.to_double());
  EXPECT_EQ(a.to_double(), std::acos(0.3));  // libm's acos is correctly rounded here (checked against MPFR's)
  EXPECT_THROW(ExactReal::parse("acos(2)"), ExactParseError);
}

/// The stadium built as a table computes the stadium's own bits: frames, hits, reflections and boundary coordinates
/// (pieces in the same order: top, right arc, bottom, left arc), in every tier whose operations are correctly
/// rounded. The argument (docs/model.md, "Tables") uses x * 1 = x, x * 0 + y = y and a + (-b) = a - b; double-double
/// arithmetic (QD's sloppy addition) keeps none of them bit for bit (a + (-b) and a - b add the low parts in another
/// order), so there the two agree to a few units of dd's epsilon instead.
template <class R>
class TableStadium : public ::testing::Test {};
TYPED_TEST_SUITE(TableStadium, rotleak::test::Tiers, rotleak::test::TierNames);

template <class R>
bool same(const R& a, const R& b) {
  if constexpr (std::is_same_v<R, dd_real>) {
    using std::abs;
    const double scale = std::max(1.0, std::abs(as_double(a)));
    return as_double(abs(R(a - b))) <= eps_times<R>(8) * scale;
  } else {
    return a == b;
  }
}

TYPED_TEST(TableStadium, TheStadiumAsATableIsTheStadiumBitForBit) {
  using R = TypeParam;
  for (const auto& [d, r] : {std::pair{"2", "1"}, std::pair{"1/10", "3/2"}, std::pair{"3", "7/10"}}) {
    const Stadium<R> st(q(d), q(r));
    const Table<R> table(stadium_table(q(d), q(r)));
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> u(0, 1), pu(-0.999, 0.999);
    int near_junction = 0, hits = 0;
    for (int i = 0; i < 3000; ++i) {
      const R s = static_cast<R>(u(gen));
      const BoundaryPoint<R> b = st.at(s);
      const TableFrame<R> f = table.at(0, s);
      ASSERT_EQ(static_cast<int>(b.piece), f.piece);
      ASSERT_TRUE(same(b.q.x, f.q.x) && same(b.q.y, f.q.y)) << "s = " << as_double(s);
      ASSERT_TRUE(same(b.tangent.x, f.tangent.x) && same(b.tangent.y, f.tangent.y)) << "s = " << as_double(s);
      ASSERT_TRUE(same(b.normal.x, f.normal.x) && same(b.normal.y, f.normal.y)) << "s = " << as_double(s);
      // a few flights from there
      Vec2<R> qv = b.q, v = st.velocity(b, static_cast<R>(pu(gen)));
      for (int k = 0; k < 5; ++k) {
        const Hit<R> h = st.next_hit(qv, v);
        const TableHit<R> g = table.next_hit(qv, v);
        ++hits;
        if (static_cast<int>(h.piece) != g.piece) {
          // only where the hit lies within rounding of a junction: both pieces end there
          ++near_junction;
          using std::abs;
          ASSERT_LE(as_double(abs(R(abs(h.q.x) - st.half_d()))), 1e-9) << "a different piece away from a junction";
          break;
        }
        ASSERT_TRUE(same(h.t, g.t) && same(h.q.x, g.q.x) && same(h.q.y, g.q.y)) << "flight " << k;
        ASSERT_TRUE(same(st.s_of(h.piece, h.q), table.s_of(g.piece, g.q))) << "flight " << k;
        const Vec2<R> v1 = st.reflect(h.piece, h.q, v), v2 = table.reflect(g.piece, g.q, v);
        ASSERT_TRUE(same(v1.x, v2.x) && same(v1.y, v2.y)) << "flight " << k;
        ASSERT_TRUE(same(st.birkhoff_p(h.piece, h.q, v1), table.birkhoff_p(g.piece, g.q, v2)));
        qv = h.q, v = v1;
      }
    }
    EXPECT_LE(near_junction, hits / 1000) << d << " " << r;
    EXPECT_TRUE(same(st.area(), table.area()) && same(st.perimeter(), table.perimeter()) &&
                same(st.mean_free_path(), table.mean_free_path()));
  }
}

/// Every table, double and one high precision: flights from random boundary points meet the boundary (never
/// nowhere), on the piece they name, keep unit speed, and s goes there and back.
template <class R>
void follow_every_table() {
  using std::abs;
  using std::sqrt;
  for (const Standard& s : standard_tables()) {
    SCOPED_TRACE(s.name);
    const Table<R> t(s.make());
    std::mt19937_64 gen(5);
    std::uniform_real_distribution<double> u(0, 1), pu(-1, 1);
    const double scale = as_double(t.scale());
    for (int i = 0; i < 200; ++i) {
      const int loop = static_cast<int>(u(gen) * t.loops());
      const TableFrame<R> f = t.at(loop, R(u(gen)));
      const R back = t.s_of(f.piece, f.q);
      const TableFrame<R> g = t.at(loop, back);
      ASSERT_LE(as_double(abs(R(g.q.x - f.q.x))) + as_double(abs(R(g.q.y - f.q.y))), eps_times<R>(64) * scale);
      Vec2<R> q = f.q, v = t.velocity(f, R(pu(gen)));
      for (int k = 0; k < 50; ++k) {
        const TableHit<R> h = t.next_hit(q, v);
        ASSERT_GE(h.piece, 0) << "flight " << k << " from (" << as_double(q.x) << ", " << as_double(q.y) << ")";
        const TablePiece<R>& p = t.piece(h.piece);
        double off;  // distance of the hit from its piece's curve
        if (p.kind == PieceKind::segment)
          off = as_double(abs(R((h.q.x - p.ax) * p.ey - (h.q.y - p.ay) * p.ex)));
        else if (p.kind == PieceKind::ellipse)  // off the unit circle in the scaled coordinates, times the least axis
          off = as_double(abs(R(sqrt((h.q.x - p.cx) * p.inv_ea * ((h.q.x - p.cx) * p.inv_ea) +
                                     (h.q.y - p.cy) * p.inv_eb * ((h.q.y - p.cy) * p.inv_eb)) -
                                R(1)))) *
                std::min(as_double(p.ea), as_double(p.eb));
        else
          off = as_double(abs(R(sqrt((h.q.x - p.cx) * (h.q.x - p.cx) + (h.q.y - p.cy) * (h.q.y - p.cy)) - p.rho)));
        ASSERT_LE(off, eps_times<R>(1e4) * scale) << "flight " << k;
        v = t.reflect(h.piece, h.q, v);
        q = h.q;
        ASSERT_LE(std::abs(as_double(sqrt(dot(v, v))) - 1), eps_times<R>(1e3));
      }
    }
  }
}

TEST(Table, FlightsStayOnEveryTablesBoundaryInDouble) { follow_every_table<double>(); }
TEST(Table, FlightsStayOnEveryTablesBoundaryInMpfr256) { follow_every_table<mpfr256>(); }

/// Santalo's formula: flights drawn from the billiard map's invariant measure (s uniform along the whole boundary,
/// p = sin theta uniform in (-1, 1)) have mean length pi A / |boundary|, for every table. Error model: the sample
/// mean of n independent flights, normal with the flights' own standard deviation / sqrt(n); the tolerance is 5 of
/// those (a false failure about once in 3.5 million runs), so a mistake in next_hit that moves the mean by 1% shows.
TEST(Table, FlightsFromTheInvariantMeasureHaveTheMeanFreePathOfSantalosFormula) {
  for (const Standard& s : standard_tables()) {
    SCOPED_TRACE(s.name);
    const Table<double> t(s.make());
    std::mt19937_64 gen(2026);
    std::uniform_real_distribution<double> u(0, 1), pu(-1, 1);
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
      double at = u(gen) * t.perimeter();  // a point of the whole boundary, uniform in length
      int loop = 0;
      while (loop + 1 < t.loops() && at >= t.loop_length(loop)) at -= t.loop_length(loop), ++loop;
      const TableFrame<double> f = t.at(loop, std::min(at / t.loop_length(loop), std::nextafter(1.0, 0.0)));
      const TableHit<double> h = t.next_hit(f.q, t.velocity(f, pu(gen)));
      ASSERT_GE(h.piece, 0);
      sum += h.t, sum2 += h.t * h.t;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, t.mean_free_path(), 5 * sd / std::sqrt(double(n)))
        << "pi A / |boundary| = " << t.mean_free_path() << ", sd " << sd;
    EXPECT_NEAR(t.mean_free_path(), M_PI * s.area / s.perimeter, 1e-13);
  }
}

/// A leak on the stadium built as a table decides every collision as the stadium's Leak does, stationary (its
/// windows) and moving (phase and s), in every correctly rounded tier.
TYPED_TEST(TableStadium, ALeakOnTheStadiumAsATableDecidesAsTheStadiumsLeak) {
  using R = TypeParam;
  if constexpr (std::is_same_v<R, dd_real>) {
    GTEST_SKIP() << "double-double is not correctly rounded (see TheStadiumAsATableIsTheStadiumBitForBit)";
  } else {
    const Stadium<R> st(q("2"), q("1"));
    const Table<R> table(stadium_table(q("2"), q("1")));
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (const auto& [width, start, omega] :
         {std::tuple{"1/10", "0", "0"}, std::tuple{"3/10", "1/4", "0"}, std::tuple{"1/50", "0.09725", "0"},
          std::tuple{"1/5", "1/2", "0"}, std::tuple{"1/10", "0", "2/3"}, std::tuple{"1/20", "0.3", "-1e-3"}}) {
      SCOPED_TRACE(std::string(width) + " " + start + " " + omega);
      const Leak<R> leak(st, q(width), q(start), q(omega));
      const std::vector<LeakSpec> specs{{0, q(width), q(start), q(omega)}};
      const LeakList<R> list(table, specs);
      int taken = 0;
      for (int i = 0; i < 20000; ++i) {
        const BoundaryPoint<R> b = st.at(static_cast<R>(u(gen)));
        const R t = static_cast<R>(1000 * u(gen));
        const bool a = leak.hit(b.piece, b.q, t);
        const int k = list.hit(table, static_cast<int>(b.piece), b.q, t);
        ASSERT_EQ(a, k == 0) << "s = " << as_double(st.s_of(b.piece, b.q)) << ", t = " << as_double(t);
        taken += a;
      }
      EXPECT_GT(taken, 0);
    }
  }
}

/// On every table, a stationary leak's windows decide as its s does (the moving leak's test, at omega = 0):
/// the two paths agree except within rounding of a leak's end. Leaks on the outer boundary and on scatterers,
/// across pieces, across the origin, and one of more than a half turn of a circle.
// The whole boundary's coordinate (the starts drawn on it, leak lists) lays the loops end to end: loop l starts after
// the lengths before it -- the Sinai table's disc after the square's 8, the annulus's inner circle after the outer
// 2 pi -- and loop_s inverts boundary_share on every loop of every table. A loop's offset stored one place early
// (mutant tests/mutants/table-loop-offset-early.patch, drawn by scripts/mutate.py) put every start of the Sinai
// table's square on its disc and was caught only by a test that then never ended.
TEST(Table, TheBoundaryCoordinateLaysTheLoopsEndToEnd) {
  const std::vector<std::pair<std::string, double>> second = {{"sinai", 8.0}, {"annulus", 2 * M_PI}};
  int two_loops = 0;
  for (const Standard& st : standard_tables()) {
    SCOPED_TRACE(st.name);
    const Table<double> t(st.make());
    EXPECT_EQ(t.loop_offset(0), 0.0);
    for (const auto& [name, offset] : second)
      if (name == st.name) {
        ASSERT_EQ(t.loops(), 2);
        EXPECT_NEAR(t.loop_offset(1), offset, 1e-14 * offset);
        ++two_loops;
      }
    for (int l = 0; l < t.loops(); ++l)
      for (const double s : {0.0, 0.1, 0.5, 0.9, 0.999}) {
        const auto [loop, back] = t.loop_s(t.boundary_share(l, s));
        EXPECT_EQ(loop, l) << "s = " << s;
        EXPECT_NEAR(back, s, 1e-12) << "loop " << l;
      }
  }
  EXPECT_EQ(two_loops, 2);
}

// A split copy's turn asks which piece a member sits on and how far it is (Table::piece_nearest,
// sim/engine/population.cpp): a boundary point is within the table's slack of its own piece, and a point a hair
// inside is that hair away, not within the slack, on every kind of piece. The ellipse's distance with its Y^2 term
// dropped (drawn by scripts/mutate.py) put every point of an ellipse far from it, and no run had shown it.
TEST(Table, APointOnTheBoundaryIsWithinTheSlackOfItsPieceAndAHairInsideIsNot) {
  for (const Standard& st : standard_tables()) {
    SCOPED_TRACE(st.name);
    const Table<double> t(st.make());
    const double hair = 1e-6 * t.scale();
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> u(0.001, 0.999);
    for (int i = 0; i < 200; ++i) {
      const int loop = static_cast<int>(u(gen) * t.loops());
      const TableFrame<double> f = t.at(loop, u(gen));
      const double d = t.piece_nearest(f.q).second;
      EXPECT_LE(d, t.slack()) << "point " << i << " on piece " << f.piece;
      for (const double side : {1.0, -1.0}) {  // inside and outside the loop, a hair off
        const Vec2<double> q{f.q.x + side * hair * f.normal.x, f.q.y + side * hair * f.normal.y};
        const double d2 = t.piece_nearest(q).second;
        EXPECT_GT(d2, t.slack()) << "point " << i << " side " << side;
        EXPECT_NEAR(d2, hair, 1e-3 * hair) << "point " << i << " side " << side << " piece " << f.piece;
      }
    }
  }
}

TEST(Table, EveryTablesLeakWindowsDecideAsItsBoundaryCoordinate) {
  for (const Standard& st : standard_tables()) {
    SCOPED_TRACE(st.name);
    const Table<double> t(st.make());
    std::mt19937_64 gen(9);
    std::uniform_real_distribution<double> u(0, 1);
    for (const auto& [loop, width, start] :
         {std::tuple{0, "1/10", "0"}, std::tuple{0, "3/10", "0.3"}, std::tuple{0, "0.7", "0.6"},
          std::tuple{1, "1/4", "0.9"}, std::tuple{1, "0.6", "0.2"}}) {
      if (loop >= t.loops()) continue;
      SCOPED_TRACE(std::to_string(loop) + " " + width + " " + start);
      const LeakList<double> list(t, std::vector<LeakSpec>{{loop, q(width), q(start), q("0")}});
      const LeakView<double>& leak = list[0];
      int taken = 0, near_end = 0;
      for (int i = 0; i < 20000; ++i) {
        const TableFrame<double> f = t.at(loop, u(gen));
        const double s = t.s_of(f.piece, f.q);
        const bool by_s = formula::in_leak(s, leak.start, leak.half_width);
        const bool by_window = list.hit(t, f.piece, f.q, 0.0) == 0;
        if (formula::distance_to_leak_end(s, leak.start, leak.half_width) < 1e-12) {
          ++near_end;
          continue;
        }
        ASSERT_EQ(by_window, by_s) << "s = " << s << " on piece " << f.piece;
        taken += by_s;
      }
      EXPECT_GT(taken, 0);
      EXPECT_LE(near_end, 2);
    }
  }
}

/// The one collision step (advance) on the stadium built as a table (TableModel: the next hit over the pieces,
/// the leak list) runs the stadium model's particles (its convex shortcut) to the same ends, bit for bit: fate,
/// time, s and collisions, stationary and moving leaks. Trajectories are chaotic, so a single hit within rounding
/// of a junction that the two name differently would part them; none is expected (see
/// TheStadiumAsATableIsTheStadiumBitForBit), and the test allows none.
TEST(TableModel, TheStadiumAsATableRunsTheStadiumsParticlesToTheSameEnds) {
  const InitialConditions ic(7, InitKind::birkhoff, 0.0, 1.0, 1.0);
  for (const auto& [width, start, omega] : {std::tuple{"1/50", "1/4", "0"}, std::tuple{"1/50", "0", "2/3"}}) {
    SCOPED_TRACE(std::string(start) + " " + omega);
    const Model<double> stadium(q("2"), q("1"), q(width), q(start), q(omega), 2000);
    const std::vector<LeakSpec> leaks{{0, q(width), q(start), q(omega)}};
    const TableModel<double> table(stadium_table(q("2"), q("1")), leaks, 2000);
    NoCollisionObserver<double> none;
    std::uint64_t collisions = 0;
    for (std::uint64_t id = 0; id < 2000; ++id) {
      const ParticleState<double> ps = initial_state(stadium.stadium, ic.draw(id));
      const ParticleEnd a = run_particle(stadium, ps, none), b = run_particle(table, ps, none);
      ASSERT_EQ(a.fate, b.fate) << "particle " << id;
      ASSERT_EQ(a.t, b.t) << "particle " << id;
      ASSERT_EQ(a.s, b.s) << "particle " << id;
      ASSERT_EQ(a.collisions, b.collisions) << "particle " << id;
      collisions += a.collisions;
    }
    EXPECT_GT(collisions, 100000u);
  }
}

/// Two leaks, each particle's end naming the one that took it. Two equal leaks that a symmetry of the table swaps
/// (the stadium's half turn: s -> s + 1/2; the circle's quarter turn: s -> s + 1/4), with starts drawn from a
/// measure that symmetry keeps (Birkhoff-uniform), take equal shares of the escapes. Error model: given n escapes,
/// leak 0's count is binomial(n, 1/2); the tolerance is 5 of its standard deviations, sqrt(n) / 2.
TEST(TableModel, TwoLeaksThatASymmetrySwapsTakeEqualSharesOfTheEscapes) {
  struct Case {
    std::string name;
    TableSpec table;
    const char* second;
  };
  for (const Case& c :
       {Case{"stadium", stadium_table(q("2"), q("1")), "1/2"}, Case{"circle", circle_table(q("1")), "1/4"}}) {
    SCOPED_TRACE(c.name);
    const std::vector<LeakSpec> leaks{{0, q("1/20"), q("0"), q("0")}, {0, q("1/20"), q(c.second), q("0")}};
    const TableModel<double> m(c.table, leaks, 5000);
    std::mt19937_64 gen(12);
    std::uniform_real_distribution<double> u(0, 1), pu(-1, 1);
    NoCollisionObserver<double> none;
    long escaped[2] = {0, 0}, n = 0;
    for (int i = 0; i < 20000; ++i) {
      const TableFrame<double> f = m.table.at(0, u(gen));
      const ParticleEnd e = run_particle(m, ParticleState<double>{f.q, m.table.velocity(f, pu(gen)), 0.0}, none);
      if (e.fate != Fate::escaped) continue;
      ASSERT_TRUE(e.leak == 0 || e.leak == 1);
      ++escaped[e.leak], ++n;
    }
    ASSERT_GT(n, 10000);
    const double share = static_cast<double>(escaped[0]) / static_cast<double>(n);
    const double err = std::sqrt(share * (1 - share) / static_cast<double>(n));
    EXPECT_NEAR(static_cast<double>(escaped[0]), static_cast<double>(n) / 2, 5 * std::sqrt(static_cast<double>(n)) / 2)
        << "leak 0 took " << share << " +- " << err << " of " << n << " escapes";
  }
}
