#include "script/point_file.h"

#include <cctype>

#include "common/errors.h"
#include "common/text_file.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

bool is_obj(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".obj";
}

/// Three finite numbers from tokens[first..]; `exact`: nothing may follow them.
bool read_xyz(const std::vector<std::string_view>& tokens, std::size_t first, bool exact, Eigen::Vector3d& p) {
  if (tokens.size() < first + 3 || (exact && tokens.size() != first + 3)) return false;
  for (int a = 0; a < 3; ++a)
    if (!parse_finite(tokens[first + static_cast<std::size_t>(a)], p[a])) return false;
  return true;
}

}  // namespace

std::vector<Eigen::Vector3d> read_point_file(const std::string& path) {
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw InputError(path + ": cannot read the file of positions");
  const bool obj = is_obj(path);
  LineScanner lines(*text);
  std::string_view line;
  std::vector<std::string_view> tokens;
  std::vector<Eigen::Vector3d> out;
  while (lines.next(line)) {
    split_tokens(line, tokens);
    if (tokens.empty() || (obj && tokens[0] != "v")) continue;
    Eigen::Vector3d p;
    if (!read_xyz(tokens, obj ? 1 : 0, !obj, p))
      throw InputError(place(path, lines.number()) +
                       (obj ? ": expected a vertex line 'v x y z' of finite numbers"
                            : ": expected one point 'x y z' (three finite numbers)"));
    out.push_back(p);
  }
  if (out.empty()) throw InputError(path + (obj ? ": the OBJ file has no 'v' line" : ": the file holds no point"));
  return out;
}

}  // namespace ffd
