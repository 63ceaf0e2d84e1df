#pragma once
// Transports move the packed bytes of a plan between ranks. Chosen at run time and named:
//   host_staged     the bytes go through host memory and MPI_Isend/MPI_Irecv; device buffers
//                   are copied to a host buffer first and back after (pageable host memory for
//                   now); host buffers (seq, par) go to MPI directly. Works everywhere.
//   nccl            ncclSend/ncclRecv in one group on unisph's CUDA stream, device buffers
//                   only; the NCCL unique id is sent round with MPI_Bcast. Built where CUDA
//                   and NCCL are (UNISPH_HAS_NCCL). Its split form (begin/finish) runs the
//                   group on the side stream, beside the main stream's work.
//   cuda_aware_mpi  device pointers handed to MPI directly; offered only where
//                   MPIX_Query_cuda_support() says the MPI library supports it (Debian's Open
//                   MPI does not: handing it a device pointer crashes).
// Without MPI, host_staged exists for the serial communicator (a copy to itself).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "unisph/comm/communicator.hpp"
#include "unisph/memory/space.hpp"

namespace unisph::comm {

enum class TransportKind { host_staged, nccl, cuda_aware_mpi };

std::string_view to_string(TransportKind kind);
// Parses "host_staged", "nccl" or "cuda_aware_mpi".
TransportKind parse_transport(std::string_view name);

// Whether `kind` can run in this build and with this MPI library; `reason` says why not.
bool transport_available(TransportKind kind, std::string* reason = nullptr);

// nccl for device memory where available, host_staged otherwise.
TransportKind default_transport(MemorySpace space);

class Transport {
 public:
  virtual ~Transport() = default;
  virtual TransportKind kind() const = 0;
  std::string_view name() const { return to_string(kind()); }
  const Communicator& communicator() const { return comm_; }

  // Collective among the ranks that exchange. Both buffers live in `space`. Rank r's bytes
  // are send[send_offsets[r], send_offsets[r + 1]) and arrive in recv[recv_offsets[r],
  // recv_offsets[r + 1]) there (the offsets are byte offsets, size() + 1 each, agreed by the
  // plan; the piece for this rank itself is copied). On return the received bytes are usable
  // by later work in `space` (for the device: in the order of unisph's stream).
  virtual void exchange(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
                        std::span<const std::uint64_t> recv_offsets) = 0;

  // The same exchange split in two, so that work reading neither buffer runs in between (the
  // interior particles' interactions while a halo's bytes move): begin() starts it; until
  // finish() the send buffer must not change and the receive buffer is not yet usable; after
  // finish() the received bytes are usable as after exchange(). No other exchange may come in
  // between. Transports that cannot overlap do the whole exchange in begin() (overlaps():
  // false): host_staged and cuda_aware_mpi.
  virtual void begin(MemorySpace space, const void* send, std::span<const std::uint64_t> send_offsets, void* recv,
                     std::span<const std::uint64_t> recv_offsets) {
    exchange(space, send, send_offsets, recv, recv_offsets);
  }
  virtual void finish() {}
  virtual bool overlaps() const { return false; }

 protected:
  explicit Transport(Communicator comm) : comm_(std::move(comm)) {}
  Communicator comm_;
};

// Throws unisph::Error naming the reason when `kind` is not available.
std::unique_ptr<Transport> make_transport(TransportKind kind, const Communicator& comm);

}  // namespace unisph::comm
