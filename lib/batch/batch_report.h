// `ffdtool report OUTDIR`: every results file of a batch (all its shards) in one summary.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ffd {

struct BatchReport {
  struct Failure {
    std::string input;
    int exit = 0;
    std::string error;
  };
  struct Timing {
    std::string input;
    double ms = 0;
  };
  std::size_t ok = 0, failed = 0, skipped = 0;
  std::vector<Failure> failures;  // by input
  double total_ms = 0, median_ms = 0;  // over the items run (ok or failed), not skipped ones
  std::vector<Timing> slowest;    // the 5 slowest items run, slowest first
};

/// The report of the results files in `folder`. \throw InputError if there are none, or
/// naming the file and line of one that is not a record.
BatchReport batch_report(const std::string& folder);

/// As a few lines of text: counts, failures, times, the slowest.
std::string report_text(const BatchReport& report);

/// The same as JSON.
nlohmann::ordered_json report_json(const BatchReport& report);

}  // namespace ffd
