#include "script/script.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/errors.h"
#include "common/text_file.h"
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
  } catch (const json::exception& e) {  // parse errors, and numbers past double's range (out_of_range)
    // nlohmann's message carries "at line L, column C"; keep that part.
    std::string what = e.what();
    const auto colon = what.find("] ");
    throw InputError(At{path}, "invalid JSON: " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
  if (auto error = check_schema(script_schema(), doc, &script.resolved))
    throw InputError(At{path + ": " + (error->path.empty() ? "/" : error->path)}, error->message);

  ScriptChecks checks(script.path);
  script.allow_inverted = script.resolved.value("allow_inverted", false);
  const json& steps = script.resolved["steps"];
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const ScriptPlace place{script.path, script.folder, "/steps/" + std::to_string(i)};
    const OpInfo* op = find_op(steps[i]["op"].get<std::string>());
    if (!op) throw std::logic_error("op " + steps[i]["op"].dump() + " is in the schema but not in the op table");
    std::unique_ptr<Step> step = op->parse(steps[i], place);
    step->check(checks);
    for (const OutputFile& file : step->outputs()) checks.check_output_path(file, place.pointer + file.key);
    script.steps.push_back(std::move(step));
  }
  return script;
}

Script load_script(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(At{path}, "no such file");
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw InputError(At{path}, "cannot open for reading");
  return parse_script(*text, path);
}

}  // namespace ffd
