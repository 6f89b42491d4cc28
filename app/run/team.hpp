// The processes that share a run: this one alone, or the ranks of an MPI job (`mpirun -np K rotleak
// ...`, when rotleak was built with MPI). The run pipeline speaks to a Team only: rank 0 writes,
// every rank runs its share of the blocks, exact tallies travel as tally files (io/tally_file.hpp).
// No networking of our own: the collectives are MPI's.
#pragma once

#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rotleak {

class Team {
 public:
  virtual ~Team() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// This rank's place among the ranks on its own machine (0 alone): which of the machine's GPUs it takes.
  virtual int node_rank() const { return 0; }
  /// Collective: true on every rank when `ok` is true on every rank.
  virtual bool all(bool ok) const { return ok; }
  /// Collective: on rank 0 every rank's bytes in rank order; elsewhere nothing.
  virtual std::vector<std::string> gather(const std::string& bytes) const { return {bytes}; }
  /// Collective: rank 0's bytes, on every rank (what `bytes` held elsewhere is replaced).
  virtual void broadcast(std::string& /*bytes*/) const {}
  /// Ends the whole job after a failure on one rank (the others may be waiting in a collective).
  virtual void abort(int /*code*/) const {}
};

/// The team of this process: MPI's ranks when it was started by mpirun and built with MPI (MPI is
/// initialised here and finalised when the returned object goes), a team of one otherwise.
std::unique_ptr<Team> join_team(int* argc, char*** argv);
/// The team join_team() made (a team of one before that, and in tests).
const Team& current_team();
/// Whether this build can run under MPI.
bool built_with_mpi();

/// A rank other than 0 ends because rank 0 refused the run (rank 0 prints why): the command exits
/// with `code` and prints nothing.
struct QuietExit : std::runtime_error {
  explicit QuietExit(int c) : std::runtime_error("quiet exit"), code(c) {}
  int code;
};

/// Collective: a failure on any rank ends the command on every rank. Rank 0's own failure is
/// rethrown (the others throw QuietExit); else each failing rank prints its own and all throw QuietExit.
/// A team of one: rethrows `failure`, if any.
void agree(const Team& team, const std::exception_ptr& failure);

}  // namespace rotleak
