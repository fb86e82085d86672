// Output files written whole or not at all. The bytes go to an unnamed file in the
// target's folder (Linux O_TMPFILE) that gets a name only once it is complete, so a
// process killed at any moment (SIGKILL included) leaves no partial file behind, and a
// failed write (a full disk) leaves nothing at all. Where the folder's file system has no
// unnamed files, a named temporary file beside the target stands in (atomic_file.cpp
// says what that, and the one remaining window, can leave).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string>

namespace ffd {

/// A file being written for `target`: write() fills it, commit() puts it in place
/// (replacing any file there in one rename), and the destructor discards it if commit()
/// was never called. Several may be staged at once and committed together at the end.
class StagedFile {
public:
  /// How the bytes are held until commit(): Auto is an unnamed file where the file system
  /// has them, else NamedTemp, a file named `target.ffdtool-PID-N.tmp` (for tests).
  enum class Staging { Auto, NamedTemp };

  /// Opens the staging file. \throw IoError ("target: cannot write: reason") if it cannot.
  explicit StagedFile(std::filesystem::path target, Staging staging = Staging::Auto);
  ~StagedFile();
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  StagedFile(StagedFile&& other) noexcept;
  StagedFile& operator=(StagedFile&& other) noexcept;

  /// Writes the file's whole content through `fill` (a buffered binary stream over the
  /// staging file); returns the bytes written. Call once.
  /// \throw IoError ("target: cannot write: No space left on device") if a write fails.
  std::size_t write(const std::function<void(std::ostream&)>& fill);
  /// Puts the written file in place of the target. \throw IoError if that fails, leaving
  /// the target as it was.
  void commit();

  const std::filesystem::path& target() const;
  /// The name the bytes are under until commit(); empty while they have none (unnamed).
  const std::filesystem::path& temp_path() const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Checks that `target`'s folder exists; throws InputError naming `what` otherwise.
void require_output_folder(const std::filesystem::path& target, const std::string& what);

/// Writes `target` whole through `write` (which fills a binary stream), or throws
/// IoError and leaves nothing behind.
void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(std::ostream&)>& write);

}  // namespace ffd
