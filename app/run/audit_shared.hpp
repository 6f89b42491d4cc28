// The audit of a scene by the ranks of an MPI job (`mpirun -np K rotleak audit ...`): its ensembles
// (the stratification scan, the float/double/long double/vectorised statistics ensembles) split by
// blocks as a run is, the shadows split by particle, and the report made once, on rank 0, from
// exactly what one process would have had.
#pragma once

#include "run/team.hpp"
#include "verify/audit.hpp"

namespace rotleak {

/// Collective: every rank of `team` calls it with the same scene and options. Rank 0 returns the
/// report audit(scene, options) gives in one process (timings aside); the other ranks an empty one.
/// A team of one: audit() itself.
AuditReport audit_shared(const Scene& scene, AuditOptions options, const Team& team);

}  // namespace rotleak
