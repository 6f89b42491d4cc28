#include "run/audit_shared.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "run/pipeline.hpp"

namespace rotleak {

AuditReport audit_shared(const Scene& scene, AuditOptions options, const Team& team) {
  if (team.size() == 1) return audit(scene, options);
  const int rank = team.rank(), ranks = team.size();
  options.work.reports = rank == 0;
  options.work.all = [&team](bool ok) { return team.all(ok); };
  options.work.ensemble = [&team](const Scene& s, const RunOptions& ro) {
    return run_shared(plan_run(s, ro), ro, team);
  };
  options.work.shadows = [&team, rank, ranks](const Scene& s, const std::vector<std::uint64_t>& ids,
                                              const ShadowOptions& so, int threads,
                                              const std::function<void(std::size_t, std::size_t)>& progress) {
    // ids dealt out in turn: the sample lists its strata by cost (survivors, the longest, first), so
    // equal runs of it would load rank 0 with all the long shadows
    std::vector<std::uint64_t> mine;
    for (std::size_t i = static_cast<std::size_t>(rank); i < ids.size(); i += static_cast<std::size_t>(ranks))
      mine.push_back(ids[i]);
    const std::vector<std::string> parts = team.gather(encode_shadows(shadow_many(s, mine, so, threads, progress)));
    std::vector<ShadowResult> runs;
    if (rank != 0) return runs;
    runs.resize(ids.size());
    std::size_t got = 0;
    for (std::size_t r = 0; r < parts.size(); ++r) {
      std::vector<ShadowResult> part = decode_shadows(parts[r], "rank " + std::to_string(r));
      for (std::size_t j = 0; j < part.size(); ++j) {
        const std::size_t i = r + j * static_cast<std::size_t>(ranks);
        if (i >= ids.size() || part[j].id != ids[i])
          throw std::logic_error("rank " + std::to_string(r) + " sent the shadow of another particle");
        runs[i] = std::move(part[j]);
      }
      got += part.size();
    }
    if (got != ids.size())
      throw std::logic_error("the ranks sent " + std::to_string(got) + " shadows of " + std::to_string(ids.size()));
    return runs;
  };
  AuditReport report = audit(scene, options);
  if (rank == 0) report.ranks = ranks;
  return report;
}

}  // namespace rotleak
