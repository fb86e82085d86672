// Staging an output file (atomic_file.h).
//
// Linux: open(folder, O_TMPFILE) makes a file with no name in the target's folder;
// write() fills it through FdBuffer; commit() names it with
// linkat("/proc/self/fd/N", target, AT_SYMLINK_FOLLOW), or where a sandbox refuses that,
// linkat(fd, "", target, AT_EMPTY_PATH) (which needs CAP_DAC_READ_SEARCH). When the
// target does not exist yet, that one call makes the file appear whole, and a process
// killed at any moment before it leaves nothing: the kernel frees an unnamed file with
// its last descriptor. linkat cannot replace a file, so when the target exists the file
// is linked to a temporary name beside it, `target.ffdtool-PID-N.tmp`, and renamed over
// the target. A kill between that link and the rename (once per file, after every byte
// is written) leaves the file, complete, under its temporary name; the batch runner
// removes such files of the items it saw killed. Linux has no call that links a file
// over an existing name, so this window can be made short, not closed.
//
// Fallbacks to the named temporary file:
// - from the start, where the folder's file system has no unnamed files (open fails with
//   EOPNOTSUPP, or EISDIR or EINVAL from a kernel without O_TMPFILE) or /proc is not
//   mounted: a kill while writing then leaves a partial temporary file (never a partial
//   target), which the batch runner's clean-up removes for its items;
// - once written, when more unnamed files wait for commit() than half the open-file
//   limit (a script saving thousands of frames): the finished file is linked to its
//   temporary name and closed, so a kill before commit leaves it complete under that
//   name. The first such check raises the soft limit to the hard one, as a program that
//   holds many files should (ffdtool uses no select()).
//
// No fsync: the promise is about the process (killed, or a write that failed), not about
// the machine losing power, and an fsync per file would cost more than writing most
// meshes. Without it, a write error that only writeback finds (EIO on a network file
// system) can surface at close(), after the link: the file linked is then removed.
//
// Over an existing regular file, the rename is an exchange (renameat2 RENAME_EXCHANGE):
// the new file takes the target's name in one step and the old one, now under the
// temporary name, is removed. ext4 takes a rename over a file as a program replacing a
// file without fsync and allocates the new file's blocks there and then (auto_da_alloc:
// 63 ms of 71 for a 107 MB OBJ here); an exchange leaves them to writeback, as for a new
// file. That heuristic is about power loss, which this file does not promise. A kill
// between the exchange and the removal leaves the old file under the temporary name.
#include "common/atomic_file.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <streambuf>
#include <system_error>
#include <vector>

#include "common/errors.h"

namespace ffd {
namespace fs = std::filesystem;

namespace {

/// A buffered output stream buffer over a file descriptor. The first failed write() is
/// kept (error()) and fails every later output, so the stream over it goes bad.
class FdBuffer final : public std::streambuf {
public:
  /// Writes to `fd` from now on (not owned).
  void attach(int fd) {
    fd_ = fd;
    data_.resize(kSize);
    setp(data_.data(), data_.data() + data_.size());
  }
  /// The errno of the first write that failed; 0 if none did.
  int error() const { return error_; }
  /// Bytes given to the buffer so far.
  std::size_t bytes() const { return written_ + static_cast<std::size_t>(pptr() - pbase()); }
  /// Frees the buffer once everything is written (many files may wait for commit).
  void release() {
    setp(nullptr, nullptr);
    std::vector<char>().swap(data_);
  }

protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    if (pptr() == epptr()) {  // released: no buffer left
      const char byte = traits_type::to_char_type(c);
      return put(&byte, 1) ? c : traits_type::eof();
    }
    *pptr() = traits_type::to_char_type(c);
    pbump(1);
    return c;
  }

  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n > epptr() - pptr()) {
      if (!drain()) return 0;
      if (n >= epptr() - pptr()) return put(s, static_cast<std::size_t>(n)) ? n : 0;  // large: past the buffer
    }
    std::memcpy(pptr(), s, static_cast<std::size_t>(n));
    pbump(static_cast<int>(n));
    return n;
  }

  int sync() override { return drain() ? 0 : -1; }

  // tellp() only.
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
    if (off == 0 && dir == std::ios_base::cur && (which & std::ios_base::out))
      return pos_type(static_cast<off_type>(bytes()));
    return pos_type(off_type(-1));
  }

private:
  static constexpr std::size_t kSize = std::size_t{1} << 18;

  // Writes out what the buffer holds.
  bool drain() {
    const auto n = static_cast<std::size_t>(pptr() - pbase());
    const bool ok = put(pbase(), n);
    setp(pbase(), epptr());
    return ok;
  }

  // Writes `n` bytes at `p` to the file, across short writes.
  bool put(const char* p, std::size_t n) {
    while (error_ == 0 && n > 0) {
      const ssize_t done = ::write(fd_, p, n);
      if (done < 0 && errno == EINTR) continue;
      if (done <= 0) {
        error_ = done < 0 ? errno : EIO;
        break;
      }
      p += done;
      n -= static_cast<std::size_t>(done);
      written_ += static_cast<std::size_t>(done);
    }
    return error_ == 0;
  }

  int fd_ = -1;
  int error_ = 0;
  std::size_t written_ = 0;
  std::vector<char> data_;
};

std::atomic<unsigned> temp_counter{0};
std::atomic<long> unnamed_open{0};  // unnamed files of this process with their descriptor open

[[noreturn]] void fail(const fs::path& target, int error) {
  throw IoError(At{target.string()}, std::string("cannot write: ") + std::strerror(error));
}

// A name beside `target` that nothing else uses: the pid keeps concurrent runs apart, the
// counter two staged writes of one path.
fs::path temp_name(const fs::path& target) {
  fs::path temp = target;
  temp += ".ffdtool-" + std::to_string(::getpid()) + "-" + std::to_string(temp_counter++) + ".tmp";
  return temp;
}

// How many unnamed files may wait for commit at once: half the open-file limit, which
// the first call raises to the hard limit (see the top of this file).
long unnamed_budget() {
  static const bool raised = [] {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur >= limit.rlim_max) return false;
    limit.rlim_cur = std::min<rlim_t>(limit.rlim_max, rlim_t{1} << 20);
    return ::setrlimit(RLIMIT_NOFILE, &limit) == 0;
  }();
  (void)raised;
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return 128;
  return static_cast<long>(std::min<rlim_t>(limit.rlim_cur / 2, rlim_t{1} << 19));
}

// An unnamed file for writing in `target`'s folder; -1 with errno set if there is none.
int open_unnamed(const fs::path& target) {
#ifdef O_TMPFILE
  static const bool proc_mounted = ::access("/proc/self/fd", X_OK) == 0;
  if (proc_mounted) {
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    return ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  }
#endif
  errno = EOPNOTSUPP;
  return -1;
}

// Whether open_unnamed's errno says the file system (or kernel) has no unnamed files.
bool no_unnamed_files(int error) { return error == EOPNOTSUPP || error == EISDIR || error == EINVAL; }

// Gives the unnamed file `fd` the name `name`; false with errno set (EEXIST: it is taken).
// Through /proc, which any user may; where a sandbox refuses that, by the descriptor
// itself (AT_EMPTY_PATH), which needs CAP_DAC_READ_SEARCH.
bool link_unnamed(int fd, const fs::path& name) {
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) return true;
  const int error = errno;
  if (error == EEXIST || error == ENOSPC || error == EDQUOT) return false;
  if (::linkat(fd, "", AT_FDCWD, name.c_str(), AT_EMPTY_PATH) == 0) return true;
  errno = error;
  return false;
}

// Puts the file named `temp` in `target`'s place in one step: over a regular file by
// exchanging the names and removing the old file (the top of this file), elsewhere (a new
// name, a directory, a symlink, a file system without exchanges) by rename. 0 or errno.
int replace_with(const fs::path& temp, const fs::path& target) {
#ifdef RENAME_EXCHANGE
  struct stat st {};
  if (::lstat(target.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
      ::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    ::unlink(temp.c_str());  // the old file: the new one is in place whatever this gives
    return 0;
  }
#endif
  return ::rename(temp.c_str(), target.c_str()) == 0 ? 0 : errno;
}

}  // namespace

/// What a StagedFile holds; the destructor discards whatever was not committed.
struct StagedFile::State {
  fs::path target;
  fs::path temp;         // the bytes' name until commit; empty while unnamed
  int fd = -1;
  bool unnamed = false;  // fd is an unnamed file (counted in unnamed_open)
  bool committed = false;
  FdBuffer buffer;
  std::ostream stream{&buffer};

  ~State() {
    close_file();
    if (!committed && !temp.empty()) ::unlink(temp.c_str());
  }

  /// Closes the file; false with errno set if close() reports an error.
  bool close_file() {
    if (fd < 0) return true;
    const int result = ::close(fd);
    fd = -1;
    if (unnamed) --unnamed_open;
    unnamed = false;
    return result == 0;
  }

  /// Creates a named temporary file for the bytes. \throw IoError if it cannot.
  void open_named() {
    for (int attempt = 0; fd < 0; ++attempt) {
      temp = temp_name(target);
      fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd < 0 && (errno != EEXIST || attempt == 8)) {
        const int error = errno;
        temp.clear();
        fail(target, error);
      }
    }
  }

  /// Links the unnamed file to a fresh temporary name. \throw IoError if it cannot.
  void link_temp() {
    for (int attempt = 0; temp.empty(); ++attempt) {
      const fs::path name = temp_name(target);
      if (link_unnamed(fd, name))
        temp = name;
      else if (errno != EEXIST || attempt == 8)
        fail(target, errno);
    }
  }

  /// Names the unnamed file `target`: directly if the name is free, else through a
  /// temporary name and rename (the window at the top of this file).
  void commit_unnamed() {
    if (!link_unnamed(fd, target)) {
      if (errno != EEXIST) fail(target, errno);
      link_temp();
      if (const int error = replace_with(temp, target)) fail(target, error);
      temp.clear();
    }
    if (!close_file()) {
      const int error = errno;
      ::unlink(target.c_str());
      fail(target, error);
    }
  }
};

StagedFile::StagedFile(fs::path target, Staging staging) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.target = std::move(target);
  if (staging == Staging::Auto) {
    s.fd = open_unnamed(s.target);
    if (s.fd < 0 && !no_unnamed_files(errno)) fail(s.target, errno);
    s.unnamed = s.fd >= 0;
    if (s.unnamed) ++unnamed_open;
  }
  if (s.fd < 0) s.open_named();
  s.buffer.attach(s.fd);
  s.stream.exceptions(std::ios::badbit);  // the first failed write ends the writer
}

StagedFile::~StagedFile() = default;
StagedFile::StagedFile(StagedFile&& other) noexcept = default;
StagedFile& StagedFile::operator=(StagedFile&& other) noexcept = default;

const fs::path& StagedFile::target() const { return state_->target; }
const fs::path& StagedFile::temp_path() const { return state_->temp; }

std::size_t StagedFile::write(const std::function<void(std::ostream&)>& fill) {
  State& s = *state_;
  try {
    fill(s.stream);
    s.stream.flush();
  } catch (const std::exception&) {
    if (s.buffer.error() == 0) throw;  // the writer's own error, not the file's
  }
  if (s.buffer.error() != 0) fail(s.target, s.buffer.error());
  if (!s.stream) throw IoError(At{s.target.string()}, "cannot write");
  const std::size_t bytes = s.buffer.bytes();
  s.buffer.release();
  // A named file needs no descriptor until commit; nor does an unnamed one past the budget.
  if (s.unnamed && unnamed_open > unnamed_budget()) s.link_temp();
  if (!s.temp.empty() && !s.close_file()) fail(s.target, errno);
  return bytes;
}

void StagedFile::commit() {
  State& s = *state_;
  if (s.committed) return;
  if (s.unnamed) {
    s.commit_unnamed();
  } else {
    if (!s.close_file()) fail(s.target, errno);
    if (const int error = replace_with(s.temp, s.target)) fail(s.target, error);
  }
  s.committed = true;
}

void require_output_folder(const fs::path& target, const std::string& what) {
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(target.string() + ": " + what + " folder '" + folder.string() +
                     "' does not exist");
}

void write_file_atomically(const fs::path& target,
                           const std::function<void(std::ostream&)>& write) {
  StagedFile staged(target);
  staged.write(write);
  staged.commit();
}

}  // namespace ffd
