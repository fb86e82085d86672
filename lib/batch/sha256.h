// SHA-256 digests of files (OpenSSL's EVP), for the batch's results log and --resume.
#pragma once

#include <string>

namespace ffd {

/// The SHA-256 of the file at `path` as 64 lowercase hex digits. \throw IoError if it
/// cannot be read.
std::string sha256_file(const std::string& path);

}  // namespace ffd
