#include "rank_reduction.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

namespace contact::petsc::internal {
namespace {

// values[0..count) <- their sum or maximum over the ranks, combined in rank order.
class Combiner {
 public:
  explicit Combiner(MPI_Comm comm) : comm_(comm) { MPI_Comm_size(comm, &ranks_); }

  void Sum(double* values, int count) {
    Gather(values, count);
    for (int i = 0; i < count; ++i) {
      double sum = 0.0;
      for (int r = 0; r < ranks_; ++r) sum += all_[static_cast<size_t>(r * count + i)];
      values[i] = sum;
    }
  }

  // std::max in rank order: a NaN on a rank is kept only where it comes first, the same
  // choice on every rank.
  void Max(double* values, int count) {
    Gather(values, count);
    for (int i = 0; i < count; ++i) {
      double largest = all_[static_cast<size_t>(i)];
      for (int r = 1; r < ranks_; ++r)
        largest = std::max(largest, all_[static_cast<size_t>(r * count + i)]);
      values[i] = largest;
    }
  }

 private:
  void Gather(const double* values, int count) {
    all_.resize(static_cast<size_t>(ranks_) * static_cast<size_t>(count));
    MPI_Allgather(values, count, MPI_DOUBLE, all_.data(), count, MPI_DOUBLE, comm_);
  }

  MPI_Comm comm_;
  int ranks_ = 1;
  std::vector<double> all_;  // every rank's values, rank by rank (kept between calls)
};

}  // namespace

ncp::fc::Reduction RankReduction(MPI_Comm comm) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  ncp::fc::Reduction reduction;
  if (ranks == 1) return reduction;
  auto combiner = std::make_shared<Combiner>(comm);
  reduction.sum = [combiner](double* values, int count) { combiner->Sum(values, count); };
  reduction.max = [combiner](double* values, int count) { combiner->Max(values, count); };
  return reduction;
}

void BroadcastText(MPI_Comm comm, std::string* s) {
  int length = static_cast<int>(s->size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  s->resize(static_cast<size_t>(length));
  MPI_Bcast(s->data(), length, MPI_CHAR, 0, comm);
}

void ThrowFromRankZero(MPI_Comm comm, std::string message) {
  BroadcastText(comm, &message);
  if (!message.empty()) throw std::invalid_argument(message);
}

}  // namespace contact::petsc::internal
