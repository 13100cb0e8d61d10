#include "study/slab_ranks.hpp"

#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "output/output_path.hpp"
#include "study/ranks.hpp"

#include "study/mpi_api.hpp"

namespace gdsmc::host::job {

namespace {

#ifdef GDSMC_WITH_MPI
void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("--decompose: ") + what + " failed (MPI error " + std::to_string(code) + ")");
}
int as_int(std::size_t n, const char* what) {
  if (n > 0x7FFFFFFFu) throw std::runtime_error(std::string("--decompose: ") + what + ": more than 2^31 - 1 items in one message");
  return static_cast<int>(n);
}
#endif

class SlabRanks final : public Decomposition {
 public:
  SlabRanks() {
    rank_ = job::rank();
    size_ = job::size();
#ifdef GDSMC_WITH_MPI
    if (size_ > 1) {
      check(MPI_Type_contiguous(static_cast<int>(sizeof(Migrant)), MPI_BYTE, &migrant_), "MPI_Type_contiguous");
      check(MPI_Type_commit(&migrant_), "MPI_Type_commit");
    }
#endif
  }
  ~SlabRanks() override {
#ifdef GDSMC_WITH_MPI
    if (size_ > 1) MPI_Type_free(&migrant_);
#endif
  }

  void share(double* values, std::size_t per_layer) const override {
    if (size_ == 1) return;
#ifdef GDSMC_WITH_MPI
    const auto& b = bounds();
    counts_.resize(static_cast<std::size_t>(size_));
    displs_.resize(static_cast<std::size_t>(size_));
    for (std::size_t r = 0; r < counts_.size(); ++r) {
      counts_[r] = as_int((b[r + 1] - b[r]) * per_layer, "share");
      displs_[r] = as_int(b[r] * per_layer, "share");
    }
    check(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, values, counts_.data(), displs_.data(), MPI_DOUBLE,
                         MPI_COMM_WORLD), "MPI_Allgatherv (layers)");
#endif
  }
  void sum(std::uint64_t* values, std::size_t n) const override {
    if (size_ == 1) return;
#ifdef GDSMC_WITH_MPI
    check(MPI_Allreduce(MPI_IN_PLACE, values, as_int(n, "sum"), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
#endif
  }
  void all_blocks(const void* mine, std::size_t bytes, void* all) const override {
    if (size_ == 1) {
      std::memcpy(all, mine, bytes);
      return;
    }
#ifdef GDSMC_WITH_MPI
    check(MPI_Allgather(mine, as_int(bytes, "all_blocks"), MPI_BYTE, all, static_cast<int>(bytes), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgather");
#endif
  }
  void broadcast(void* data, std::size_t bytes) const override {
    if (size_ == 1) return;
#ifdef GDSMC_WITH_MPI
    check(MPI_Bcast(data, as_int(bytes, "broadcast"), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast");
#endif
  }
  void exchange(const std::vector<std::vector<Migrant>>& outgoing, std::vector<Migrant>& incoming) const override {
    incoming.clear();
    if (size_ == 1) return;
#ifdef GDSMC_WITH_MPI
    const auto n = static_cast<std::size_t>(size_);
    send_counts_.assign(n, 0);
    send_displs_.assign(n, 0);
    send_.clear();
    for (std::size_t r = 0; r < n; ++r) {
      send_displs_[r] = as_int(send_.size(), "exchange");
      send_counts_[r] = as_int(outgoing[r].size(), "exchange");
      send_.insert(send_.end(), outgoing[r].begin(), outgoing[r].end());
    }
    counts_.assign(n, 0);
    check(MPI_Alltoall(send_counts_.data(), 1, MPI_INT, counts_.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
    displs_.assign(n, 0);
    std::size_t total = 0;
    for (std::size_t r = 0; r < n; ++r) {
      displs_[r] = as_int(total, "exchange");
      total += static_cast<std::size_t>(counts_[r]);
    }
    incoming.resize(total);
    check(MPI_Alltoallv(send_.data(), send_counts_.data(), send_displs_.data(), migrant_, incoming.data(), counts_.data(),
                        displs_.data(), migrant_, MPI_COMM_WORLD), "MPI_Alltoallv (migration)");
#endif
  }
  void gather(const std::vector<Migrant>& mine, std::vector<Migrant>& all, std::vector<std::size_t>& counts) const override {
    counts.assign(static_cast<std::size_t>(size_), 0);
    if (size_ == 1) {
      all = mine;
      counts[0] = mine.size();
      return;
    }
#ifdef GDSMC_WITH_MPI
    int count = as_int(mine.size(), "gather");
    counts_.assign(static_cast<std::size_t>(size_), 0);
    check(MPI_Gather(&count, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    displs_.assign(static_cast<std::size_t>(size_), 0);
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts_.size(); ++r) {
      displs_[r] = as_int(total, "gather");
      total += static_cast<std::size_t>(counts_[r]);
      counts[r] = static_cast<std::size_t>(counts_[r]);
    }
    counts[static_cast<std::size_t>(rank_)] = mine.size();  // MPI_Gather told rank 0 alone
    if (root()) all.resize(total);
    check(MPI_Gatherv(mine.data(), count, migrant_, root() ? all.data() : nullptr, counts_.data(), displs_.data(), migrant_,
                      0, MPI_COMM_WORLD), "MPI_Gatherv (particles)");
#endif
  }
  void scatter(const std::vector<Migrant>& all, const std::vector<std::size_t>& counts, std::vector<Migrant>& mine) const override {
    if (size_ == 1) {
      mine = all;
      return;
    }
#ifdef GDSMC_WITH_MPI
    counts_.assign(static_cast<std::size_t>(size_), 0);
    displs_.assign(static_cast<std::size_t>(size_), 0);
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts_.size(); ++r) {
      counts_[r] = as_int(counts[r], "scatter");
      displs_[r] = as_int(total, "scatter");
      total += counts[r];
    }
    mine.resize(counts[static_cast<std::size_t>(rank_)]);
    check(MPI_Scatterv(root() ? all.data() : nullptr, counts_.data(), displs_.data(), migrant_, mine.data(),
                       as_int(mine.size(), "scatter"), migrant_, 0, MPI_COMM_WORLD), "MPI_Scatterv (particles)");
#endif
  }

 private:
#ifdef GDSMC_WITH_MPI
  MPI_Datatype migrant_ = MPI_DATATYPE_NULL;
#endif
  // Scratch of the collectives, kept between steps (no allocation once they have grown).
  mutable std::vector<int> counts_, displs_, send_counts_, send_displs_;
  mutable std::vector<Migrant> send_;
};

}  // namespace

std::unique_ptr<Decomposition> slab_ranks() { return std::make_unique<SlabRanks>(); }

void abort_job(int status) {
  remove_live_temporaries_from_signal_handler();  // this rank's temporary output and lock (rank 0's)
#ifdef GDSMC_WITH_MPI
  if (job::size() > 1) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

}  // namespace gdsmc::host::job
