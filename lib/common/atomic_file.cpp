#include "common/atomic_file.h"

#include <atomic>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "common/errors.h"

namespace ffd {
namespace fs = std::filesystem;

StagedFile::StagedFile(fs::path target) : target_(std::move(target)) {
  // The pid keeps concurrent runs apart, the counter two staged writes of one path.
  static std::atomic<unsigned> counter{0};
  temp_ = target_;
  temp_ += ".ffdtool-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".tmp";
}

StagedFile::StagedFile(StagedFile&& other) noexcept
    : target_(std::move(other.target_)), temp_(std::move(other.temp_)), done_(other.done_) {
  other.done_ = true;
}

StagedFile::~StagedFile() {
  if (!done_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void StagedFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw IoError(At{target_.string()}, "cannot write: " + ec.message());
  done_ = true;
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
  {
    std::ofstream os(staged.temp_path(), std::ios::binary | std::ios::trunc);
    if (!os) throw IoError(At{target.string()}, "cannot open for writing");
    write(os);
    os.flush();
    if (!os) throw IoError(At{target.string()}, "write failed (disk full?)");
  }
  staged.commit();
}

}  // namespace ffd
