// A run's exact tallies in a file: the checkpoint of an unfinished run (DIR.checkpoint), the tallies
// of a shard (DIR/tally.bin) that `rotleak merge` combines, and what MPI ranks send to rank 0. One
// format for all three, so what one writes the others read.
//
// Layout: the line "rotleak-tallies 4" (4: a split run's sums of Y w0 added), the header's length in bytes and a
// newline, the header (JSON: the run's inputs as text, its ids, block size, the blocks done, the array sizes; a
// checkpoint's also the seconds spent so far), then the arrays as little-endian 64-bit words (counts; each exact sum as
// its lowest limb's index, its limb count and its limbs; escape records: t, s, collisions and the word
// fate + 256 leak), then an FNV-1a 64 checksum of everything
// before it. The counts are integers and the sums fixed-point integers, so a tally read back merges to the same bits as
// the one written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/engine/engine.hpp"
#include "sim/tally/blocks.hpp"

namespace rotleak {

struct TallyFile {
  std::string inputs;           ///< simulation_inputs() of the whole run (tier and engine resolved)
  std::uint64_t particles = 0;  ///< ids run: [first_id, first_id + particles)
  std::uint64_t first_id = 0;
  std::uint64_t of = 0;  ///< the whole run's particle count (a shard's differs from particles)
  IntervalSet done;      ///< blocks (of kBlockSize ids from first_id) whose particles are in the tally
  Tally tally;
  std::vector<EscapeRecord> records;  ///< by id - first_id; entries of blocks not done are zero
  /// Checkpoints only: the seconds the run has spent on the blocks done, across resumes (0: not kept;
  /// a resumed run's execution.wall_seconds adds it, so its rate counts the whole run's time).
  double wall_seconds = 0;

  bool complete() const { return done == IntervalSet::range(0, block_count(particles)); }
};

std::string encode_tally_file(const TallyFile& f);
/// `body` followed by the checksum a tally file ends with (encode_tally_file's last step). A fuzzer seals
/// the contents it mutates, so that they reach the checks behind the checksum.
std::string sealed_tally_bytes(std::string body);
/// Throws std::runtime_error naming `where` on a damaged or foreign file.
TallyFile decode_tally_file(const std::string& bytes, const std::string& where);

/// Atomically (a temporary name, then rename).
void write_tally_file(const std::filesystem::path& path, const TallyFile& f);
TallyFile read_tally_file(const std::filesystem::path& path);

/// The first line where two inputs texts differ, as "KEY: A vs B" (for the error that refuses a
/// resume or a merge); empty when equal.
std::string inputs_difference(const std::string& a, const std::string& b);

}  // namespace rotleak
