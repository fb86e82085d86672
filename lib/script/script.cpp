#include "script/script.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/errors.h"
#include "script/ops.h"
#include "script/schema.h"
#include "script/schema_check.h"
#include "script/script_checks.h"

namespace ffd {
using json = nlohmann::json;

Script parse_script(const std::string& text, const std::string& path) {
  Script script;
  script.path = path;
  script.folder = std::filesystem::path(path).parent_path().string();
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message carries "at line L, column C"; keep that part.
    std::string what = e.what();
    const auto colon = what.find("] ");
    throw InputError(path + ": invalid JSON: " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
  if (auto error = check_schema(script_schema(), doc, &script.resolved))
    throw InputError(path + ": " + (error->path.empty() ? "/" : error->path) + ": " + error->message);

  ScriptChecks checks(script.path, script.folder);
  const json& steps = script.resolved["steps"];
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const json& step = steps[i];
    find_op(step["op"].get<std::string>()).check(checks, step, "/steps/" + std::to_string(i));
  }
  return script;
}

Script load_script(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path + ": cannot open for reading");
  std::stringstream ss;
  ss << is.rdbuf();
  return parse_script(ss.str(), path);
}

}  // namespace ffd
