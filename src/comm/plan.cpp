#include "unisph/comm/plan.hpp"

#include <string>

#include "unisph/core/error.hpp"

namespace unisph::comm {

Plan::Plan(const Communicator& comm) : ranks_(comm.size()), rank_(comm.rank()), vars_(std::make_unique<Variables>()) {}

void Plan::set_send_counts(const Communicator& comm, std::span<const std::uint64_t> send_counts) {
  const std::size_t p = std::size_t(ranks_);
  std::string bad;
  if (send_counts.size() != p)
    bad = "communication plan: " + std::to_string(send_counts.size()) + " send counts for " + std::to_string(p) +
          " ranks";
  comm.check_all(bad.empty(), bad);
  send_counts_.assign(send_counts.begin(), send_counts.end());
  send_offsets_.assign(p + 1, 0);
  for (std::size_t r = 0; r < p; ++r) send_offsets_[r + 1] = send_offsets_[r] + send_counts_[r];
}

void Plan::receive_counts(const Communicator& comm) {
  const std::size_t p = std::size_t(ranks_);
  recv_counts_ = comm.alltoall(send_counts_);
  recv_offsets_.assign(p + 1, 0);
  for (std::size_t r = 0; r < p; ++r) recv_offsets_[r + 1] = recv_offsets_[r] + recv_counts_[r];
  import_count_ = recv_offsets_[p];
  vars_->send_offsets.assign(send_offsets_);
  vars_->recv_offsets.assign(recv_offsets_);
}

void Plan::copy_lists_to_host() const {
  if (host_lists_) return;
  export_index_ = vars_->export_index.to_vector();
  export_rank_ = vars_->export_rank.to_vector();
  import_rank_ = vars_->import_rank.to_vector();
  host_lists_ = true;
}

Plan::Plan(const Communicator& comm, std::span<const std::uint32_t> export_index, std::span<const int> export_rank)
    : Plan(comm) {
  if (export_index.size() != export_rank.size())
    throw Error("communication plan: " + std::to_string(export_index.size()) + " indices but " +
                std::to_string(export_rank.size()) + " destination ranks");
  const std::size_t p = std::size_t(ranks_);
  // Checked on every rank together, so that a bad rank on one stops all of them.
  std::string bad;
  for (std::size_t k = 0; k < export_rank.size() && bad.empty(); ++k)
    if (export_rank[k] < 0 || export_rank[k] >= ranks_)
      bad = "communication plan: item " + std::to_string(export_index[k]) + " is sent to rank " +
            std::to_string(export_rank[k]) + " of " + std::to_string(ranks_);
  comm.check_all(bad.empty(), bad);

  std::vector<std::uint64_t> counts(p, 0);
  for (int r : export_rank) ++counts[std::size_t(r)];
  set_send_counts(comm, counts);
  // Stable counting sort by destination.
  const std::size_t n = export_index.size();
  export_index_.resize(n);
  export_rank_.resize(n);
  export_order_.resize(n);
  std::vector<std::uint64_t> next(send_offsets_.begin(), send_offsets_.end() - 1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t at = next[std::size_t(export_rank[k])]++;
    export_index_[at] = export_index[k];
    export_rank_[at] = export_rank[k];
    export_order_[at] = static_cast<std::uint32_t>(k);
  }
  export_count_ = n;
  receive_counts(comm);
  import_rank_.resize(import_count_);
  for (std::size_t r = 0; r < p; ++r)
    for (std::uint64_t j = recv_offsets_[r]; j < recv_offsets_[r + 1]; ++j) import_rank_[j] = static_cast<int>(r);

  vars_->export_index.assign(export_index_);
  vars_->export_rank.assign(export_rank_);
  vars_->import_rank.assign(import_rank_);
}

}  // namespace unisph::comm
