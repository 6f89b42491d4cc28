// The vectorised kernel talks to its caller through plain buffers (simd::Exchange), never a callback, and goes on
// where it stopped (simd::KernelState). How the caller feeds it must change nothing: fed every start at once with
// roomy buffers, or three starts a call with buffers that hold one step's worth (so that it pauses for starts, for
// room for its ends and for room for its counted collisions), each particle's end and the multiset of f_c's
// counted collisions are the same, bit for bit, on the stadium (a moving leak, weighted starts, f_c, hand-backs to
// the fast-forward) and on a table (the mushroom, a moving leak, f_c), for every kernel width this CPU runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "io/scene_file.hpp"
#include "kernel_widths.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/sampling.hpp"

using namespace rotleak;

namespace {

struct Outcome {
  std::vector<simd::End> ends;
  std::vector<simd::DensityHit> hits;
  std::set<simd::Pause> pauses;
};

/// Runs `starts` through the kernel of `ks`, handing it at most `feed` starts a call, with ends and hits buffers of
/// `room` entries; the ends sorted by id, the hits by (cell, bin, weight).
Outcome drive(const simd::KernelScene& ks, const std::vector<simd::Start>& starts, std::size_t feed, std::size_t room) {
  Outcome o;
  auto state = std::make_unique<simd::KernelState>();
  std::vector<simd::End> ends(room);
  std::vector<simd::DensityHit> hits(room);
  std::vector<simd::Start> pending;
  std::size_t given = 0;
  simd::Exchange x;
  x.ends = ends.data(), x.end_capacity = room, x.hits = hits.data(), x.hit_capacity = room;
  for (int calls = 0;; ++calls) {
    if (calls > 1000000) {
      ADD_FAILURE() << "the kernel never went idle";
      break;
    }
    while (pending.size() < feed && given < starts.size()) pending.push_back(starts[given++]);
    x.starts = pending.data(), x.n_starts = pending.size(), x.taken = 0, x.n_ends = 0, x.n_hits = 0;
    x.last = given == starts.size();
    const simd::Pause why = simd::run(ks, *state, x);
    o.pauses.insert(why);
    EXPECT_LE(x.n_ends, room);
    EXPECT_LE(x.n_hits, room);
    pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(x.taken));
    o.ends.insert(o.ends.end(), ends.begin(), ends.begin() + static_cast<std::ptrdiff_t>(x.n_ends));
    o.hits.insert(o.hits.end(), hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(x.n_hits));
    if (why == simd::Pause::idle) break;
  }
  EXPECT_TRUE(pending.empty());
  std::sort(o.ends.begin(), o.ends.end(), [](const simd::End& a, const simd::End& b) { return a.id < b.id; });
  std::sort(o.hits.begin(), o.hits.end(), [](const simd::DensityHit& a, const simd::DensityHit& b) {
    return std::tie(a.cell, a.bin, a.weight) < std::tie(b.cell, b.bin, b.weight);
  });
  return o;
}

/// Two ends are the same bits (every field).
bool same(const simd::End& a, const simd::End& b) {
  return a.fate == b.fate && std::memcmp(&a.t, &b.t, sizeof a.t) == 0 && std::memcmp(&a.qx, &b.qx, sizeof a.qx) == 0 &&
         std::memcmp(&a.qy, &b.qy, sizeof a.qy) == 0 && std::memcmp(&a.vx, &b.vx, sizeof a.vx) == 0 &&
         std::memcmp(&a.vy, &b.vy, sizeof a.vy) == 0 && std::memcmp(&a.weight, &b.weight, sizeof a.weight) == 0 &&
         a.piece == b.piece && a.leak == b.leak && a.collisions == b.collisions && a.id == b.id;
}

/// Runs the starts both ways and compares; `want_handback`: some lane must be handed back.
void check(const simd::KernelScene& ks, const std::vector<simd::Start>& starts, bool want_handback) {
  const Outcome roomy = drive(ks, starts, starts.size(), 1 << 20);
  const auto lanes = static_cast<std::size_t>(simd::pack_lanes(ks.lanes));
  const Outcome tight = drive(ks, starts, 3, lanes);
  ASSERT_EQ(roomy.ends.size(), starts.size()) << ks.lanes << " lanes";
  ASSERT_EQ(tight.ends.size(), starts.size());
  std::size_t handed = 0, escaped = 0, differ = 0, first = 0;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    ASSERT_EQ(roomy.ends[i].id, starts[i].id);
    if (!same(roomy.ends[i], tight.ends[i]) && differ++ == 0) first = i;
    handed += roomy.ends[i].fate == LaneEnd::handed_back;
    escaped += roomy.ends[i].fate == LaneEnd::escaped;
  }
  EXPECT_EQ(differ, 0u) << "particles whose end differs, the first " << starts[first].id << ", " << ks.lanes
                        << " lanes";
  EXPECT_GT(escaped, starts.size() / 10);
  if (want_handback) {
    EXPECT_GT(handed, 0u);
  }
  ASSERT_GT(roomy.hits.size(), 10 * lanes);  // f_c counted many collisions
  ASSERT_EQ(roomy.hits.size(), tight.hits.size());
  std::size_t hits_differ = 0;
  for (std::size_t i = 0; i < roomy.hits.size(); ++i) {
    const simd::DensityHit &a = roomy.hits[i], &b = tight.hits[i];
    hits_differ += !(a.cell == b.cell && a.bin == b.bin && a.weight == b.weight);
  }
  EXPECT_EQ(hits_differ, 0u);
  // the tight feed paused for each reason; the roomy one only to finish
  EXPECT_EQ(tight.pauses,
            (std::set<simd::Pause>{simd::Pause::starts, simd::Pause::ends, simd::Pause::hits, simd::Pause::idle}));
  EXPECT_EQ(roomy.pauses, std::set<simd::Pause>{simd::Pause::idle});
}

}  // namespace

TEST(KernelExchange, TheStadiumsEndsDoNotDependOnHowTheKernelIsFed) {
  Scene s = parse_scene(
      "[leak]\nwidth = \"0.05\"\nstart = \"0.1\"\nomega = \"2/3\"\n[ensemble]\nparticles = 3000\nseed = 7\n"
      "sampling = \"mupo\"\n[run]\nt_max = 400\n[observe]\ncollision_density = { bins = 50, windows = [[0, 400], "
      "[100, 300]] }\n[fit]\nkappa_window = [0, 100]\n");
  const Model<double> model = Model<double>::from(s);
  const std::unique_ptr<Sampler> sampler = make_sampler(s);
  for (int lanes : test::kernel_widths()) {
    simd::KernelScene ks = simd_scene(model);
    ks.lanes = lanes;
    ks.handoff_bounces = 16;  // hand long bouncing-ball phases back (mupo starts many)
    simd_density(ks, s);
    std::vector<simd::Start> starts(s.particles);
    draw_starts(DrawSource{sampler.get(), 0, nullptr}, ks, true, 0, starts.size(), starts.data());
    for (std::size_t i = 0; i < starts.size(); ++i) starts[i].id = 1000 + i;
    check(ks, starts, true);
  }
}

TEST(KernelExchange, ATablesEndsDoNotDependOnHowTheKernelIsFed) {
  const Scene s = parse_scene(
      "[table]\nkind = \"mushroom\"\nradius = \"1\"\nstem_width = \"0.5\"\nstem_height = \"1\"\n[leak]\n"
      "width = \"0.05\"\nstart = \"0.3\"\nomega = \"1/3\"\n[ensemble]\nparticles = 2000\nseed = 3\n[run]\nt_max = "
      "300\n[observe]\ncollision_density = { bins = 40, windows = [[0, 300]] }\n[fit]\nkappa_window = [0, 100]\n");
  const TableModel<double> model(table_spec(s), leak_specs(s), s.t_max);
  const std::unique_ptr<Sampler> sampler = make_sampler(s);
  const DrawSource draw{sampler.get(), 0, nullptr};
  for (int lanes : test::kernel_widths()) {
    auto numbers = std::make_unique<simd::KernelTable>();
    kernel_table(model, *numbers);
    simd::KernelScene ks = simd_scene(model, *numbers);
    ks.lanes = lanes;
    simd_density(ks, s);
    std::vector<simd::Start> starts(s.particles);
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const ParticleState<double> ps = initial_state(model.table, draw(i));
      starts[i] = {ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, 0, 1.0, i};
    }
    check(ks, starts, false);
  }
}
