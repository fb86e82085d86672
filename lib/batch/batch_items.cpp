#include "batch/batch_items.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/mesh_io.h"

namespace ffd {
namespace fs = std::filesystem;

namespace {

// One INPUT argument's mesh files.
void expand_input(const std::string& input, bool recursive, std::vector<std::string>& out) {
  if (!input.empty() && input[0] == '@') {
    const std::string list = input.substr(1);
    std::ifstream is(list);
    if (!is) throw InputError(At{list}, "cannot read the list of meshes");
    std::string line;
    for (std::size_t number = 1; std::getline(is, line); ++number) {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      if (!fs::is_regular_file(line)) throw InputError(At{list + ":" + std::to_string(number)}, "no such mesh file '" + line + "'");
      out.push_back(line);
    }
    return;
  }
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    for (const std::string& file : mesh_files_under(input, recursive)) out.push_back((fs::path(input) / file).string());
    return;
  }
  if (!fs::is_regular_file(input, ec)) throw InputError(At{input}, "no such file or folder");
  out.push_back(input);
}

// Each file's item name: its stem, or, for files that share their stem with another
// input, its file name with the extension's dot made '_' ("pig.off" -> "pig_off").
// \throw InputError naming both files when two names are still the same.
std::vector<std::string> item_names(const std::vector<std::string>& files) {
  std::map<std::string, std::size_t> stems;
  for (const std::string& file : files) ++stems[fs::path(file).stem().string()];
  std::vector<std::string> names;
  std::map<std::string, std::size_t> by_name;
  for (const std::string& file : files) {
    const fs::path path(file);
    const bool shared = stems[path.stem().string()] > 1;
    const std::string extension = path.extension().string();
    names.push_back(path.stem().string() + (shared && !extension.empty() ? "_" + extension.substr(1) : ""));
    const auto [seen, fresh] = by_name.emplace(names.back(), names.size() - 1);
    if (!fresh)
      throw InputError(At{file}, "has the same name '" + names.back() + "' as " + files[seen->second] +
                                     " (inputs that share a stem are named by their file name, the extension's dot "
                                     "made '_'), so both would be written to one output");
  }
  return names;
}

}  // namespace

std::vector<std::string> mesh_files_under(const std::string& folder, bool recursive) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError(At{folder}, "no such folder");
  std::vector<std::string> out;
  const auto add = [&](const fs::directory_entry& entry) {
    if (entry.is_regular_file(ec) && has_mesh_extension(entry.path()))
      out.push_back(fs::relative(entry.path(), folder, ec).generic_string());
  };
  if (recursive)
    for (const auto& entry : fs::recursive_directory_iterator(folder, ec)) add(entry);
  else
    for (const auto& entry : fs::directory_iterator(folder, ec)) add(entry);
  if (ec) throw InputError(At{folder}, "cannot list the folder: " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<BatchItem> batch_items(const std::vector<std::string>& inputs, bool recursive,
                                   const std::string& output_folder, const std::string& format) {
  std::vector<std::string> found, files;
  for (const std::string& input : inputs) expand_input(input, recursive, found);
  // Not the batch's own outputs, when the output folder lies inside an input folder.
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(output_folder, ec);
  for (const std::string& file : found) {
    const fs::path parent = fs::weakly_canonical(file, ec).parent_path();
    const auto [o, p] = std::mismatch(out.begin(), out.end(), parent.begin(), parent.end());
    if (o != out.end()) files.push_back(file);
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError("no mesh file among the inputs");
  for (const std::string& file : files) mesh_format(file);  // names the file when its extension is not a mesh format
  const std::vector<std::string> names = item_names(files);
  std::vector<BatchItem> items;
  for (std::size_t i = 0; i < files.size(); ++i) {
    BatchItem item;
    item.index = i;
    item.input = files[i];
    item.name = names[i];
    // Without --format an output keeps its input's file name: pig.off and pig.stl stay
    // apart by their extensions, and a folder compare pairs input and output.
    item.output = (fs::path(output_folder) / (format.empty() ? fs::path(item.input).filename().string()
                                                              : item.name + "." + format)).string();
    item.save_folder = (fs::path(output_folder) / item.name).string();
    if (fs::exists(item.output, ec) && fs::equivalent(item.output, item.input, ec))
      throw InputError(At{item.input}, "its output " + item.output + " would overwrite it");
    mesh_format(item.output);
    items.push_back(item);
  }
  return items;
}

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  long long index = -1, count = -1;
  if (slash == std::string::npos || !parse_integer(text.substr(0, slash), index) ||
      !parse_integer(text.substr(slash + 1), count) || count < 1 || index < 0 || index >= count)
    throw InputError("--shard: expected I/N with 0 <= I < N, found '" + text + "'");
  return {static_cast<std::size_t>(index), static_cast<std::size_t>(count), "--shard"};
}

namespace {

// An environment variable as a non-negative integer, or -1 when unset.
long long environment_integer(const char* name) {
  const char* value = std::getenv(name);
  if (!value || !*value) return -1;
  long long v = -1;
  if (!parse_integer(value, v) || v < 0) throw InputError(std::string(name) + ": expected a non-negative integer, found '" + value + "'");
  return v;
}

}  // namespace

std::optional<Shard> shard_from_environment() {
  const long long id = environment_integer("SLURM_ARRAY_TASK_ID");
  if (id >= 0) {
    const long long count = environment_integer("SLURM_ARRAY_TASK_COUNT");
    const long long first = std::max(0LL, environment_integer("SLURM_ARRAY_TASK_MIN"));
    const long long step = std::max(1LL, environment_integer("SLURM_ARRAY_TASK_STEP"));
    const long long index = (id - first) / step;
    if (count < 1 || index < 0 || index >= count)
      throw InputError("SLURM_ARRAY_TASK_ID " + std::to_string(id) + " is not a task of an array of " +
                       std::to_string(count) + " (SLURM_ARRAY_TASK_COUNT)");
    return Shard{static_cast<std::size_t>(index), static_cast<std::size_t>(count), "SLURM_ARRAY_TASK_ID"};
  }
  const long long completion = environment_integer("JOB_COMPLETION_INDEX");
  if (completion < 0) return std::nullopt;
  const long long count = environment_integer("FFD_SHARD_COUNT");
  if (count < 1 || completion >= count)
    throw InputError("JOB_COMPLETION_INDEX " + std::to_string(completion) +
                     " needs FFD_SHARD_COUNT, the Indexed Job's completions, above it");
  return Shard{static_cast<std::size_t>(completion), static_cast<std::size_t>(count), "JOB_COMPLETION_INDEX"};
}

std::vector<BatchItem> shard_items(const std::vector<BatchItem>& all, const Shard& shard) {
  std::vector<BatchItem> out;
  for (const BatchItem& item : all)
    if (item.index % shard.count == shard.index) out.push_back(item);
  return out;
}

}  // namespace ffd
