// A file's bytes, read whole: mapped read-only from the page cache when the file is a
// regular one that mmap(2) takes, read(2) into one buffer otherwise. A mapped file costs
// no copy and no page of fresh memory: a 400 MB volume mesh is in hand in tens of ms
// instead of the ~250 ms that read(2) into a new buffer takes (its pages are faulted in
// and zeroed one by one).
//
// A mapping sees the file as it is on disk: a file truncated by another process while
// ffdtool holds it would fault. ffdtool's own writes never do that: they stage a new file
// and rename it over the old one (common/atomic_file.h), which leaves the mapped inode as
// it was, so an output may replace its input.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace ffd {

class FileBytes {
 public:
  FileBytes() = default;
  /// Bytes already in memory (tests, fuzzing, a buffer read some other way).
  explicit FileBytes(std::string owned);
  ~FileBytes();
  FileBytes(FileBytes&& other) noexcept;
  FileBytes& operator=(FileBytes&& other) noexcept;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;

  const char* data() const { return data_; }
  std::size_t size() const { return size_; }
  std::string_view view() const { return {data_, size_}; }
  operator std::string_view() const { return view(); }  // NOLINT: a view of the bytes
  /// Gives a mapped file's resident pages back (they stay in the page cache, and a later
  /// read of the bytes faults them in again): a reader that has parsed the file calls it
  /// before building from what it parsed, so the file and the built mesh are not both in
  /// the process's memory at its peak. A no-op for bytes in a buffer.
  void release_pages() const;

 private:
  friend FileBytes read_file_bytes(const std::string& path);
  void unmap();

  std::string owned_;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
  bool mapped_ = false;
};

/// The whole file at `path`. \throw InputError when it is not a regular file or cannot be
/// opened, IoError when reading it fails.
FileBytes read_file_bytes(const std::string& path);

/// The same, shared (volume readers keep the bytes for the writer that patches them).
std::shared_ptr<const FileBytes> read_shared_file_bytes(const std::string& path);

}  // namespace ffd
