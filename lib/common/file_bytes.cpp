#include "common/file_bytes.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/errors.h"

namespace ffd {

FileBytes::FileBytes(std::string owned) : owned_(std::move(owned)), data_(owned_.data()), size_(owned_.size()) {}

FileBytes::~FileBytes() { unmap(); }

FileBytes::FileBytes(FileBytes&& other) noexcept { *this = std::move(other); }

FileBytes& FileBytes::operator=(FileBytes&& other) noexcept {
  if (this == &other) return *this;
  unmap();
  mapped_ = std::exchange(other.mapped_, false);
  size_ = std::exchange(other.size_, 0);
  if (mapped_) {
    data_ = std::exchange(other.data_, nullptr);
  } else {
    owned_ = std::move(other.owned_);
    data_ = owned_.data();
    other.owned_.clear();
    other.data_ = other.owned_.data();
  }
  return *this;
}

void FileBytes::unmap() {
  if (mapped_) ::munmap(const_cast<char*>(data_), size_);
  mapped_ = false;
  data_ = owned_.data();
  size_ = owned_.size();
}

namespace {

// Closes a descriptor when it goes out of scope.
struct Descriptor {
  int fd;
  ~Descriptor() { ::close(fd); }
};

// Reads to the end of `fd` (even past a size that grew since fstat), retrying on EINTR.
std::string read_to_end(int fd, std::size_t expected, const std::string& path) {
  std::string bytes;
  bytes.reserve(expected);
  char buffer[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got == 0) return bytes;
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw IoError(At{path}, std::string("cannot read: ") + std::strerror(errno));
    bytes.append(buffer, static_cast<std::size_t>(got));
  }
}

}  // namespace

void FileBytes::release_pages() const {
  if (mapped_) ::madvise(const_cast<char*>(data_), size_, MADV_DONTNEED);  // advice: failing it changes nothing
}

FileBytes read_file_bytes(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(At{path}, "no such file");
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) throw InputError(At{path}, std::string("cannot open for reading: ") + std::strerror(errno));
  struct stat st {};
  const std::size_t size = ::fstat(file.fd, &st) == 0 && st.st_size > 0 ? static_cast<std::size_t>(st.st_size) : 0;
  if (size > 0) {
    // MAP_POPULATE: the pages are read ahead and mapped in one call, not faulted in one by one.
    void* at = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, file.fd, 0);
    if (at != MAP_FAILED) {
      FileBytes bytes;
      bytes.data_ = static_cast<const char*>(at);
      bytes.size_ = size;
      bytes.mapped_ = true;
      return bytes;
    }
  }
  return FileBytes(read_to_end(file.fd, size, path));
}

std::shared_ptr<const FileBytes> read_shared_file_bytes(const std::string& path) {
  return std::make_shared<const FileBytes>(read_file_bytes(path));
}

}  // namespace ffd
