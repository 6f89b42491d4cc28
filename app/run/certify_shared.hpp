// A certified sample shared by MPI ranks: rank k certifies the ids i with i % ranks == k (long and short
// lives interleave, so the shares cost alike), rank 0 gathers the certificates (as checkpoint records, times
// exactly), runs the point tiers and returns the sample; the others return an empty one. A team of one is
// certify_sample itself. The certificates, and so the files, are the single process's.
#pragma once

#include "run/team.hpp"
#include "verify/certify_sample.hpp"

namespace rotleak {

SampleCertificate certify_shared(const Scene& scene, SampleOptions opt, const Team& team);

}  // namespace rotleak
