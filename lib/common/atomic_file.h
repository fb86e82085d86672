// Output files written whole or not at all: write to a temporary file beside the
// target, then rename over it. A failure leaves no partial file behind.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace ffd {

/// A file being written beside `target`; commit() renames it into place, the
/// destructor removes it if commit() was never called.
class StagedFile {
public:
  explicit StagedFile(std::filesystem::path target);
  ~StagedFile();
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  StagedFile(StagedFile&& other) noexcept;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temp_path() const { return temp_; }
  /// Renames the temporary file to the target. Throws IoError if that fails.
  void commit();

private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool done_ = false;
};

/// Checks that `target`'s folder exists; throws InputError naming `what` otherwise.
void require_output_folder(const std::filesystem::path& target, const std::string& what);

/// Writes `target` whole through `write` (which fills a binary ofstream), or throws
/// IoError and leaves nothing behind.
void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(std::ostream&)>& write);

}  // namespace ffd
