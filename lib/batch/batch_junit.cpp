#include "batch/batch_junit.h"

#include <algorithm>
#include <filesystem>

namespace ffd {
namespace {

// The test case of one results record.
JUnitCase record_case(const ResultRecord& r) {
  JUnitCase c;
  c.name = r.value("input", "");
  c.classname = "ffdtool.batch";
  c.seconds = r.value("ms", 0.0) / 1000;
  const std::string status = r.value("status", "");
  if (status == "skipped") {
    c.outcome = JUnitCase::Outcome::Skipped;
    c.message = "done before with the same input and script (--resume)";
  } else if (status != "ok") {
    c.outcome = JUnitCase::Outcome::Failed;
    c.message = r.value("error", "");
    c.detail = "exit " + std::to_string(r.value("exit", 0)) + ": " + c.message;
  }
  return c;
}

}  // namespace

JUnitSuite batch_junit(const std::vector<ResultRecord>& records, const std::string& output_folder) {
  JUnitSuite suite;
  // The folder as written, without a trailing separator: "out/" and "out" name one suite.
  std::string folder = std::filesystem::path(output_folder).lexically_normal().string();
  while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
  suite.name = "ffdtool batch " + folder;
  for (const ResultRecord& r : records) suite.cases.push_back(record_case(r));
  std::sort(suite.cases.begin(), suite.cases.end(),
            [](const JUnitCase& a, const JUnitCase& b) { return a.name < b.name; });
  for (const JUnitCase& c : suite.cases) suite.seconds += c.seconds;
  return suite;
}

}  // namespace ffd
