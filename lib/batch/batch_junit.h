// A batch as a JUnit XML report (`batch --junit`, `report --junit`): one test case per
// mesh, for CI systems that show test results.
#pragma once

#include <string>
#include <vector>

#include "batch/results_log.h"
#include "common/junit.h"

namespace ffd {

/// The suite "ffdtool batch OUTDIR" of a batch's results records (those of one batch, or
/// every shard's as read_results gives them), one case per record, sorted by input: an
/// ok mesh passes, a failed one fails with its error line as the message (and the exit
/// code with it as the text), a mesh skipped by --resume is skipped; each with its time
/// (the record's ms). The suite's seconds are the sum of the cases' (the caller that knows
/// the wall time sets it); no timestamp or hostname.
JUnitSuite batch_junit(const std::vector<ResultRecord>& records, const std::string& output_folder);

}  // namespace ffd
