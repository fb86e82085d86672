// Buffered output for the mesh writers: text, and the bytes of binary PLY and STL.
// Numbers and indices are formatted straight into one fixed buffer (std::to_chars) that
// goes to the stream in 1 MB blocks, so a writer's memory stays bounded whatever the
// mesh size and no string is built per token.
#pragma once

#include <charconv>
#include <cstdint>
#include <cstring>
#include <memory>
#include <ostream>
#include <string_view>

#include "common/numbers.h"

namespace ffd {

class TextSink {
public:
  explicit TextSink(std::ostream& os) : os_(os), buffer_(new char[kSize]), end_(buffer_.get()) {}
  TextSink(const TextSink&) = delete;
  TextSink& operator=(const TextSink&) = delete;

  void put(char c) {
    room(1);
    *end_++ = c;
  }
  void put(std::string_view text) {
    if (text.size() > kSize / 2) {  // a long header line: straight through
      flush();
      os_.write(text.data(), static_cast<std::streamsize>(text.size()));
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
  /// Writes what is buffered to the stream. Call it at the end; the destructor does not,
  /// so that a writer that throws leaves no half-formatted block behind.
  void flush() {
    os_.write(buffer_.get(), static_cast<std::streamsize>(end_ - buffer_.get()));
    end_ = buffer_.get();
  }

private:
  static constexpr std::size_t kSize = std::size_t{1} << 20;
  void room(std::size_t n) {
    if (static_cast<std::size_t>(buffer_.get() + kSize - end_) < n) flush();
  }
  std::ostream& os_;
  std::unique_ptr<char[]> buffer_;
  char* end_;
};

}  // namespace ffd
