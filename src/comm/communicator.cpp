// The Communicator over MPI (UNISPH_HAS_MPI) or the serial one (rank 0 of 1).

#include "unisph/comm/communicator.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "unisph/exec/algorithms.hpp"

#if UNISPH_HAS_MPI
#include <mpi.h>
#endif

namespace unisph::comm {

bool mpi_built() { return UNISPH_HAS_MPI; }

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

#if UNISPH_HAS_MPI

struct Communicator::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  MPI_Comm node = MPI_COMM_NULL;  // ranks sharing this node, made on first use
  bool owned = false;
  ~Impl() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized) return;
    if (node != MPI_COMM_NULL) MPI_Comm_free(&node);
    if (owned && comm != MPI_COMM_NULL) MPI_Comm_free(&comm);
  }
};

namespace {
void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(std::string("MPI: ") + what + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}
bool mpi_initialized() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}
MPI_Comm comm_of(const std::shared_ptr<Communicator::Impl>& impl) { return impl->comm; }
}  // namespace

Environment::Environment(int& argc, char**& argv) {
  if (mpi_initialized()) return;
  int provided = 0;
  check_mpi(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  // Errors come back as codes (turned into exceptions), not as MPI's default abort.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
}
Environment::~Environment() {
  if (mpi_initialized()) MPI_Finalize();
}

Communicator Communicator::world() {
  if (!mpi_initialized()) return serial();
  Communicator c;
  c.impl_ = std::make_shared<Impl>();
  c.impl_->comm = MPI_COMM_WORLD;
  MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
  return c;
}

int Communicator::local_rank() const {
  if (!impl_) return 0;
  if (impl_->node == MPI_COMM_NULL)
    check_mpi(MPI_Comm_split_type(impl_->comm, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &impl_->node),
              "MPI_Comm_split_type");
  int r = 0;
  MPI_Comm_rank(impl_->node, &r);
  return r;
}
int Communicator::local_size() const {
  if (!impl_) return 1;
  local_rank();
  int s = 1;
  MPI_Comm_size(impl_->node, &s);
  return s;
}

void Communicator::barrier() const {
  if (impl_) check_mpi(MPI_Barrier(comm_of(impl_)), "MPI_Barrier");
}

namespace {
template <class T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}
template <>
MPI_Datatype mpi_type<std::uint64_t>() {
  return MPI_UINT64_T;
}
template <class T>
T allreduce(const std::shared_ptr<Communicator::Impl>& impl, T x, MPI_Op op, const char* what) {
  if (!impl) return x;
  T out{};
  check_mpi(MPI_Allreduce(&x, &out, 1, mpi_type<T>(), op, comm_of(impl)), what);
  return out;
}
template <class T>
std::vector<T> gather_all(const std::shared_ptr<Communicator::Impl>& impl, int size, T x) {
  std::vector<T> out(static_cast<std::size_t>(size));
  if (!impl) {
    out[0] = x;
    return out;
  }
  check_mpi(MPI_Allgather(&x, 1, mpi_type<T>(), out.data(), 1, mpi_type<T>(), comm_of(impl)), "MPI_Allgather");
  return out;
}
template <class T>
std::vector<T> gather_all_v(const std::shared_ptr<Communicator::Impl>& impl, int size, std::span<const T> local) {
  if (!impl) return std::vector<T>(local.begin(), local.end());
  if (local.size() > std::size_t(std::numeric_limits<int>::max()))
    throw Error("allgatherv: " + std::to_string(local.size()) + " values on one rank; MPI counts are int");
  const int n = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
  check_mpi(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_of(impl)), "MPI_Allgather");
  long long total = 0;
  for (int r = 0; r < size; ++r) {
    displs[std::size_t(r)] = static_cast<int>(total);
    total += counts[std::size_t(r)];
  }
  if (total > std::numeric_limits<int>::max())
    throw Error("allgatherv: " + std::to_string(total) + " values in all; MPI displacements are int");
  std::vector<T> out(static_cast<std::size_t>(total));
  check_mpi(MPI_Allgatherv(local.data(), n, mpi_type<T>(), out.data(), counts.data(), displs.data(), mpi_type<T>(),
                           comm_of(impl)),
            "MPI_Allgatherv");
  return out;
}
}  // namespace

double Communicator::allreduce_min(double x) const { return allreduce(impl_, x, MPI_MIN, "MPI_Allreduce(min)"); }
double Communicator::allreduce_max(double x) const { return allreduce(impl_, x, MPI_MAX, "MPI_Allreduce(max)"); }
std::uint64_t Communicator::allreduce_min(std::uint64_t x) const {
  return allreduce(impl_, x, MPI_MIN, "MPI_Allreduce(min)");
}
std::uint64_t Communicator::allreduce_max(std::uint64_t x) const {
  return allreduce(impl_, x, MPI_MAX, "MPI_Allreduce(max)");
}
std::uint64_t Communicator::allreduce_sum(std::uint64_t x) const {
  return allreduce(impl_, x, MPI_SUM, "MPI_Allreduce(sum)");
}
namespace {
// Elementwise MPI_SUM of an array in place, in chunks: MPI counts are int.
template <class T>
void sum_in_place(const std::shared_ptr<Communicator::Impl>& impl, std::span<T> values, MPI_Datatype type) {
  if (!impl || values.empty()) return;
  const std::size_t chunk = std::size_t(1) << 28;
  for (std::size_t at = 0; at < values.size(); at += chunk) {
    const int n = static_cast<int>(std::min(chunk, values.size() - at));
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, values.data() + at, n, type, MPI_SUM, comm_of(impl)), "MPI_Allreduce(sum)");
  }
}
}  // namespace

void Communicator::allreduce_sum(std::span<std::uint64_t> values) const { sum_in_place(impl_, values, MPI_UINT64_T); }
// MPI_SUM is exact here whatever its association: all but one addend of each element are 0.
void Communicator::combine_owned(std::span<double> values) const { sum_in_place(impl_, values, MPI_DOUBLE); }
double Communicator::allreduce_sum(double x) const {
  // Not MPI_SUM: its association is the library's choice (and may change with the rank count
  // or the algorithm it picks); here every rank folds the gathered values in rank order.
  const std::vector<double> all = gather_all(impl_, size_, x);
  double sum = all[0];
  for (std::size_t r = 1; r < all.size(); ++r) sum += all[r];
  return sum;
}
std::vector<std::uint64_t> Communicator::allgather(std::uint64_t x) const { return gather_all(impl_, size_, x); }
std::vector<double> Communicator::allgather(double x) const { return gather_all(impl_, size_, x); }
std::vector<double> Communicator::allgatherv(std::span<const double> local) const {
  return gather_all_v(impl_, size_, local);
}
std::vector<std::uint64_t> Communicator::allgatherv(std::span<const std::uint64_t> local) const {
  return gather_all_v(impl_, size_, local);
}

std::vector<std::uint64_t> Communicator::alltoall(std::span<const std::uint64_t> send) const {
  if (send.size() != std::size_t(size_))
    throw Error("alltoall: " + std::to_string(send.size()) + " values for " + std::to_string(size_) + " ranks");
  std::vector<std::uint64_t> recv(send.size());
  if (!impl_) {
    recv[0] = send[0];
    return recv;
  }
  check_mpi(MPI_Alltoall(send.data(), 1, MPI_UINT64_T, recv.data(), 1, MPI_UINT64_T, comm_of(impl_)),
            "MPI_Alltoall");
  return recv;
}

void Communicator::broadcast(void* data, std::size_t bytes, int root) const {
  if (!impl_) return;
  if (bytes > std::size_t(std::numeric_limits<int>::max())) throw Error("broadcast: more than 2^31 bytes");
  check_mpi(MPI_Bcast(data, static_cast<int>(bytes), MPI_BYTE, root, comm_of(impl_)), "MPI_Bcast");
}

void Communicator::exchange(std::span<const Segment> send, std::span<const Segment> recv) const {
  if (send.size() != std::size_t(size_) || recv.size() != std::size_t(size_))
    throw Error("exchange: segment lists must have one entry per rank (" + std::to_string(size_) + ")");
  const Segment& self_send = send[std::size_t(rank_)];
  const Segment& self_recv = recv[std::size_t(rank_)];
  if (self_send.bytes != self_recv.bytes)
    throw Error("exchange: " + std::to_string(self_send.bytes) + " bytes sent to self but " +
                std::to_string(self_recv.bytes) + " expected");
  if (self_send.bytes) std::memcpy(self_recv.data, self_send.data, self_send.bytes);
  if (!impl_) return;
  std::vector<MPI_Request> requests;
  constexpr int tag = 4242;
  const std::size_t max_message = std::size_t(1) << 30;  // MPI counts are int: large segments go in pieces
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    const Segment& s = recv[std::size_t(r)];
    for (std::size_t at = 0; at < s.bytes; at += max_message) {
      requests.emplace_back();
      check_mpi(MPI_Irecv(static_cast<char*>(s.data) + at, static_cast<int>(std::min(max_message, s.bytes - at)),
                          MPI_BYTE, r, tag, comm_of(impl_), &requests.back()),
                "MPI_Irecv");
    }
  }
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    const Segment& s = send[std::size_t(r)];
    for (std::size_t at = 0; at < s.bytes; at += max_message) {
      requests.emplace_back();
      check_mpi(MPI_Isend(static_cast<const char*>(s.data) + at,
                          static_cast<int>(std::min(max_message, s.bytes - at)), MPI_BYTE, r, tag, comm_of(impl_),
                          &requests.back()),
                "MPI_Isend");
    }
  }
  check_mpi(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
}

void Communicator::check_all(bool ok, std::string_view message) const {
  const std::vector<std::uint64_t> flags = gather_all(impl_, size_, std::uint64_t(ok ? 0 : 1));
  int first = -1, failed = 0;
  for (int r = 0; r < size_; ++r)
    if (flags[std::size_t(r)]) {
      if (first < 0) first = r;
      ++failed;
    }
  if (first < 0) return;
  // The first failing rank's message, sent to everyone.
  std::uint64_t length = rank_ == first ? message.size() : 0;
  if (impl_) check_mpi(MPI_Bcast(&length, 1, MPI_UINT64_T, first, comm_of(impl_)), "MPI_Bcast");
  std::string text(static_cast<std::size_t>(length), '\0');
  if (rank_ == first) text.assign(message);
  if (impl_ && length) check_mpi(MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, first, comm_of(impl_)),
                                 "MPI_Bcast");
  std::string line = "rank " + std::to_string(first) + ": " + (text.empty() ? "failed" : text);
  if (failed > 1) line += " (and " + std::to_string(failed - 1) + " more rank" + (failed > 2 ? "s" : "") + ")";
  throw RankFailure(first, line);
}

void Communicator::abort(std::string_view line, int code) const {
  std::fprintf(stderr, "unisph: rank %d: %.*s\n", rank_, static_cast<int>(line.size()), line.data());
  std::fflush(stderr);
  if (impl_) MPI_Abort(comm_of(impl_), code);
  std::abort();
}

const void* Communicator::native_handle() const { return impl_ ? &impl_->comm : nullptr; }

#else  // serial only

struct Communicator::Impl {};

Environment::Environment(int&, char**&) {}
Environment::~Environment() = default;

Communicator Communicator::world() { return serial(); }

int Communicator::local_rank() const { return 0; }
int Communicator::local_size() const { return 1; }
void Communicator::barrier() const {}
double Communicator::allreduce_min(double x) const { return x; }
double Communicator::allreduce_max(double x) const { return x; }
double Communicator::allreduce_sum(double x) const { return x; }
std::uint64_t Communicator::allreduce_min(std::uint64_t x) const { return x; }
std::uint64_t Communicator::allreduce_max(std::uint64_t x) const { return x; }
std::uint64_t Communicator::allreduce_sum(std::uint64_t x) const { return x; }
void Communicator::allreduce_sum(std::span<std::uint64_t>) const {}
void Communicator::combine_owned(std::span<double>) const {}
std::vector<std::uint64_t> Communicator::allgather(std::uint64_t x) const { return {x}; }
std::vector<double> Communicator::allgather(double x) const { return {x}; }
std::vector<double> Communicator::allgatherv(std::span<const double> local) const {
  return std::vector<double>(local.begin(), local.end());
}
std::vector<std::uint64_t> Communicator::allgatherv(std::span<const std::uint64_t> local) const {
  return std::vector<std::uint64_t>(local.begin(), local.end());
}
std::vector<std::uint64_t> Communicator::alltoall(std::span<const std::uint64_t> send) const {
  if (send.size() != 1) throw Error("alltoall: " + std::to_string(send.size()) + " values for 1 rank");
  return {send[0]};
}
void Communicator::broadcast(void*, std::size_t, int) const {}
void Communicator::exchange(std::span<const Segment> send, std::span<const Segment> recv) const {
  if (send.size() != 1 || recv.size() != 1 || send[0].bytes != recv[0].bytes)
    throw Error("exchange: the serial communicator exchanges one segment with itself");
  if (send[0].bytes) std::memcpy(recv[0].data, send[0].data, send[0].bytes);
}
void Communicator::check_all(bool ok, std::string_view message) const {
  if (!ok) throw RankFailure(0, "rank 0: " + (message.empty() ? std::string("failed") : std::string(message)));
}
void Communicator::abort(std::string_view line, int) const {
  std::fprintf(stderr, "unisph: rank 0: %.*s\n", static_cast<int>(line.size()), line.data());
  std::fflush(stderr);
  std::abort();
}
const void* Communicator::native_handle() const { return nullptr; }

#endif

Communicator Communicator::serial() { return Communicator(); }

namespace {
struct ValueAt {
  const double* values;
  UNISPH_HOST_DEVICE double operator()(Index i) const { return values[i]; }
};
}  // namespace

double Communicator::ordered_sum(std::span<const double> local_values) const {
  const std::vector<double> all = allgatherv(local_values);
  return deterministic_reduce(seq, all.size(), Sum<double>{}, ValueAt{all.data()});
}

}  // namespace unisph::comm
