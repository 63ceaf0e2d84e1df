#pragma once
// The binary container of a checkpoint: a fixed header, named sections of plain values and
// byte blocks, and a trailer that holds the content's length and checksum. Host code only.
//
//   offset 0   "UNISPH-CHECKPOINT\n" (18 bytes), format version (u32)
//   ...        what the writer appended: u32/u64/f64 values, strings and byte blocks (a u64
//              length, then the bytes), each group opened by a section name
//   end        "END!" (4 bytes), content length (u64), FNV-1a 64 of the content (u64)
//
// Little-endian, as every machine unisph runs on (x86-64, aarch64, the GPUs' hosts).
// The writer builds the file in memory and writes it to "<name>.tmp", then renames it, so a
// crash never leaves a broken checkpoint under the final name. The reader checks the magic,
// the version, the trailer and the checksum before anything is read, and every read after that
// against the remaining length: a wrong, truncated or damaged file is one error line that names
// the file and what is wrong.
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/io/vtk_xml_writer.hpp"

namespace unisph::io {

static_assert(std::endian::native == std::endian::little,
              "Checkpoints are written little-endian byte for byte; this machine is big-endian.");

class CheckpointError : public Error {
 public:
  using Error::Error;
};

inline constexpr std::string_view checkpoint_magic = "UNISPH-CHECKPOINT\n";
inline constexpr std::string_view checkpoint_trailer = "END!";

inline std::uint64_t fnv1a64(const char* data, std::size_t size) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= std::uint8_t(data[i]);
    h *= 1099511628211ull;
  }
  return h;
}

class CheckpointWriter {
 public:
  explicit CheckpointWriter(std::uint32_t version) {
    bytes_.append(checkpoint_magic);
    u32(version);
  }

  void section(std::string_view name) { string(name); }
  void u32(std::uint32_t v) { raw(&v, sizeof v); }
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void string(std::string_view s) { block(s.data(), s.size()); }
  void block(const void* data, std::size_t size) {
    u64(size);
    raw(data, size);
  }
  void f64s(const std::vector<double>& v) {
    u64(v.size());
    for (double x : v) f64(x);
  }

  // Appends the trailer and writes the file (temporary file, then rename).
  void commit(const std::filesystem::path& path) {
    const std::uint64_t length = bytes_.size();
    const std::uint64_t sum = fnv1a64(bytes_.data(), bytes_.size());
    bytes_.append(checkpoint_trailer);
    raw(&length, sizeof length);
    raw(&sum, sizeof sum);
    write_file_atomically(path, bytes_);
  }

 private:
  void raw(const void* data, std::size_t size) { bytes_.append(static_cast<const char*>(data), size); }
  std::string bytes_;
};

class CheckpointReader {
 public:
  // Reads and checks the whole file; `expected_version` is the only version this reader knows.
  CheckpointReader(const std::filesystem::path& path, std::uint32_t expected_version) : path_(path.string()) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot be opened");
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const std::size_t head = checkpoint_magic.size() + sizeof(std::uint32_t);
    if (bytes_.size() < checkpoint_magic.size() || std::string_view(bytes_).substr(0, checkpoint_magic.size()) != checkpoint_magic)
      fail("is not a unisph checkpoint (it does not start with \"UNISPH-CHECKPOINT\")");
    const std::size_t tail = checkpoint_trailer.size() + 2 * sizeof(std::uint64_t);
    if (bytes_.size() < head + tail) fail("is truncated (" + std::to_string(bytes_.size()) + " bytes)");
    std::uint32_t version = 0;
    std::memcpy(&version, bytes_.data() + checkpoint_magic.size(), sizeof version);
    if (version != expected_version)
      fail("has format version " + std::to_string(version) + "; this unisph reads version " +
           std::to_string(expected_version));
    const std::size_t content = bytes_.size() - tail;
    std::uint64_t length = 0, sum = 0;
    std::memcpy(&length, bytes_.data() + content + checkpoint_trailer.size(), sizeof length);
    std::memcpy(&sum, bytes_.data() + content + checkpoint_trailer.size() + sizeof length, sizeof sum);
    if (std::string_view(bytes_).substr(content, checkpoint_trailer.size()) != checkpoint_trailer || length != content)
      fail("is truncated or has trailing bytes (" + std::to_string(bytes_.size()) + " bytes, no end marker where expected)");
    if (fnv1a64(bytes_.data(), content) != sum) fail("is damaged (checksum mismatch)");
    end_ = content;
    at_ = head;
  }

  const std::string& path() const { return path_; }

  // Reads a section name and checks it is `name` (the file's layout is what this reader expects).
  void section(std::string_view name) {
    const std::string found = string();
    if (found != name) fail("holds section '" + found + "' where '" + std::string(name) + "' was expected");
  }
  std::uint32_t u32() { return value<std::uint32_t>(); }
  std::uint64_t u64() { return value<std::uint64_t>(); }
  double f64() { return value<double>(); }
  std::string string() {
    const std::uint64_t n = u64();
    need(n, "a string");
    std::string s(bytes_.data() + at_, n);
    at_ += n;
    return s;
  }
  // A block of exactly `size` bytes copied to `out`; `what` names it in the error.
  void block(void* out, std::size_t size, const std::string& what) {
    const std::uint64_t n = u64();
    if (n != size)
      fail("holds " + std::to_string(n) + " bytes for " + what + " where " + std::to_string(size) + " were expected");
    need(n, what);
    if (n) std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  std::vector<double> f64s() {
    const std::uint64_t n = u64();
    need(n * sizeof(double), "a list of numbers");
    std::vector<double> v(n);
    for (double& x : v) x = f64();
    return v;
  }
  bool at_end() const { return at_ == end_; }

  [[noreturn]] void fail(const std::string& what) const { throw CheckpointError("checkpoint " + path_ + ": " + what); }

 private:
  template <class V>
  V value() {
    need(sizeof(V), "a value");
    V v;
    std::memcpy(&v, bytes_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  void need(std::uint64_t n, const std::string& what) const {
    if (n > end_ - at_)
      fail("ends inside " + what + " at byte " + std::to_string(at_) + " (needs " + std::to_string(n) + ", " +
           std::to_string(end_ - at_) + " left)");
  }

  std::string path_;
  std::string bytes_;
  std::size_t at_ = 0;
  std::size_t end_ = 0;
};

}  // namespace unisph::io
