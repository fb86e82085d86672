// Whole small text files (scripts, selection files, files of positions) read at once.
#pragma once

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace ffd {

/// The bytes of the file at `path`, or nothing when it cannot be opened for reading.
inline std::optional<std::string> read_text_file(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) return std::nullopt;
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

}  // namespace ffd
