#include "run/team.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>

#ifdef ROTLEAK_HAVE_MPI
#include <mpi.h>
#endif

namespace rotleak {

namespace {

const Team kSolo;
const Team* g_current = &kSolo;

#ifdef ROTLEAK_HAVE_MPI
/// Whether a launcher (mpirun, srun with PMI) started this process: only then is MPI initialised,
/// so a plain `rotleak simulate` never touches it.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

class MpiTeam final : public Team {
 public:
  MpiTeam(int* argc, char*** argv) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);  // OpenMP threads never call MPI
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm node;  // the ranks that share this machine's memory (and its GPUs)
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &node_rank_);
    MPI_Comm_free(&node);
  }
  ~MpiTeam() override {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int node_rank() const override { return node_rank_; }
  bool all(bool ok) const override {
    int in = ok ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return out != 0;
  }
  std::vector<std::string> gather(const std::string& bytes) const override {
    // sizes first (64-bit: a tally can pass 2 GiB), then each rank's bytes to rank 0 in pieces
    const auto mine = static_cast<unsigned long long>(bytes.size());
    std::vector<unsigned long long> sizes(static_cast<std::size_t>(size_));
    MPI_Gather(&mine, 1, MPI_UNSIGNED_LONG_LONG, sizes.data(), 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    if (rank_ == 0) {
      out.resize(static_cast<std::size_t>(size_));
      out[0] = bytes;
      for (int r = 1; r < size_; ++r) {
        std::string& b = out[static_cast<std::size_t>(r)];
        b.resize(sizes[static_cast<std::size_t>(r)]);
        for (std::size_t at = 0; at < b.size(); at += kPiece)
          MPI_Recv(b.data() + at, static_cast<int>(std::min(kPiece, b.size() - at)), MPI_BYTE, r, 7, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE);
      }
    } else {
      for (std::size_t at = 0; at < bytes.size(); at += kPiece)
        MPI_Send(bytes.data() + at, static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, 0, 7,
                 MPI_COMM_WORLD);
    }
    return out;
  }
  void broadcast(std::string& bytes) const override {
    auto size = static_cast<unsigned long long>(bytes.size());
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    bytes.resize(size);
    for (std::size_t at = 0; at < bytes.size(); at += kPiece)
      MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, 0, MPI_COMM_WORLD);
  }
  void abort(int code) const override {
    if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
  }

 private:
  static constexpr std::size_t kPiece = std::size_t{1} << 30;  // MPI counts are int: at most 1 GiB a message
  int rank_ = 0, size_ = 1, node_rank_ = 0;
};
#endif

/// Restores the solo team when the joined one goes.
class Joined final : public Team {
 public:
  explicit Joined(std::unique_ptr<Team> t) : inner_(std::move(t)) { g_current = inner_.get(); }
  ~Joined() override { g_current = &kSolo; }
  int rank() const override { return inner_->rank(); }
  int size() const override { return inner_->size(); }
  int node_rank() const override { return inner_->node_rank(); }
  bool all(bool ok) const override { return inner_->all(ok); }
  std::vector<std::string> gather(const std::string& b) const override { return inner_->gather(b); }
  void broadcast(std::string& b) const override { inner_->broadcast(b); }
  void abort(int code) const override { inner_->abort(code); }

 private:
  std::unique_ptr<Team> inner_;
};

}  // namespace

std::unique_ptr<Team> join_team(int* argc, char*** argv) {
#ifdef ROTLEAK_HAVE_MPI
  if (launched_by_mpi()) return std::make_unique<Joined>(std::make_unique<MpiTeam>(argc, argv));
#else
  (void)argc;
  (void)argv;
#endif
  return std::make_unique<Joined>(std::make_unique<Team>());
}

const Team& current_team() { return *g_current; }

void agree(const Team& team, const std::exception_ptr& failure) {
  if (team.size() == 1) {
    if (failure) std::rethrow_exception(failure);
    return;
  }
  const bool zero_ok = team.all(team.rank() != 0 || !failure);
  const bool all_ok = team.all(!failure);
  if (zero_ok && all_ok) return;
  if (failure && team.rank() == 0) std::rethrow_exception(failure);
  if (failure && zero_ok) {  // this rank's own trouble: it says so (the command line prints rank 0's errors only)
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rotleak: rank %d: error: %s\n", team.rank(), e.what());
    }
  }
  throw QuietExit(2);
}

bool built_with_mpi() {
#ifdef ROTLEAK_HAVE_MPI
  return true;
#else
  return false;
#endif
}

}  // namespace rotleak
