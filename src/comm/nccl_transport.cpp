// The NCCL transport: ncclSend/ncclRecv in one group on unisph's CUDA stream. Compiled only
// where the CUDA backend, MPI and NCCL are built (UNISPH_HAS_NCCL). The communicator is made
// on first use from a unique id that rank 0 creates and MPI_Bcast sends round; the device is
// the one this process's CUDA runtime uses (the caller picks it, e.g. by local rank).

#include <cuda_runtime.h>
#include <nccl.h>

#include <string>

#include "unisph/comm/transport.hpp"
#include "unisph/core/error.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph::comm {

namespace {

void check_nccl(ncclResult_t code, const char* what) {
  if (code == ncclSuccess) return;
  throw Error(std::string("NCCL: ") + what + " failed: " + ncclGetErrorString(code));
}

class Nccl final : public Transport {
 public:
  explicit Nccl(Communicator comm) : Transport(std::move(comm)) {}
  ~Nccl() override {
    if (nccl_) ncclCommDestroy(nccl_);
  }
  TransportKind kind() const override { return TransportKind::nccl; }

  void exchange(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
                std::span<const std::uint64_t> recv_offsets) override {
    post(space, send, send_offsets, recv, recv_offsets, static_cast<cudaStream_t>(cuda::main_stream_handle()));
  }
  // The group on the side stream, after the main stream's packing; finish() puts the main
  // stream after it.
  void begin(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
             std::span<const std::uint64_t> recv_offsets) override {
    post(space, send, send_offsets, recv, recv_offsets, static_cast<cudaStream_t>(cuda::side_stream_handle()));
  }
  // Work queued on the side stream (cuda::SideStreamScope) follows the group already.
  void finish() override {
    if (!cuda::on_side_stream()) cuda::main_wait_side_stream("NCCL transport: receiving");
  }
  bool overlaps() const override { return true; }

 private:
  // The piece for this rank itself is copied on the main stream; the group goes to `stream`
  // (the main one, or the side one after the main stream's work so far).
  void post(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
            std::span<const std::uint64_t> recv_offsets, cudaStream_t stream) {
    if (space != MemorySpace::device)
      throw Error("the NCCL transport moves device buffers; use host_staged for the seq and par policies");
    const int p = comm_.size(), me = comm_.rank();
    if (send_offsets.size() != std::size_t(p) + 1 || recv_offsets.size() != std::size_t(p) + 1)
      throw Error("transport: offsets must have ranks + 1 entries");
    connect();
    const auto* s = static_cast<const char*>(send);
    auto* r = static_cast<char*>(recv);
    const std::uint64_t own = send_offsets[std::size_t(me) + 1] - send_offsets[std::size_t(me)];
    if (own)
      cuda::copy_on_device(r + recv_offsets[std::size_t(me)], s + send_offsets[std::size_t(me)], own,
                           "NCCL transport: own piece");
    if (stream != static_cast<cudaStream_t>(cuda::main_stream_handle())) cuda::side_stream_wait_main("NCCL transport: packing");
    check_nccl(ncclGroupStart(), "ncclGroupStart");
    for (int q = 0; q < p; ++q) {
      if (q == me) continue;
      const std::uint64_t out = send_offsets[std::size_t(q) + 1] - send_offsets[std::size_t(q)];
      const std::uint64_t in = recv_offsets[std::size_t(q) + 1] - recv_offsets[std::size_t(q)];
      if (out) check_nccl(ncclSend(s + send_offsets[std::size_t(q)], out, ncclChar, q, nccl_, stream), "ncclSend");
      if (in) check_nccl(ncclRecv(r + recv_offsets[std::size_t(q)], in, ncclChar, q, nccl_, stream), "ncclRecv");
    }
    check_nccl(ncclGroupEnd(), "ncclGroupEnd");
  }

  void connect() {
    if (nccl_) return;
    ncclUniqueId id{};
    if (comm_.rank() == 0) check_nccl(ncclGetUniqueId(&id), "ncclGetUniqueId");
    comm_.broadcast(&id, sizeof(id), 0);
    check_nccl(ncclCommInitRank(&nccl_, comm_.size(), id, comm_.rank()), "ncclCommInitRank");
  }
  ncclComm_t nccl_ = nullptr;
};

}  // namespace

std::unique_ptr<Transport> make_nccl_transport(const Communicator& comm) { return std::make_unique<Nccl>(comm); }

}  // namespace unisph::comm
