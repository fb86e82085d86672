// The batch's results log: one JSON line per item (results.jsonl, or
// results-I-of-N.jsonl for a shard), appended as items finish, and read back by
// --resume, `ffdtool report` and `report --junit`. A record is JSON because it holds
// the items' stats steps as lib/script's runner wrote them.
#pragma once

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ffd {

/// An item's line: input, output, status (ok | error | skipped), exit, error, ms, stats,
/// and the SHA-256 of the input, the script and the output.
using ResultRecord = nlohmann::ordered_json;

/// The results file of `shard` ("results.jsonl" unsharded, "results-I-of-N.jsonl").
std::string results_file_name(bool sharded, std::size_t index, std::size_t count);

/// Every record of every results file in `folder`, file by file in name order; a later
/// line for the same input replaces an earlier one. A file's last line that has no
/// newline and is not a record is the torn append of a batch killed (or out of disk)
/// while writing it, and is skipped. \throw InputError naming the file and line of any
/// other line that is not a record.
std::vector<ResultRecord> read_results(const std::string& folder);

/// Appends records to a results file, one write() per whole line, so that lines never
/// interleave; a failed append is cut off again, and a killed batch leaves at most a torn
/// last line (which read_results skips).
class ResultsLog {
public:
  /// Creates `path` holding `first` (the records carried over by --resume), replacing
  /// any file there in one step: a batch killed before that still has its earlier
  /// results. \throw IoError if it cannot.
  explicit ResultsLog(const std::string& path, const std::vector<ResultRecord>& first = {});
  ~ResultsLog();
  ResultsLog(const ResultsLog&) = delete;
  ResultsLog& operator=(const ResultsLog&) = delete;
  /// \throw IoError on a failed write.
  void append(const ResultRecord& record);
  const std::string& path() const { return path_; }

private:
  std::string path_;
  int fd_ = -1;
  std::size_t size_ = 0;  // the file's size: whole lines only
};

}  // namespace ffd
