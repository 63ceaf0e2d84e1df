#pragma once
// Moving variables along a plan: packing and unpacking as kernels on the policy's memory, one
// buffer and one transport exchange for all the variables together.
//
// Buffer layout: the bytes for rank r form one block, blocks in rank order; inside a block one
// segment per variable, in the order the variables are given, each holding that rank's items
// in plan order and padded to a multiple of 4 bytes (so that the kernels copy 4-byte words
// wherever the element size allows). Both sides compute the same layout from the plan's counts.
//
// Sources that call these templates launch kernels: list them in unisph_kernel_sources().

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "unisph/comm/plan.hpp"
#include "unisph/comm/transport.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/variable_base.hpp"

namespace unisph::comm {

namespace exchange_detail {

// Send item k: element index[k] of `src` to its place in the block of rank rank[k].
template <class Word>
struct PackElements {
  View<const std::uint32_t> index;
  View<const std::int32_t> rank;
  View<const std::uint64_t> item_offset;     // first send item of each rank (ranks + 1)
  View<const std::uint64_t> segment_offset;  // byte offset of this variable's segment per rank
  const Word* src;
  unsigned char* buffer;
  Index words;  // per element
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    const int r = rank[k];
    const Word* from = src + static_cast<Index>(index[k]) * words;
    Word* to = reinterpret_cast<Word*>(buffer + segment_offset[r]) + (k - item_offset[r]) * words;
    for (Index w = 0; w < words; ++w) to[w] = from[w];
  }
};

// The same for a position: the copy is shifted by the item's periodic image. Written in 4-byte
// words: segments are aligned to 4 bytes only (a segment after a 1-byte variable's), and a
// store of a double there is a misaligned address on the GPU (seen on H100s: the periodic halo
// tests, whose ranks send to themselves and to others, stopped with cudaErrorMisalignedAddress).
template <class T>
struct PackShifted {
  static_assert(sizeof(T) % 4 == 0, "A shifted position is packed in 4-byte words: its size must be a multiple of 4.");
  View<const std::uint32_t> index;
  View<const std::int32_t> rank;
  View<const std::uint64_t> item_offset;
  View<const std::uint64_t> segment_offset;
  View<const T> shift;  // per send item
  const T* src;
  unsigned char* buffer;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    constexpr Index words = sizeof(T) / 4;
    const int r = rank[k];
    T value = src[index[k]];
    value += shift[k];
    std::uint32_t w[words];
    memcpy(w, &value, sizeof(T));
    std::uint32_t* to = reinterpret_cast<std::uint32_t*>(buffer + segment_offset[r]) + (k - item_offset[r]) * words;
    for (Index i = 0; i < words; ++i) to[i] = w[i];
  }
};

// Received item j to element j of `dst` (dst points at the first received slot).
template <class Word>
struct UnpackElements {
  View<const std::int32_t> rank;
  View<const std::uint64_t> item_offset;
  View<const std::uint64_t> segment_offset;
  const unsigned char* buffer;
  Word* dst;
  Index words;
  UNISPH_HOST_DEVICE void operator()(Index j) const {
    const int r = rank[j];
    const Word* from = reinterpret_cast<const Word*>(buffer + segment_offset[r]) + (j - item_offset[r]) * words;
    Word* to = dst + j * words;
    for (Index w = 0; w < words; ++w) to[w] = from[w];
  }
};

inline std::uint64_t padded(std::uint64_t bytes) { return (bytes + 3) / 4 * 4; }

// Byte offsets: segment[v * ranks + r] for variable v in rank r's block, and the blocks'
// exclusive scan (ranks + 1).
struct Layout {
  std::vector<std::uint64_t> segment;
  std::vector<std::uint64_t> block;
};
inline Layout layout(std::span<const std::uint64_t> counts, std::span<const std::size_t> element_sizes) {
  const std::size_t p = counts.size(), nv = element_sizes.size();
  Layout l{std::vector<std::uint64_t>(nv * p), std::vector<std::uint64_t>(p + 1, 0)};
  for (std::size_t r = 0; r < p; ++r) {
    std::uint64_t at = l.block[r];
    for (std::size_t v = 0; v < nv; ++v) {
      l.segment[v * p + r] = at;
      at += padded(counts[r] * element_sizes[v]);
    }
    l.block[r + 1] = at;
  }
  return l;
}

}  // namespace exchange_detail

// Moves variables along a plan. Reusable: the buffers and layout tables grow as needed, and the
// layout tables reach the device only when they change (a halo's refreshes send the same
// variables along the same plan many times per step).
class VariableExchange {
 public:
  // Packs element plan.export_index()[k] of each variable, exchanges, and unpacks the received
  // items into elements [first_slot, first_slot + plan.import_count()) of the same variables
  // (which must be that large by then: `before_unpack()` runs between exchange and unpacking,
  // e.g. to resize them). `pack_override(v, policy, index, rank, items, segment, src, buffer)`
  // packs variable v itself and returns true where the plain copy will not do (halo
  // positions: shifted by their periodic image).
  template <ExecutionPolicy P, class BeforeUnpack, class PackOverride>
  void run(P policy, const Plan& plan, Transport& transport, std::span<VariableBase* const> variables,
           Index first_slot, BeforeUnpack&& before_unpack, PackOverride&& pack_override) {
    start(policy, plan, transport, variables, pack_override, false);
    before_unpack();
    complete(policy, plan, variables, first_slot);
  }

  // The same in two halves around work that reads neither the packed variables' received
  // elements nor changes their sent ones: start() packs and begins the transport's exchange
  // (Transport::begin), complete() finishes it and unpacks. The variables keep their sizes
  // in between.
  template <ExecutionPolicy P, class PackOverride>
  void start(P policy, const Plan& plan, Transport& transport, std::span<VariableBase* const> variables,
             PackOverride&& pack_override, bool split = true) {
    using namespace exchange_detail;
    const std::size_t p = std::size_t(plan.ranks());
    sizes_.clear();
    for (VariableBase* v : variables) sizes_.push_back(v->element_size());
    const Layout send = layout(plan.send_counts(), sizes_);
    recv_layout_ = layout(plan.recv_counts(), sizes_);
    if (send.segment != sent_segments_) {
      send_segments_.assign(send.segment);
      sent_segments_ = send.segment;
    }
    if (recv_layout_.segment != received_segments_) {
      recv_segments_.assign(recv_layout_.segment);
      received_segments_ = recv_layout_.segment;
    }
    send_buffer_.resize(std::max<Index>(send_buffer_.size(), send.block[p] / 4));
    recv_buffer_.resize(std::max<Index>(recv_buffer_.size(), recv_layout_.block[p] / 4));

    View<const std::uint32_t> index = plan.export_index_variable().read(policy);
    View<const std::int32_t> send_rank = plan.export_rank_variable().read(policy);
    View<const std::uint64_t> send_items = plan.send_offsets_variable().read(policy);
    View<const std::uint64_t> send_segment = send_segments_.read(policy);
    auto* send_bytes = reinterpret_cast<unsigned char*>(send_buffer_.write(policy).data());
    for (std::size_t v = 0; v < variables.size(); ++v) {
      if (plan.export_count() == 0) break;
      const View<const std::uint64_t> segment = send_segment.subview(v * p, p);
      const void* src = variables[v]->prepare(P::space, Access::read);
      if (pack_override(v, policy, index, send_rank, send_items, segment, src, send_bytes)) continue;
      const std::size_t e = sizes_[v];
      if (e % 4 == 0)
        particle_for(policy, plan.export_count(),
                     PackElements<std::uint32_t>{index, send_rank, send_items, segment,
                                                 static_cast<const std::uint32_t*>(src), send_bytes, e / 4});
      else
        particle_for(policy, plan.export_count(),
                     PackElements<unsigned char>{index, send_rank, send_items, segment,
                                                 static_cast<const unsigned char*>(src), send_bytes, e});
    }
    auto* recv_bytes = reinterpret_cast<unsigned char*>(recv_buffer_.write(policy).data());
    transport_ = &transport;
    if (split)
      transport.begin(P::space, send_bytes, send.block, recv_bytes, recv_layout_.block);
    else
      transport.exchange(P::space, send_bytes, send.block, recv_bytes, recv_layout_.block);
  }

  template <ExecutionPolicy P>
  void complete(P policy, const Plan& plan, std::span<VariableBase* const> variables, Index first_slot) {
    using namespace exchange_detail;
    if (transport_) transport_->finish();
    transport_ = nullptr;
    if (plan.import_count() == 0) return;
    const std::size_t p = std::size_t(plan.ranks());
    View<const std::int32_t> recv_rank = plan.import_rank_variable().read(policy);
    View<const std::uint64_t> recv_items = plan.recv_offsets_variable().read(policy);
    View<const std::uint64_t> recv_segment = recv_segments_.read(policy);
    const auto* recv_bytes = reinterpret_cast<const unsigned char*>(recv_buffer_.read(policy).data());
    for (std::size_t v = 0; v < variables.size(); ++v) {
      const View<const std::uint64_t> segment = recv_segment.subview(v * p, p);
      if (variables[v]->size() < first_slot + plan.import_count())
        throw Error("exchange: " + variables[v]->describe() + " has no room for " +
                    std::to_string(plan.import_count()) + " received items from index " + std::to_string(first_slot));
      auto* dst = static_cast<unsigned char*>(variables[v]->prepare(P::space, Access::read_write)) + first_slot * sizes_[v];
      const std::size_t e = sizes_[v];
      if (e % 4 == 0)
        particle_for(policy, plan.import_count(),
                     UnpackElements<std::uint32_t>{recv_rank, recv_items, segment, recv_bytes,
                                                   reinterpret_cast<std::uint32_t*>(dst), e / 4});
      else
        particle_for(policy, plan.import_count(),
                     UnpackElements<unsigned char>{recv_rank, recv_items, segment, recv_bytes, dst, e});
    }
  }

 private:
  DiscreteVariable<std::uint64_t> send_segments_{"Exchange.SendSegments"};
  DiscreteVariable<std::uint64_t> recv_segments_{"Exchange.RecvSegments"};
  DiscreteVariable<std::uint32_t> send_buffer_{"Exchange.SendBuffer"};
  DiscreteVariable<std::uint32_t> recv_buffer_{"Exchange.RecvBuffer"};
  std::vector<std::uint64_t> sent_segments_, received_segments_;  // what the tables hold
  std::vector<std::size_t> sizes_;
  exchange_detail::Layout recv_layout_;
  Transport* transport_ = nullptr;  // between start() and complete()
};

}  // namespace unisph::comm
