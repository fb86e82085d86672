#include "batch/results_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/atomic_file.h"
#include "common/errors.h"

namespace ffd {
namespace fs = std::filesystem;

std::string results_file_name(bool sharded, std::size_t index, std::size_t count) {
  if (!sharded) return "results.jsonl";
  return "results-" + std::to_string(index) + "-of-" + std::to_string(count) + ".jsonl";
}

std::vector<ResultRecord> read_results(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("results", 0) == 0 && entry.path().extension() == ".jsonl") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  std::vector<ResultRecord> records;
  std::map<std::string, std::size_t> by_input;
  for (const std::string& file : files) {
    std::ifstream is(file);
    std::string line;
    for (std::size_t number = 1; std::getline(is, line); ++number) {
      if (line.empty()) continue;
      ResultRecord record = ResultRecord::parse(line, nullptr, false);
      if (record.is_discarded() || !record.is_object() || !record.contains("input") || !record["input"].is_string()) {
        if (is.eof()) break;  // a last line with no newline: a torn append
        throw InputError(At{file + ":" + std::to_string(number)}, "not a results record");
      }
      const auto [at, fresh] = by_input.emplace(record["input"].get<std::string>(), records.size());
      if (fresh)
        records.push_back(std::move(record));
      else
        records[at->second] = std::move(record);
    }
  }
  return records;
}

ResultsLog::ResultsLog(const std::string& path, const std::vector<ResultRecord>& first) : path_(path) {
  StagedFile staged(path);
  size_ = staged.write([&](std::ostream& os) {
    for (const ResultRecord& record : first) os << record.dump() << "\n";
  });
  staged.commit();
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) throw IoError(At{path}, std::string("cannot write: ") + std::strerror(errno));
}

ResultsLog::~ResultsLog() {
  if (fd_ >= 0) ::close(fd_);
}

void ResultsLog::append(const ResultRecord& record) {
  const std::string line = record.dump() + "\n";
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      if (done > 0) (void)!::ftruncate(fd_, static_cast<off_t>(size_));  // no torn line left
      throw IoError(At{path_}, std::string("cannot write: ") + std::strerror(error));
    }
    done += static_cast<std::size_t>(n);
  }
  size_ += done;
}

}  // namespace ffd
