#include "batch/sha256.h"

#include <openssl/evp.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

#include "common/errors.h"

namespace ffd {

std::string sha256_file(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) throw IoError(At{path}, "cannot read it to hash it");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!context || EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) != 1) throw IoError("SHA-256: cannot start a digest");
  std::vector<char> buffer(1 << 20);
  while (is) {
    is.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (is.gcount() > 0) EVP_DigestUpdate(context.get(), buffer.data(), static_cast<std::size_t>(is.gcount()));
  }
  if (is.bad()) throw IoError(At{path}, "read failed while hashing it");
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(context.get(), digest, &length);
  std::string hex;
  char two[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(two, sizeof two, "%02x", digest[i]);
    hex += two;
  }
  return hex;
}

}  // namespace ffd
