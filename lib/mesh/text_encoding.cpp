#include "mesh/text_encoding.h"

#include "common/errors.h"

namespace ffd {

std::string wide_text_encoding(std::string_view bytes) {
  auto starts = [&](std::string_view prefix) { return bytes.substr(0, prefix.size()) == prefix; };
  // UTF-32LE's mark begins with UTF-16LE's, so the longer marks are tried first.
  if (starts(std::string_view("\xFF\xFE\0\0", 4))) return "UTF-32LE";
  if (starts(std::string_view("\0\0\xFE\xFF", 4))) return "UTF-32BE";
  if (starts("\xFF\xFE")) return "UTF-16LE";
  if (starts("\xFE\xFF")) return "UTF-16BE";
  if (bytes.size() < 4) return {};
  const bool z[4] = {bytes[0] == 0, bytes[1] == 0, bytes[2] == 0, bytes[3] == 0};
  if (!z[0] && z[1] && z[2] && z[3]) return "UTF-32LE";
  if (z[0] && z[1] && z[2] && !z[3]) return "UTF-32BE";
  if (!z[0] && z[1] && !z[2] && z[3]) return "UTF-16LE";
  if (z[0] && !z[1] && z[2] && !z[3]) return "UTF-16BE";
  return {};
}

std::string_view without_utf8_bom(std::string_view bytes) {
  return bytes.substr(0, 3) == "\xEF\xBB\xBF" ? bytes.substr(3) : bytes;
}

void refuse_wide_text(std::string_view bytes, const std::string& path) {
  const std::string encoding = wide_text_encoding(bytes);
  if (!encoding.empty())
    throw InputError(At{path}, encoding + " text is not supported; save the file as UTF-8 or ASCII");
}

}  // namespace ffd
