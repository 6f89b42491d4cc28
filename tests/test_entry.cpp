// Particles that enter through a hole (ensemble.enter_through, docs/tables.md "Transmission and reflection"): the
// key's checks, the draws (the Birkhoff measure restricted to the hole, on any loop), and the one exact law the
// engine must keep: time reversal makes transmission reciprocal, the escapes from A through B at each time as
// many as from B through A for holes of equal width, while the two holes' reflections may differ.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "analysis/output/run_output.hpp"
#include "geometry/table.hpp"
#include "geometry/table_spec.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "leak/leak.hpp"
#include "scene_error.hpp"
#include "sim/engine/engine.hpp"
#include "sim/model/sampling.hpp"

using namespace rotleak;

namespace {

/// The stadium d = 4, r = 1 (L = 8 + 2 pi) with hole A on the top edge at x in [-1.5, -0.7] and hole B on the
/// bottom edge at x in [0.1, 0.9] (the bottom edge runs from s = 1/2 at x = 0 towards -x): the scene of the
/// two-hole comparison in docs/model.md ("Two holes: transmission and reflection").
const char* kTwoHoles =
    "[stadium]\nd = \"4\"\nr = \"1\"\n\n"
    "[[leaks]]\nwidth = \"0.8/(8+2*pi)\"\nstart = \"-1.1/(8+2*pi)\"\n\n"
    "[[leaks]]\nwidth = \"0.8/(8+2*pi)\"\nstart = \"1/2-0.5/(8+2*pi)\"\n\n"
    "[ensemble]\ncreation_window = 0.0\n\n[run]\nt_max = 3000.0\n";

/// Escapes through `leak` per survival bin.
std::vector<std::uint64_t> through(const Tally& t, std::size_t leak) {
  std::vector<std::uint64_t> out(t.escapes_per_bin.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = t.leak_escapes(leak, k);
  return out;
}

/// Two samples of one distribution over time bins, each count Poisson given its total: the binned chi-square
/// sum (n_k - m_k)^2 / (n_k + m_k) over bins merged until each pair holds >= 20 escapes, and its degrees of freedom.
std::pair<double, int> two_sample_chi2(const std::vector<std::uint64_t>& n, const std::vector<std::uint64_t>& m) {
  double chi2 = 0, a = 0, b = 0;
  int dof = 0;
  for (std::size_t k = 0; k < n.size(); ++k) {
    a += static_cast<double>(n[k]), b += static_cast<double>(m[k]);
    if (a + b < 20 && k + 1 < n.size()) continue;
    if (a + b > 0) chi2 += (a - b) * (a - b) / (a + b), ++dof;
    a = b = 0;
  }
  return {chi2, dof};
}

}  // namespace

TEST(Entry, TheKeyIsCheckedAndWrittenBack) {
  const std::string two = "[[leaks]]\nwidth = \"0.02\"\n\n[[leaks]]\nwidth = \"0.02\"\nstart = \"1/2\"\n";
  EXPECT_EQ(error_of(two, {"ensemble.enter_through=1"}), "");
  EXPECT_EQ(error_of("", {"ensemble.enter_through=0"}), "");  // the one leak of [leak]
  const std::string beyond = error_of(two, {"ensemble.enter_through=2"});
  EXPECT_EQ(beyond.rfind("ensemble.enter_through = 2: must be a leak's place in the list, an integer in [0, 1]", 0), 0u)
      << beyond;
  EXPECT_EQ(error_of(two, {"ensemble.enter_through=-1"}).rfind("ensemble.enter_through = -1", 0), 0u);
  const std::string flow = error_of(two, {"ensemble.enter_through=0", "ensemble.init=flow"});
  EXPECT_NE(flow.find("ensemble.init = \"birkhoff\" only"), std::string::npos) << flow;
  const std::string mupo = error_of("", {"ensemble.enter_through=0", "ensemble.sampling=mupo"});
  EXPECT_NE(mupo.find("ensemble.sampling = \"uniform\""), std::string::npos) << mupo;
  const std::string moving = error_of("", {"ensemble.enter_through=0", "leak.omega=2/3"});
  EXPECT_NE(moving.find("needs a stationary leak"), std::string::npos) << moving;
  // written back and read again to the same scene; absent when not given
  const Scene s = parse_scene(two, {"ensemble.enter_through=1"});
  EXPECT_EQ(s.enter_through, 1);
  EXPECT_EQ(parse_scene(scene_to_toml(s)).enter_through, 1);
  EXPECT_EQ(scene_to_toml(parse_scene(two)).find("enter_through"), std::string::npos);
}

TEST(Entry, StartsAreTheBirkhoffMeasureOnTheHole) {
  // Each draw's s lies in the hole's window (its loop's s, mapped back from the whole boundary's share); over 20000
  // draws the offset from the centre in widths, u - 1/2, has mean 0 and variance 1/12 (uniform), and p mean 0 and
  // mean square 1/3 (uniform in (-1, 1)). Error model: the means of 20000 independent draws, 5 standard errors.
  struct Case {
    std::string scene;
    int loop;
    double centre, width;
  };
  const std::vector<Case> cases = {
      {"[leak]\nwidth = \"0.05\"\nstart = \"-0.03\"\n", 0, 0.97, 0.05},
      {"[[leaks]]\nwidth = \"0.02\"\n\n[[leaks]]\nwidth = \"0.1\"\nstart = \"0.3\"\n", 0, 0.3, 0.1},
      {"[table]\nkind = \"annulus\"\nradius = \"1\"\ninner_radius = \"1/4\"\noffset = \"-1/3\"\n\n"
       "[[leaks]]\nwidth = \"0.02\"\n\n[[leaks]]\nloop = 1\nwidth = \"0.2\"\nstart = \"0.95\"\n",
       1, 0.95, 0.2},
  };
  const int n = 20000;
  for (const Case& c : cases) {
    const Scene s = parse_scene(c.scene, {"ensemble.enter_through=" + std::string(c.width == 0.05 ? "0" : "1")});
    const auto sampler = make_sampler(s);
    std::optional<Table<double>> table;
    if (s.table) table.emplace(table_spec(s));
    double su = 0, su2 = 0, sp = 0, sp2 = 0;
    for (int i = 0; i < n; ++i) {
      const InitialDraw d = sampler->draw(static_cast<std::uint64_t>(i));
      const auto [loop, s_loop] = table ? table->loop_s(d.s) : std::pair<int, double>{0, d.s};
      ASSERT_EQ(loop, c.loop) << c.scene;
      double off = s_loop - c.centre;
      off -= std::round(off);  // on the circle s mod 1
      const double u = off / c.width;
      ASSERT_LE(std::abs(u), 0.5 + 1e-9) << c.scene << " draw " << i << " s " << s_loop;
      su += u, su2 += u * u, sp += d.p, sp2 += d.p * d.p;
    }
    EXPECT_LE(std::abs(su / n), 5 * std::sqrt(1.0 / 12 / n)) << c.scene;
    EXPECT_LE(std::abs(su2 / n - 1.0 / 12), 5 * std::sqrt((1.0 / 80 - 1.0 / 144) / n)) << c.scene;
    EXPECT_LE(std::abs(sp / n), 5 * std::sqrt(1.0 / 3 / n)) << c.scene;
    EXPECT_LE(std::abs(sp2 / n - 1.0 / 3), 5 * std::sqrt((1.0 / 5 - 1.0 / 9) / n)) << c.scene;
  }
}

TEST(Entry, TransmissionIsReciprocalAndReflectionsDiffer) {
  // Time reversal maps an entry through A that leaves through B after t onto an entry through B that leaves
  // through A after t, measure for measure (the Birkhoff measure ds dp is reversible): for equal widths the
  // transmitted escapes A -> B and B -> A have one distribution over time. Error model: two independent runs of
  // 100000 particles, each bin's count Poisson; the binned two-sample chi-square within dof + 5 sqrt(2 dof), and
  // the totals within 5 standard errors of their difference. The reflections have no such law: the holes' gaps
  // to the caps differ (0.5 and 1.1), and their time distributions must differ (chi-square > dof + 10 sqrt(2 dof))
  // -- the check that the test can see a difference at this size.
  const Scene a = parse_scene(kTwoHoles, {"ensemble.enter_through=0", "ensemble.particles=100000"});
  // another seed: with the same draws the two runs are not independent (the A-B gap is symmetric under the half
  // turn about its middle, which maps an entry at A's edge onto one at B's with the same draw)
  const Scene b = parse_scene(kTwoHoles, {"ensemble.enter_through=1", "ensemble.particles=100000", "ensemble.seed=2"});
  const RunResult ra = run_ensemble(a, RunOptions{}), rb = run_ensemble(b, RunOptions{});
  const std::vector<std::uint64_t> ab = through(ra.tally, 1), ba = through(rb.tally, 0);
  const auto [chi2, dof] = two_sample_chi2(ab, ba);
  ASSERT_GT(dof, 20);
  EXPECT_LE(chi2, dof + 5 * std::sqrt(2.0 * dof))
      << "transmission A->B vs B->A over time: chi2 " << chi2 << ", dof " << dof;
  const double n_ab = static_cast<double>(ra.tally.leak_escaped(1)),
               n_ba = static_cast<double>(rb.tally.leak_escaped(0));
  EXPECT_LE(std::abs(n_ab - n_ba), 5 * std::sqrt(n_ab * (1 - n_ab / 1e5) + n_ba * (1 - n_ba / 1e5)))
      << n_ab << " vs " << n_ba;
  const auto [chi2_r, dof_r] = two_sample_chi2(through(ra.tally, 0), through(rb.tally, 1));
  EXPECT_GT(chi2_r, dof_r + 10 * std::sqrt(2.0 * dof_r))
      << "reflections at A and B: chi2 " << chi2_r << ", dof " << dof_r;
}

TEST(Entry, EscapeRecordsNameTheirLeakOnEveryEngineAndInTheTallyFile) {
  // entries through A of the two-hole stadium with escape records: each escaped record's leak agrees with the
  // per-leak tallies (as many records name leak j as leak j's escapes), on the scalar engine and the vectorised
  // one alike (the same bytes of escapes.csv, now with its leak column), and a tally file keeps the leaks; a fate
  // word naming a leak the run does not have is refused.
  Scene s = parse_scene(kTwoHoles, {"ensemble.enter_through=0", "ensemble.particles=20000", "observe.escapes=true"});
  RunOptions scalar;
  scalar.engine = Engine::scalar;
  const RunResult a = run_ensemble(s, scalar), b = run_ensemble(s, RunOptions{});
  std::uint64_t named[2] = {0, 0};
  for (const EscapeRecord& e : a.records)
    if (e.fate == Fate::escaped) ++named[e.leak];
  EXPECT_EQ(named[0], a.tally.leak_escaped(0));
  EXPECT_EQ(named[1], a.tally.leak_escaped(1));
  EXPECT_GT(named[0], 1000u);
  EXPECT_GT(named[1], 1000u);
  const std::string csv = escapes_csv(0, a.records, true);
  EXPECT_EQ(csv.rfind("id,fate,t,s,collisions,leak\n", 0), 0u);
  EXPECT_EQ(csv, escapes_csv(0, b.records, true));
  TallyFile f{simulation_inputs(s, "scalar"), s.particles, 0, s.particles, a.done, a.tally, a.records};
  const std::string bytes = encode_tally_file(f);
  const TallyFile back = decode_tally_file(bytes, "mem");
  EXPECT_EQ(escapes_csv(0, back.records, true), csv);
  f.records[0].leak = 2;  // the run has leaks 0 and 1
  EXPECT_THROW(decode_tally_file(encode_tally_file(f), "mem"), std::runtime_error);
  // a header of leak bins but no survival bins, behind a valid checksum, is refused and not divided by (the header
  // and its length prefix edited as in TallyFile.RoundTripsBitForBitAndRefusesDamage)
  const std::string body = bytes.substr(0, bytes.size() - 8);
  const std::size_t magic = body.find('\n') + 1, nl = body.find('\n', magic);
  std::string header = body.substr(nl + 1, std::stoull(body.substr(magic, nl - magic)));
  const std::string rest = body.substr(nl + 1 + header.size());
  const std::size_t at = header.find("\"survival_bins\":");
  ASSERT_NE(at, std::string::npos);
  header.replace(at, 16, "\"survival_bins\":0,\"x\":");
  const std::string edited = body.substr(0, magic) + std::to_string(header.size()) + "\n" + header + rest;
  try {
    decode_tally_file(sealed_tally_bytes(edited), "mem");
    ADD_FAILURE() << "accepted leak bins without survival bins";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("leak_bins"), std::string::npos) << e.what();
  }
}
