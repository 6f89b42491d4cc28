// Proven periodic orbits (verify/orbits.hpp, docs/model.md "Periodic orbits"): the closed-form multipliers,
// codes without an orbit refused, proofs that nest when the bits double, the code enumeration against a
// brute-force count, and the found set closed under the stadium's mirrors and stable against more starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "analysis/cycle_expansion.hpp"
#include "io/files.hpp"
#include "numeric/input.hpp"
#include "paths.hpp"
#include "scratch.hpp"
#include "verify/orbit_checkpoint.hpp"
#include "verify/orbit_replay.hpp"
#include "verify/orbits.hpp"

namespace rotleak {
namespace {

const ExactReal kD = ExactReal::parse("2"), kR = ExactReal::parse("1");

/// |enclosure's midpoint - exact| and whether the enclosure holds the exact value, at 256 bits.
void expect_value(const Mpfi& got, const Mpfr& exact, const char* what) {
  EXPECT_TRUE(got.contains(exact.data())) << what << ": the enclosure misses the closed form";
  mpfr_t mid;
  mpfr_init2(mid, 256);
  mpfi_mid(mid, got.data());
  mpfr_sub(mid, mid, exact.data(), MPFR_RNDN);
  EXPECT_LT(std::abs(mpfr_get_d(mid, MPFR_RNDN)), 1e-30) << what;
  mpfr_clear(mid);
}

// The horizontal 2-bounce orbit through (+-2, 0): Lambda = 17 + 12 sqrt 2, length 8. The diamond through
// (0, +-1), (+-2, 0): Lambda = 31 + 8 sqrt 15, length 4 sqrt 5 (d = 2, r = 1). Both enclosed and matched
// to 1e-30.
TEST(Orbits, ClosedFormMultipliersAndLengths) {
  OrbitOptions opt;
  const CodeOrbits rl = code_orbits(kD, kR, parse_orbit_code("RL"), opt);
  const CodeOrbits diamond = code_orbits(kD, kR, parse_orbit_code("TRBL"), opt);
  ASSERT_EQ(rl.orbits.size(), 1u);
  ASSERT_EQ(diamond.orbits.size(), 1u);
  const MpfrPrecision guard(256);
  expect_value(rl.orbits[0].multiplier, Mpfr(17) + Mpfr(12) * sqrt(Mpfr(2)), "RL multiplier");
  expect_value(rl.orbits[0].length, Mpfr(8), "RL length");
  expect_value(diamond.orbits[0].multiplier, Mpfr(31) + Mpfr(8) * sqrt(Mpfr(15)), "TRBL multiplier");
  expect_value(diamond.orbits[0].length, Mpfr(4) * sqrt(Mpfr(5)), "TRBL length");
  EXPECT_EQ(rl.orbits[0].stability(), "hyperbolic");
  EXPECT_EQ(rl.orbits[0].weight, 1);  // its own reverse
}

// RRR has no orbit (a circle keeps the angle of incidence, so three bounces on one semicircle step the centre
// angle by 2 pi / 3 each, a span of 4 pi / 3 > pi), nor has BR (perpendicular to the bottom and to the arc: the
// vertical through the arc's centre, which meets both at the junction), nor TB (the bouncing-ball family, a
// continuum: none isolated). Each is refused: no orbit listed. A start that is no zero is proven only as the
// zero Newton reaches from it (its box holds that zero, not the start).
TEST(Orbits, CodesWithoutAnOrbitAreRefused) {
  OrbitOptions opt;
  for (const char* text : {"RRR", "BR", "TB", "TBTB"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), opt);
    EXPECT_TRUE(got.orbits.empty()) << text;
    EXPECT_EQ(got.family, std::string(text).find('R') == std::string::npos) << text;
  }
  const MpfrPrecision guard(opt.bits);
  ProvenOrbit o;
  ASSERT_TRUE(prove_orbit(kD, kR, parse_orbit_code("RL"), {Mpfr(0.3), Mpfr(0.1)}, opt.bits, o));
  EXPECT_TRUE(o.box[0].contains(Mpfr(0).data()) && o.box[1].contains(Mpfr(0).data()));
  EXPECT_FALSE(o.proof_box[0].contains(Mpfr(0.3).data()));
  EXPECT_THROW(parse_orbit_code("TTR"), InputError);
  EXPECT_THROW(parse_orbit_code("BRB"), InputError);  // cyclically B follows B
  EXPECT_THROW(parse_orbit_code("TXB"), InputError);
  EXPECT_THROW(parse_orbit_code("R"), InputError);
}

// An orbit proven again at twice the bits (from its box's midpoint) lies inside the first proof's box and
// inside its Krawczyk image: the two proofs speak of the same unique zero.
TEST(Orbits, ReprovenAtTwiceTheBitsLiesInTheFirstBox) {
  OrbitOptions opt;
  for (const char* text : {"RRL", "TRL", "TRBL", "RRLRLLB", "TRRBLLTRBL"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), opt);
    ASSERT_FALSE(got.orbits.empty()) << text;
    for (const ProvenOrbit& first : got.orbits) {
      const MpfrPrecision guard(2 * opt.bits);
      const std::vector<Mpfr> mid = box_midpoint(first.box);
      ProvenOrbit second;
      ASSERT_TRUE(prove_orbit(kD, kR, first.code, mid, 2 * opt.bits, second)) << text;
      for (std::size_t i = 0; i < mid.size(); ++i) {
        EXPECT_GT(mpfi_is_strictly_inside(second.box[i].data(), first.proof_box[i].data()), 0) << text << " " << i;
        EXPECT_GT(mpfi_is_inside(second.box[i].data(), first.box[i].data()), 0) << text << " " << i;
      }
      EXPECT_LT(second.box_width, first.box_width * 1e-20) << text;
    }
  }
}

// The Krawczyk test must refuse what it cannot prove: a box around a proven orbit's point is proven at the
// proof's radius 2^-(bits/2) and refused when too wide for the Hessian to be near its midpoint value (radius
// 1/4, 1/16); a small box around a point 1e-3 from the orbit (no zero in it) is refused; a box around two zeros
// of one code (RRL's two mirror orbits, centred between them) is refused, since it cannot hold exactly one.
// Checking the Hessian at the midpoint only (not over the box) would "prove" the wide boxes.
TEST(Krawczyk, RefusesBoxesThatCannotContract) {
  OrbitOptions opt;
  for (const char* text : {"TRL", "RRL", "TRBL", "RRLRLLB"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), opt);
    ASSERT_FALSE(got.orbits.empty()) << text;
    const ProvenOrbit& o = got.orbits[0];
    const MpfrPrecision guard(opt.bits);
    const std::vector<Mpfr> m = box_midpoint(o.box);
    EXPECT_TRUE(krawczyk_contracts(kD, kR, o.code, m, opt.bits / 2)) << text;
    for (long wide : {2L, 4L})
      EXPECT_FALSE(krawczyk_contracts(kD, kR, o.code, m, wide)) << text << " radius 2^-" << wide;
    std::vector<Mpfr> off = m;
    off[0] += Mpfr(1e-3);
    EXPECT_FALSE(krawczyk_contracts(kD, kR, o.code, off, opt.bits / 2)) << text << ": a box with no zero";
  }
  const CodeOrbits two = code_orbits(kD, kR, parse_orbit_code("RRL"), opt);
  ASSERT_EQ(two.orbits.size(), 2u);
  const MpfrPrecision guard(opt.bits);
  const std::vector<Mpfr> a = box_midpoint(two.orbits[0].box), b = box_midpoint(two.orbits[1].box);
  std::vector<Mpfr> mid;
  double half = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    mid.push_back((a[i] + b[i]) / Mpfr(2));
    half = std::max(half, std::abs(num_traits<Mpfr>::to_double(a[i] - b[i])) / 2);
  }
  const long shift = static_cast<long>(std::floor(-std::log2(half))) - 1;  // 2^-shift > half: both zeros inside
  ASSERT_GT(std::ldexp(1.0, static_cast<int>(-shift)), half);
  EXPECT_FALSE(krawczyk_contracts(kD, kR, two.orbits[0].code, mid, shift)) << "a box around two zeros";
}

// Admissibility: the equations continue each piece past its ends (an edge's line, an arc's circle), so Newton
// from starts outside the pieces can reach zeros that are no orbit of the stadium; the proof must refuse them.
// Starts on a grid reaching 0.9 past each piece's bound (|u| < d/2 on an edge, pi/2 on an arc): every orbit
// proven from them bounces strictly inside its pieces (with the bound loosened by 1, TRRL's starts prove zeros
// whose second bounce lies past its arc).
TEST(Orbits, ZerosOutsideThePiecesAreRefused) {
  OrbitOptions opt;
  const MpfrPrecision guard(opt.bits);
  int proven = 0;
  for (const char* text : {"TRL", "RRL", "TRB", "TRRL", "RRLB"}) {
    const OrbitCode code = parse_orbit_code(text);
    const std::size_t n = code.size();
    std::vector<double> bound(n);
    for (std::size_t i = 0; i < n; ++i) bound[i] = code[i] == Piece::top || code[i] == Piece::bottom ? 1.0 : M_PI / 2;
    for (int k = 0; k < 200; ++k) {
      std::vector<Mpfr> u;
      for (std::size_t i = 0; i < n; ++i) {  // a deterministic spread of starts over (bound + 0.9) in each u
        const double f = std::fmod(0.6180339887498949 * (k + 1) * static_cast<double>(i + 1) + 0.1 * k, 1.0);
        u.emplace_back((2 * f - 1) * (bound[i] + 0.9));
      }
      ProvenOrbit o;
      if (!prove_orbit(kD, kR, code, u, opt.bits, o)) continue;
      ++proven;
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_LT(std::abs(num_traits<Mpfi>::to_double(o.box[i])), bound[i]) << text << " bounce " << i;
    }
  }
  EXPECT_GT(proven, 0);
}

// The claim fails one ulp away: an orbit's proof box for d = 2 holds no zero of the stadium whose d is one ulp
// of double above 2 (the orbit moves by ~1e-16, the box is 2^-80 wide): its Krawczyk test there is refused,
// while that stadium's own orbits are proven. The diamond TRBL is the control: its bounces sit at the pieces'
// midpoints whatever d (u = 0 each), so its claim rightly holds on both stadiums.
TEST(Krawczyk, TheProofFailsForAStadiumOneUlpAway) {
  OrbitOptions opt;
  const ExactReal d_ulp = ExactReal::parse("2.000000000000000444089209850062616169452667236328125");  // 2 + 2^-51
  for (const char* text : {"TRBL", "TRL", "RRLRLLB", "TRRBLLTRBL"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), opt);
    ASSERT_FALSE(got.orbits.empty()) << text;
    const MpfrPrecision guard(opt.bits);
    const std::vector<Mpfr> m = box_midpoint(got.orbits[0].box);
    EXPECT_TRUE(krawczyk_contracts(kD, kR, got.orbits[0].code, m, opt.bits / 2)) << text;
    EXPECT_EQ(krawczyk_contracts(d_ulp, kR, got.orbits[0].code, m, opt.bits / 2), std::string(text) == "TRBL") << text;
    const CodeOrbits moved = code_orbits(d_ulp, kR, parse_orbit_code(text), opt);
    EXPECT_EQ(moved.orbits.size(), got.orbits.size()) << text;
  }
}

// The stored orbits (data/orbits, periods 2 to 11) regenerated to period 6 (125 rows): the same bytes, row for
// row, as the stored file's first rows; a proof that changed would change a box width or a digit.
TEST(Orbits, RegeneratedToPeriodSixAreTheStoredRows) {
  const test::ScratchDir dir("rotleak_orbits_regen_");
  const OrbitSearch s = find_orbits(kD, kR, 6, OrbitOptions{}, 0);
  write_orbits(dir.path, kD, kR, s, OrbitOptions{});
  const std::string fresh = read_file(dir.path / "orbits.csv");
  const std::string stored = read_file(std::filesystem::path(test::source_dir()) / "data" / "orbits" / "orbits.csv");
  std::size_t rows = 0;
  for (char ch : fresh) rows += ch == '\n';
  EXPECT_EQ(rows, 126u) << "header and 125 orbits to period 6";
  ASSERT_LE(fresh.size(), stored.size());
  EXPECT_EQ(stored.substr(0, fresh.size()), fresh);
  const std::size_t next = stored.find('\n', fresh.size());
  ASSERT_NE(next, std::string::npos);
  const std::string after = stored.substr(fresh.size(), next - fresh.size());
  EXPECT_NE(after.find(",7,"), std::string::npos) << "the stored rows after period 6 start period 7: " << after;
}

// orbit_codes(n): one code per class under rotation and reversal, against a brute-force count of the
// classes of all 4^n words with no two cyclically adjacent bounces on one straight edge.
TEST(Orbits, CodesAreOnePerClassOfRotationAndReversal) {
  for (int n = 2; n <= 7; ++n) {
    std::set<std::string> classes;
    std::string w(static_cast<std::size_t>(n), 'T');
    for (long k = 0; k < (1L << (2 * n)); ++k) {
      for (int i = 0; i < n; ++i) w[static_cast<std::size_t>(i)] = "TRBL"[(k >> (2 * i)) & 3];
      bool ok = true;
      for (int i = 0; i < n && ok; ++i) {
        const char a = w[static_cast<std::size_t>(i)], b = w[static_cast<std::size_t>((i + 1) % n)];
        ok = !((a == 'T' || a == 'B') && a == b);
      }
      if (!ok) continue;
      std::string best = w, rev(w.rbegin(), w.rend());
      for (int s = 0; s < n; ++s) {
        best = std::min({best, w.substr(static_cast<std::size_t>(s)) + w.substr(0, static_cast<std::size_t>(s)),
                         rev.substr(static_cast<std::size_t>(s)) + rev.substr(0, static_cast<std::size_t>(s))},
                        [](const std::string& a, const std::string& b) {
                          // the enumeration's order: T < R < B < L
                          const auto rank = [](char c) { return std::string("TRBL").find(c); };
                          return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(),
                                                              [&](char x, char y) { return rank(x) < rank(y); });
                        });
      }
      classes.insert(best);
    }
    std::set<std::string> ours;
    for (const OrbitCode& c : orbit_codes(n)) ours.insert(orbit_code_text(c));
    EXPECT_EQ(ours, classes) << "period " << n;
  }
}

// The search to period 8: four times the starts (another seed) find no orbit more (the count is the search's
// fixed point), and every orbit's mirror images are in the set (close_under_symmetry adds what a code's own
// search missed; at period 11 it adds 44 orbits).
TEST(Orbits, TheSetIsClosedUnderMirrorsAndStableAgainstMoreStarts) {
  OrbitOptions opt;
  opt.starts = 24;
  const OrbitSearch a = find_orbits(kD, kR, 8, opt, 0);
  opt.starts = 96;
  opt.seed = 7;
  const OrbitSearch b = find_orbits(kD, kR, 8, opt, 0);
  ASSERT_EQ(a.periods.size(), b.periods.size());
  for (std::size_t i = 0; i < a.periods.size(); ++i) {
    EXPECT_EQ(a.periods[i].proven, b.periods[i].proven) << "period " << a.periods[i].period;
    EXPECT_EQ(a.periods[i].prime_cycles, b.periods[i].prime_cycles) << "period " << a.periods[i].period;
    EXPECT_EQ(a.periods[i].unproven, 0u);
  }
  // each orbit's three mirror images lie in proof boxes of their codes' orbits
  std::map<std::string, std::vector<const ProvenOrbit*>> by_code;
  for (const ProvenOrbit& o : a.orbits) by_code[orbit_code_text(o.code)].push_back(&o);
  const MpfrPrecision guard(opt.bits);
  std::size_t images = 0;
  for (const ProvenOrbit& o : a.orbits) {
    const std::vector<Mpfr> mid = box_midpoint(o.box);
    for (const auto& [mx, my] : {std::pair{true, false}, {false, true}, {true, true}}) {
      const auto [code, u] = mirror_orbit(o.code, mid, mx, my);
      const auto& list = by_code[orbit_code_text(code)];
      const bool held = std::any_of(list.begin(), list.end(), [&](const ProvenOrbit* p) {
        for (std::size_t s = 0; s < u.size(); ++s) {  // the image may start at another bounce of a code w^k
          bool in = true;
          for (std::size_t i = 0; i < u.size() && in; ++i) in = p->proof_box[i].contains(u[(i + s) % u.size()].data());
          if (in) return true;
        }
        return false;
      });
      EXPECT_TRUE(held) << orbit_code_text(o.code) << " mirrored (" << mx << ", " << my << ") -> "
                        << orbit_code_text(code);
      ++images;
    }
  }
  EXPECT_EQ(images, 3 * a.orbits.size());
}

// The cycle expansion on a system it must reproduce exactly: the full binary shift with every symbol
// stretching by 2 and taking time 1 + symbol (prime cycles: the binary Lyndon words, P_n = (1/n) sum_{d | n}
// mu(d) 2^{n/d}). Its zeta functions are polynomials of degree 1 in z: the topological entropy is ln 2 and
// the Lyapunov exponent ln 2 a collision at every order, and ln 2 / (3/2) a unit time (each symbol weighs
// 1/|Lambda| = 1/2, so the mean time a collision is 3/2).
TEST(Orbits, CycleExpansionIsExactOnTheFullBinaryShift) {
  std::vector<PrimeCycle> cycles;
  for (int n = 1; n <= 10; ++n)
    for (unsigned w = 0; w < (1u << n); ++w) {
      bool lyndon = true;  // w smaller than each of its proper rotations
      for (int k = 1; k < n && lyndon; ++k) {
        const unsigned rot = ((w << k) | (w >> (n - k))) & ((1u << n) - 1);
        lyndon = w < rot;
      }
      if (n == 1) lyndon = true;
      if (!lyndon) continue;
      const int ones = __builtin_popcount(w);
      cycles.push_back({n, static_cast<double>(n + ones), n * std::log(2.0), 1});
    }
  for (const CycleAverages& a : cycle_averages(cycles, 10)) {
    EXPECT_NEAR(a.entropy, std::log(2.0), 1e-12) << a.order;
    EXPECT_NEAR(a.lyapunov_collision, std::log(2.0), 1e-12) << a.order;
    EXPECT_NEAR(a.lyapunov_time, std::log(2.0) / 1.5, 1e-12) << a.order;
    EXPECT_NEAR(a.escape_time, 0.0, 1e-12) << a.order;
  }
}

// The stadium's cycles to period 9: the topological entropy stays below Cinc & Troubetzkoy's rigorous bound
// log(3.49066) on the billiard map's (every cycle count N_n <= 3.49066^n, up to the polynomial factor the
// bound allows: here the plain inequality is checked), and a closed billiard escapes at rate 0 (|s(0)| small
// against the Lyapunov exponent).
TEST(Orbits, StadiumCyclesRespectTheEntropyBound) {
  const OrbitSearch s = find_orbits(kD, kR, 9, OrbitOptions{}, 0);
  const std::vector<PrimeCycle> cycles = prime_cycles(s, OrbitOptions{});
  const double bound = std::log(3.49066);
  for (const CycleAverages& a : cycle_averages(cycles, 9)) {
    EXPECT_LT(a.entropy, bound) << a.order;
    EXPECT_LT(a.entropy_count, bound) << a.order;
  }
  const CycleAverages last = cycle_averages(cycles, 9).back();
  EXPECT_LT(std::abs(last.escape_time), 0.1 * last.lyapunov_time);
}

// Each tier follows a proven orbit until its own error, amplified by |Lambda| a period, passes the tolerance:
// the departure collision lies in the error model's window around n ln(tol / u) / ln|Lambda|, for every
// tier from float to MPFR at 256 bits, on every piece the code says. (Not RL: on the x axis, started at
// s = 1/4, p = 0 exactly, double-double and float128 compute the symmetric orbit without error and never
// leave it.)
TEST(OrbitReplay, EachTierLeavesTheOrbitWhenItsErrorModelSays) {
  for (const char* text : {"TRBL", "RRL", "TRRBLLTRBL", "RRLRLLB"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), OrbitOptions{});
    ASSERT_FALSE(got.orbits.empty()) << text;
    for (const std::string& tier : replay_tiers()) {
      const OrbitReplay rp = replay_orbit(kD, kR, got.orbits[0], tier);
      std::printf("%s %-12s departs at %zu, predicted %.1f [%.1f, %.1f], A ~ %.3g\n", text, tier.c_str(), rp.departure,
                  rp.predicted, rp.low, rp.high,
                  1e-6 / (rp.unit_roundoff * std::exp(rp.log_multiplier * static_cast<double>(rp.departure) /
                                                      static_cast<double>(rp.period))));
      EXPECT_TRUE(rp.pass) << text << " " << tier << ": departs at " << rp.departure << ", window [" << rp.low << ", "
                           << rp.high << "], wrong piece at " << rp.wrong_piece;
    }
  }
}

// A one-ulp change in the reflection (v.x += 2^-53 v.x after each bounce, an error double makes anyway)
// leaves float and double on their schedule, and breaks the replay of every finer tier: they leave the orbit
// at double's time, far before their own window.
TEST(OrbitReplay, AOneUlpChangeInTheReflectionBreaksTheFinerTiers) {
  const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code("TRBL"), OrbitOptions{});
  ASSERT_EQ(got.orbits.size(), 1u);
  ReplayOptions kicked;
  kicked.reflection_kick = 0x1p-53;
  for (const std::string& tier : replay_tiers()) {
    const OrbitReplay clean = replay_orbit(kD, kR, got.orbits[0], tier),
                      rp = replay_orbit(kD, kR, got.orbits[0], tier, kicked);
    EXPECT_TRUE(clean.pass) << tier;
    const bool coarse = tier == "float" || tier == "double";
    EXPECT_EQ(rp.pass, coarse) << tier << ": departs at " << rp.departure << ", window [" << rp.low << ", " << rp.high
                               << "]";
    if (!coarse) {
      EXPECT_LT(static_cast<double>(rp.departure), rp.low) << tier;
    }
  }
}

// Each engine (scalar and vectorised, with and without the fast-forward) follows a proven orbit from bounce
// 0 for one period: a leak of width 1e-6 centred there takes the particle at collision n, at the orbit's
// length. With p0 moved by 1e-7 the particle misses it (the check can fail).
TEST(OrbitReplay, EnginesFollowAnOrbitForAPeriod) {
  for (const char* text : {"TRBL", "RRLRLLB"}) {
    const CodeOrbits got = code_orbits(kD, kR, parse_orbit_code(text), OrbitOptions{});
    ASSERT_FALSE(got.orbits.empty());
    for (const Engine e : {Engine::scalar, Engine::simd})
      for (const bool ff : {false, true}) {
        const OrbitEngineReplay rp = replay_orbit_engine(kD, kR, got.orbits[0], e, ff);
        EXPECT_TRUE(rp.pass) << text << " " << rp.engine << ": expected " << rp.expected << ", got " << rp.got;
      }
    ProvenOrbit moved = got.orbits[0];
    moved.p0 = moved.p0 + Mpfi(1e-7);
    EXPECT_FALSE(replay_orbit_engine(kD, kR, moved, Engine::scalar, false).pass) << text;
  }
}

// A second stadium (d = 1, r = 1): the horizontal orbit between the arcs, a chord of l = d + 2 r = 3, has
// trace 2 (2 (l / r - 1)^2 - 1) = 14, so Lambda = 7 + 4 sqrt 3, and length 2 l = 6.
TEST(Orbits, ClosedFormOnASecondStadium) {
  const ExactReal d1 = ExactReal::parse("1");
  const CodeOrbits rl = code_orbits(d1, kR, parse_orbit_code("RL"), OrbitOptions{});
  ASSERT_EQ(rl.orbits.size(), 1u);
  const MpfrPrecision guard(256);
  expect_value(rl.orbits[0].multiplier, Mpfr(7) + Mpfr(4) * sqrt(Mpfr(3)), "RL multiplier, d = 1");
  expect_value(rl.orbits[0].length, Mpfr(6), "RL length, d = 1");
}

/// What a search's orbits.csv would hold, as text: codes, weights, enclosures to 30 digits, box widths.
std::string listing(const OrbitSearch& s) {
  std::string out;
  const MpfrPrecision guard(OrbitOptions{}.bits);
  for (const ProvenOrbit& o : s.orbits)
    out += orbit_code_text(o.code) + " " + std::to_string(o.weight) + " " + orbit_digits(o.length) + " " +
           orbit_digits(o.multiplier) + " " + std::to_string(o.box_width) + "\n";
  for (const PeriodTally& t : s.periods)
    out += std::to_string(t.period) + ": " + std::to_string(t.proven) + " " + std::to_string(t.prime_cycles) + "\n";
  return out;
}

// A search stopped after period 5 (its checkpoint written) and resumed to period 7 lists exactly what one
// search to period 7 lists: the stored points are the proofs' own (exact hexadecimal), and refining a
// refined point changes nothing. A checkpoint of other inputs is refused; a damaged one names its line.
TEST(Orbits, AResumedSearchListsWhatOneSearchLists) {
  const test::ScratchDir dir("rotleak_orbits_ckpt_");
  std::filesystem::create_directories(dir.path);
  const std::filesystem::path ckpt = dir.path / "orbits.checkpoint";
  const OrbitSearch whole = find_orbits(kD, kR, 7, OrbitOptions{}, 0);
  find_orbits(kD, kR, 5, OrbitOptions{}, 0, nullptr, ckpt);
  ASSERT_TRUE(std::filesystem::exists(ckpt));
  const OrbitSearch resumed = find_orbits(kD, kR, 7, OrbitOptions{}, 0, nullptr, ckpt);
  EXPECT_EQ(listing(resumed), listing(whole));
  const OrbitSearch shorter = find_orbits(kD, kR, 4, OrbitOptions{}, 0, nullptr, ckpt);
  EXPECT_EQ(shorter.periods.size(), 3u);
  OrbitOptions other;
  other.seed = 2;
  EXPECT_THROW(find_orbits(kD, kR, 7, other, 0, nullptr, ckpt), InputError);
  const std::string text = read_file(ckpt);
  for (const std::string& bad :
       {text.substr(0, text.size() / 2), std::string("rotleak-orbits-checkpoint 1\n"),
        std::string("rotleak-orbits-checkpoint 1\ninputs\n"),  // found by fuzz_orbit_checkpoint
        text + "orbit RL 1 0x0p0\n", text + "period 9 1 1 1 1 0 1 0 0 0.1\n"}) {
    try {
      parse_orbit_checkpoint(bad, "ckpt");
      ADD_FAILURE() << "accepted: " << bad.substr(bad.size() > 60 ? bad.size() - 60 : 0);
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("ckpt:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rotleak
