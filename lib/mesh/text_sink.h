// Buffered output for the mesh writers: text, and the bytes of binary PLY and STL.
// Numbers and indices are formatted straight into one fixed buffer (std::to_chars) that
// goes to the stream in 1 MB blocks, so a writer's memory stays bounded whatever the
// mesh size and no string is built per token.
#pragma once

#include <omp.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "common/numbers.h"

namespace ffd {

class TextSink {
public:
  explicit TextSink(std::ostream& os) : os_(&os), size_(kSize), buffer_(new char[size_]), end_(buffer_.get()) {}
  /// Into memory, through a smaller buffer: flush() appends to `into` (put_ordered's blocks).
  explicit TextSink(std::string& into) : into_(&into), size_(kBlockSize), buffer_(new char[size_]), end_(buffer_.get()) {}
  TextSink(const TextSink&) = delete;
  TextSink& operator=(const TextSink&) = delete;

  void put(char c) {
    room(1);
    *end_++ = c;
  }
  void put(std::string_view text) {
    if (text.size() > size_ / 2) {  // a long header line, or a formatted block: straight through
      flush();
      write(text.data(), text.size());
      return;
    }
    room(text.size());
    std::memcpy(end_, text.data(), text.size());
    end_ += text.size();
  }
  /// The bytes of a trivially copyable value as the machine holds it (little-endian on
  /// x86-64), for the binary writers.
  template <class T>
  void raw(const T& value) {
    room(sizeof value);
    std::memcpy(end_, &value, sizeof value);
    end_ += sizeof value;
  }
  /// The shortest round-trip text of x (append_number's).
  void number(double x) {
    room(kNumberChars);
    end_ = format_number_to(end_, x);
  }
  void integer(std::uint64_t x) {
    room(24);
    end_ = std::to_chars(end_, end_ + 24, x).ptr;
  }
  void integer(std::int64_t x) {
    room(24);
    end_ = std::to_chars(end_, end_ + 24, x).ptr;
  }
  void integer(std::uint32_t x) { integer(static_cast<std::uint64_t>(x)); }
  void integer(std::int32_t x) { integer(static_cast<std::int64_t>(x)); }
  /// Room for n characters (at most half the buffer) written straight at the returned
  /// pointer; commit(end) then takes them up to `end`. For a line whose longest form is
  /// known: one check for the line instead of one per token.
  char* claim(std::size_t n) {
    room(n);
    return end_;
  }
  void commit(char* end) { end_ = end; }
  /// Writes what is buffered to the stream. Call it at the end; the destructor does not,
  /// so that a writer that throws leaves no half-formatted block behind.
  void flush() {
    write(buffer_.get(), static_cast<std::size_t>(end_ - buffer_.get()));
    end_ = buffer_.get();
  }

private:
  static constexpr std::size_t kSize = std::size_t{1} << 20, kBlockSize = std::size_t{64} << 10;
  void write(const char* data, std::size_t n) {
    if (os_)
      os_->write(data, static_cast<std::streamsize>(n));
    else
      into_->append(data, n);
  }
  void room(std::size_t n) {
    if (static_cast<std::size_t>(buffer_.get() + size_ - end_) < n) flush();
  }
  std::ostream* os_ = nullptr;
  std::string* into_ = nullptr;
  std::size_t size_;
  std::unique_ptr<char[]> buffer_;
  char* end_;
};

/// Writes what `format(sink, i)` writes for i = first .. last - 1, in order. With more than
/// one OpenMP thread, a long range is formatted by the team in blocks, each into its own
/// buffer, while one thread writes the previous round's blocks in order: the same bytes
/// whatever the thread count, in memory bounded by two blocks per thread. `format` must
/// depend on i alone.
template <class Format>
void put_ordered(TextSink& out, std::size_t first, std::size_t last, const Format& format) {
  constexpr std::size_t kItems = 4096;  // per block: about 250 KB of OBJ v lines
  const int threads = omp_get_max_threads();
  if (threads == 1 || last - first < 4 * kItems || omp_in_parallel()) {
    for (std::size_t i = first; i < last; ++i) format(out, i);
    return;
  }
  const std::size_t team = static_cast<std::size_t>(threads), blocks = (last - first + kItems - 1) / kItems;
  const std::size_t rounds = (blocks + team - 1) / team;
  std::vector<std::string> buffers(2 * team);  // round r's block r * team + t: buffers[(r % 2) * team + t]
  std::vector<std::exception_ptr> failures(team);
  std::exception_ptr write_failure;
#pragma omp parallel num_threads(threads)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    TextSink even(buffers[t]), odd(buffers[team + t]);
    for (std::size_t r = 0; r <= rounds; ++r) {
      const std::size_t b = r * team + t;
      if (r < rounds && b < blocks && !failures[t]) {
        std::string& mine = buffers[(r % 2) * team + t];
        TextSink& sink = r % 2 ? odd : even;
        try {
          mine.clear();
          for (std::size_t i = first + b * kItems; i < std::min(last, first + (b + 1) * kItems); ++i) format(sink, i);
          sink.flush();
        } catch (...) {
          failures[t] = std::current_exception();
        }
      }
      if (t == 0 && r > 0 && !write_failure) {  // the previous round, while the team formats this one
        try {
          for (std::size_t k = 0; k < team && (r - 1) * team + k < blocks; ++k) out.put(buffers[((r - 1) % 2) * team + k]);
        } catch (...) {
          write_failure = std::current_exception();
        }
      }
#pragma omp barrier
    }
  }
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
  if (write_failure) std::rethrow_exception(write_failure);
}

}  // namespace ffd
