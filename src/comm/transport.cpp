// The host-staged and CUDA-aware-MPI transports, and the choice among transports.

#include "unisph/comm/transport.hpp"

#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

#if UNISPH_HAS_MPI
#include <mpi.h>
#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>
#endif
#endif

namespace unisph::comm {

#if UNISPH_HAS_NCCL
// src/comm/nccl_transport.cpp
std::unique_ptr<Transport> make_nccl_transport(const Communicator& comm);
#endif

std::string_view to_string(TransportKind kind) {
  switch (kind) {
    case TransportKind::host_staged:
      return "host_staged";
    case TransportKind::nccl:
      return "nccl";
    case TransportKind::cuda_aware_mpi:
      return "cuda_aware_mpi";
  }
  return "unknown";
}

TransportKind parse_transport(std::string_view name) {
  for (TransportKind k : {TransportKind::host_staged, TransportKind::nccl, TransportKind::cuda_aware_mpi})
    if (name == to_string(k)) return k;
  throw Error("unknown transport '" + std::string(name) + "': use host_staged, nccl or cuda_aware_mpi");
}

namespace {
bool mpi_cuda_aware(std::string* reason) {
#if UNISPH_HAS_MPI && defined(MPIX_CUDA_AWARE_SUPPORT)
  if (MPIX_Query_cuda_support() == 1) return true;
  if (reason) *reason = "MPIX_Query_cuda_support() says this MPI library cannot take device pointers";
  return false;
#elif UNISPH_HAS_MPI
  if (reason) *reason = "this MPI library has no MPIX_Query_cuda_support() to say it takes device pointers";
  return false;
#else
  if (reason) *reason = "unisph was built without MPI";
  return false;
#endif
}
}  // namespace

bool transport_available(TransportKind kind, std::string* reason) {
  switch (kind) {
    case TransportKind::host_staged:
      return true;
    case TransportKind::nccl:
#if UNISPH_HAS_NCCL
      return true;
#else
      if (reason) *reason = "unisph was built without NCCL (it needs the CUDA backend, MPI, nccl.h and libnccl.so.2)";
      return false;
#endif
    case TransportKind::cuda_aware_mpi:
      if (!UNISPH_HAS_CUDA) {
        if (reason) *reason = "unisph was built without CUDA";
        return false;
      }
      return mpi_cuda_aware(reason);
  }
  return false;
}

TransportKind default_transport(MemorySpace space) {
  if (space == MemorySpace::device && transport_available(TransportKind::nccl)) return TransportKind::nccl;
  return TransportKind::host_staged;
}

namespace {

std::vector<Communicator::Segment> segments(void* base, std::span<const std::uint64_t> offsets) {
  std::vector<Communicator::Segment> s(offsets.size() - 1);
  for (std::size_t r = 0; r + 1 < offsets.size(); ++r)
    s[r] = {static_cast<char*>(base) + offsets[r], static_cast<std::size_t>(offsets[r + 1] - offsets[r])};
  return s;
}

void check_offsets(const Communicator& comm, std::span<const std::uint64_t> send, std::span<const std::uint64_t> recv) {
  if (send.size() != std::size_t(comm.size()) + 1 || recv.size() != std::size_t(comm.size()) + 1)
    throw Error("transport: offsets must have ranks + 1 = " + std::to_string(comm.size() + 1) + " entries");
}

class HostStaged final : public Transport {
 public:
  explicit HostStaged(Communicator comm) : Transport(std::move(comm)) {}
  TransportKind kind() const override { return TransportKind::host_staged; }
  void exchange(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
                std::span<const std::uint64_t> recv_offsets) override {
    check_offsets(comm_, send_offsets, recv_offsets);
    const std::size_t send_bytes = send_offsets.back(), recv_bytes = recv_offsets.back();
    if (space == MemorySpace::host) {
      comm_.exchange(segments(const_cast<void*>(send), send_offsets), segments(recv, recv_offsets));
      return;
    }
    send_stage_.resize(send_bytes);
    recv_stage_.resize(recv_bytes);
    if (send_bytes) cuda::copy_to_host(send_stage_.data(), send, send_bytes, "host-staged transport: send buffer");
    comm_.exchange(segments(send_stage_.data(), send_offsets), segments(recv_stage_.data(), recv_offsets));
    if (recv_bytes)
      cuda::copy_to_device(recv, recv_stage_.data(), recv_bytes, "host-staged transport: receive buffer");
  }

 private:
  std::vector<unsigned char> send_stage_, recv_stage_;
};

#if UNISPH_HAS_MPI
// Device pointers straight to MPI (only where the library says it takes them).
class CudaAwareMpi final : public Transport {
 public:
  explicit CudaAwareMpi(Communicator comm) : Transport(std::move(comm)) {}
  TransportKind kind() const override { return TransportKind::cuda_aware_mpi; }
  void exchange(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
                std::span<const std::uint64_t> recv_offsets) override {
    check_offsets(comm_, send_offsets, recv_offsets);
    // MPI reads the device buffer as soon as it is called: the packing kernels must be done.
    if (space == MemorySpace::device) cuda::synchronize("CUDA-aware MPI transport: packing");
    std::vector<Communicator::Segment> s = segments(const_cast<void*>(send), send_offsets);
    std::vector<Communicator::Segment> r = segments(recv, recv_offsets);
    // The piece for this rank itself: a copy in its own space.
    const std::size_t me = std::size_t(comm_.rank());
    if (space == MemorySpace::device && s[me].bytes) {
      cuda::copy_on_device(r[me].data, s[me].data, s[me].bytes, "CUDA-aware MPI transport: own piece");
      cuda::synchronize("CUDA-aware MPI transport: own piece");
    }
    if (space == MemorySpace::device) s[me].bytes = r[me].bytes = 0;
    comm_.exchange(s, r);
  }
};
#endif

}  // namespace

std::unique_ptr<Transport> make_transport(TransportKind kind, const Communicator& comm) {
  std::string reason;
  if (!transport_available(kind, &reason))
    throw Error("transport " + std::string(to_string(kind)) + " is not available: " + reason);
  switch (kind) {
    case TransportKind::host_staged:
      return std::make_unique<HostStaged>(comm);
    case TransportKind::nccl:
#if UNISPH_HAS_NCCL
      return make_nccl_transport(comm);
#else
      break;
#endif
    case TransportKind::cuda_aware_mpi:
#if UNISPH_HAS_MPI
      return std::make_unique<CudaAwareMpi>(comm);
#else
      break;
#endif
  }
  throw Error("transport " + std::string(to_string(kind)) + " is not available");
}

}  // namespace unisph::comm
