#include "batch/batch_report.h"

#include <algorithm>
#include <cstdio>

#include "batch/results_log.h"
#include "common/errors.h"
#include "common/numbers.h"

namespace ffd {

BatchReport batch_report(const std::string& folder) {
  const std::vector<ResultRecord> records = read_results(folder);
  if (records.empty()) throw InputError(At{folder}, "no results*.jsonl with any record here");
  BatchReport report;
  std::vector<BatchReport::Timing> timings;
  for (const ResultRecord& r : records) {
    const std::string status = r.value("status", "");
    const std::string input = r["input"].get<std::string>();
    if (status == "skipped") {
      ++report.skipped;
      continue;
    }
    if (status == "ok")
      ++report.ok;
    else {
      ++report.failed;
      report.failures.push_back({input, r.value("exit", 0), r.value("error", "")});
    }
    timings.push_back({input, r.value("ms", 0.0)});
  }
  std::sort(report.failures.begin(), report.failures.end(),
            [](const auto& a, const auto& b) { return a.input < b.input; });
  for (const auto& t : timings) report.total_ms += t.ms;
  std::sort(timings.begin(), timings.end(), [](const auto& a, const auto& b) {
    return a.ms != b.ms ? a.ms > b.ms : a.input < b.input;
  });
  if (!timings.empty()) {
    const std::size_t n = timings.size();
    report.median_ms = n % 2 ? timings[n / 2].ms : (timings[n / 2 - 1].ms + timings[n / 2].ms) / 2;
  }
  timings.resize(std::min<std::size_t>(5, timings.size()));
  report.slowest = timings;
  return report;
}

std::string report_text(const BatchReport& report) {
  char line[512];
  std::string out;
  std::snprintf(line, sizeof line, "meshes   %s ok, %s failed, %s skipped\n", format_count(report.ok).c_str(),
                format_count(report.failed).c_str(), format_count(report.skipped).c_str());
  out += line;
  std::snprintf(line, sizeof line, "time     %.1f s in all, median %.1f ms per mesh\n", report.total_ms / 1000,
                report.median_ms);
  out += line;
  for (const auto& f : report.failures) out += "failed   " + f.input + " (exit " + std::to_string(f.exit) + "): " + f.error + "\n";
  for (const auto& t : report.slowest) {
    std::snprintf(line, sizeof line, "slowest  %10.1f ms  %s\n", t.ms, t.input.c_str());
    out += line;
  }
  return out;
}

nlohmann::ordered_json report_json(const BatchReport& report) {
  nlohmann::ordered_json j;
  j["counts"] = {{"ok", report.ok}, {"failed", report.failed}, {"skipped", report.skipped}};
  j["failures"] = nlohmann::ordered_json::array();
  for (const auto& f : report.failures) j["failures"].push_back({{"input", f.input}, {"exit", f.exit}, {"error", f.error}});
  j["total_ms"] = report.total_ms;
  j["median_ms"] = report.median_ms;
  j["slowest"] = nlohmann::ordered_json::array();
  for (const auto& t : report.slowest) j["slowest"].push_back({{"input", t.input}, {"ms", t.ms}});
  return j;
}

}  // namespace ffd
