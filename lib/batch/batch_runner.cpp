#include "batch/batch.h"

#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "batch/batch_junit.h"
#include "batch/child_process.h"
#include "batch/results_log.h"
#include "batch/sha256.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "common/timer.h"
#include "script/script.h"

namespace ffd {
namespace fs = std::filesystem;

namespace {

// What a batch will do, worked out before any item runs.
struct Plan {
  BatchOptions options;
  std::string script_sha;
  std::vector<std::string> saves;  // the script's outputs, relative to an item's save folder
  std::size_t total = 0;           // items of all shards
  std::optional<Shard> shard;
  std::vector<BatchItem> items;    // this shard's
  std::size_t jobs = 1, threads = 1;
  std::string program;             // what runs an item
  std::string temp;                // the children's stats and stderr
};

// The cores this process may run on (its CPU affinity: what Slurm or taskset gave it),
// not the machine's.
std::size_t available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return static_cast<std::size_t>(CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

// --junit FILE: its folder exists, and it is neither the script nor an input.
void check_junit_path(const BatchOptions& options, const std::vector<BatchItem>& items) {
  require_output_folder(options.junit, "--junit");
  std::error_code ec;
  if (!fs::exists(options.junit, ec)) return;
  const auto same = [&](const std::string& file) { return fs::equivalent(options.junit, file, ec); };
  if (same(options.script)) throw InputError(At{options.junit}, "--junit would overwrite the script");
  for (const BatchItem& item : items)
    if (same(item.input)) throw InputError(At{options.junit}, "--junit would overwrite the input mesh " + item.input);
}

Plan plan_batch(const BatchOptions& options) {
  Plan plan;
  plan.options = options;
  const Script script = load_script(options.script);  // a bad script fails before any work
  for (const auto& step : script.steps)
    for (const OutputFile& file : step->outputs()) plan.saves.push_back(file.path);
  std::error_code ec;
  fs::create_directories(options.output_folder, ec);
  if (!fs::is_directory(options.output_folder, ec))
    throw InputError(At{options.output_folder}, "cannot create the output folder");
  const std::vector<BatchItem> all = batch_items(options.inputs, options.recursive, options.output_folder, options.format);
  if (!options.junit.empty()) check_junit_path(options, all);
  plan.total = all.size();
  plan.shard = options.shard ? options.shard : shard_from_environment();
  plan.items = plan.shard ? shard_items(all, *plan.shard) : all;
  const std::size_t cores = available_cores();
  plan.jobs = options.jobs ? options.jobs : cores;
  const std::size_t running = std::max<std::size_t>(1, std::min(plan.jobs, plan.items.size()));
  plan.threads = std::max<std::size_t>(1, cores / running);  // the cores shared by the meshes at once
  plan.program = options.runner.empty() ? "/proc/self/exe" : options.runner;
  plan.script_sha = sha256_file(options.script);
  return plan;
}

// The message of an item's "ffdtool: error: ..." line, or what else ended it (with the
// last line it wrote, if any: a loader that could not map a library, say).
std::string error_message(const std::string& stderr_path, const ChildEnd& end) {
  std::ifstream is(stderr_path);
  std::string line, message, last;
  const std::string prefix = "ffdtool: error: ";
  while (std::getline(is, line)) {
    if (line.rfind(prefix, 0) == 0) message = line.substr(prefix.size());
    if (!line.empty()) last = line;
  }
  if (end.reason.empty() && !message.empty()) return message;
  const std::string reason = end.reason.empty() ? "exited with code " + std::to_string(end.exit) : end.reason;
  return last.empty() || !message.empty() ? reason : reason + ": " + last;
}

// The results line of a finished item.
ResultRecord record_of(const Plan& plan, const BatchItem& item, const ChildEnd& end, double ms,
                       const std::string& stats_path, const std::string& stderr_path) {
  ResultRecord r;
  r["input"] = item.input;
  r["output"] = item.output;
  r["status"] = end.exit == 0 ? "ok" : "error";
  r["exit"] = end.exit;
  r["error"] = end.exit == 0 ? "" : error_message(stderr_path, end);
  r["ms"] = ms;
  r["stats"] = nullptr;
  if (end.exit == 0) {
    std::ifstream is(stats_path);
    const ResultRecord stats = ResultRecord::parse(is, nullptr, false);
    if (!stats.is_discarded() && stats.contains("steps")) r["stats"] = stats["steps"];
  }
  r["sha256"] = {{"input", sha256_file(item.input)},
                 {"script", plan.script_sha},
                 {"output", end.exit == 0 ? ResultRecord(sha256_file(item.output)) : ResultRecord()}};
  return r;
}

// Removes what a failed item left: the named temporary files a killed child can leave
// (common/atomic_file.cpp: killed between link and rename, or on a file system without
// unnamed files), and the save folders made for it that stayed empty.
void remove_leftovers(const BatchItem& item, pid_t pid) {
  const std::string mark = ".ffdtool-" + std::to_string(pid) + "-";
  std::error_code ec;
  const auto clean = [&](const fs::path& entry) {
    const std::string name = entry.filename().string();
    if (name.find(mark) != std::string::npos && entry.extension() == ".tmp") fs::remove(entry, ec);
  };
  for (const auto& entry : fs::directory_iterator(fs::path(item.output).parent_path(), ec)) clean(entry.path());
  if (!fs::is_directory(item.save_folder, ec)) return;
  std::vector<fs::path> folders = {item.save_folder};
  for (const auto& entry : fs::recursive_directory_iterator(item.save_folder, ec)) {
    clean(entry.path());
    if (entry.is_directory(ec)) folders.push_back(entry.path());
  }
  // The folders made for its saves, if they stayed empty: deepest first.
  std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) { return a.string() > b.string(); });
  for (const fs::path& folder : folders)
    if (fs::is_empty(folder, ec)) fs::remove(folder, ec);
}

// Whether a record from an earlier batch says `item` is done with this input and script.
bool done_before(const Plan& plan, const BatchItem& item, const std::map<std::string, ResultRecord>& earlier) {
  const auto it = earlier.find(item.input);
  if (it == earlier.end()) return false;
  const ResultRecord& r = it->second;
  const std::string status = r.value("status", "");
  std::error_code ec;
  if ((status != "ok" && status != "skipped") || !fs::is_regular_file(item.output, ec) || !r.contains("sha256"))
    return false;
  const ResultRecord& sha = r["sha256"];
  return sha.value("script", "") == plan.script_sha && sha.value("input", "") == sha256_file(item.input) &&
         sha["output"].is_string() && sha["output"] == sha256_file(item.output);
}

}  // namespace

namespace {

// An item whose process runs.
struct Running {
  BatchItem item;
  Child child;
  std::string stats_path, stderr_path;
};

// The items' processes, at most plan.jobs at once, and their results as they finish.
class ItemPool {
public:
  ItemPool(const Plan& plan, ResultsLog& log, Progress& progress) : plan_(plan), log_(log), progress_(progress) {}

  void start(const BatchItem& item) {
    std::error_code ec;
    for (const std::string& save : plan_.saves)
      fs::create_directories((fs::path(item.save_folder) / save).parent_path(), ec);
    Running r;
    r.item = item;
    r.stats_path = plan_.temp + "/" + std::to_string(item.index) + ".stats.json";
    r.stderr_path = plan_.temp + "/" + std::to_string(item.index) + ".stderr";
    std::vector<std::string> args = {"run", item.input, plan_.options.script, "-o", item.output,
                                     "--stats", r.stats_path, "--quiet", "--threads", std::to_string(plan_.threads)};
    if (!plan_.saves.empty()) args.insert(args.end(), {"--save-dir", item.save_folder});
    r.child = start_child(plan_.program, args, r.stderr_path, plan_.options.max_memory);
    progress_.item_start(item.input);
    running_.push_back(std::move(r));
  }

  bool full() const { return running_.size() >= plan_.jobs; }
  bool empty() const { return running_.empty(); }

  /// Collects every item that ended (killing those past the timeout); false if none did.
  bool reap() {
    bool any = false;
    for (std::size_t i = 0; i < running_.size();) {
      int status = 0;
      bool timed_out = false;
      pid_t done = ::waitpid(running_[i].child.pid, &status, WNOHANG);
      if (done == 0 && plan_.options.timeout_s > 0 && seconds(running_[i]) > plan_.options.timeout_s) {
        ::kill(running_[i].child.pid, SIGKILL);
        done = ::waitpid(running_[i].child.pid, &status, 0);
        timed_out = true;
      }
      if (done == 0) {
        ++i;
        continue;
      }
      finish(running_[i], child_end(status, timed_out, plan_.options.timeout_s));
      running_.erase(running_.begin() + static_cast<long>(i));
      any = true;
    }
    return any;
  }

  int worst = 0;
  std::size_t ok = 0, failed = 0;
  std::vector<ResultRecord> records;  // of the items that ended, in the order they did

private:
  static double seconds(const Running& r) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - r.child.started).count();
  }

  void finish(const Running& r, const ChildEnd& end) {
    const double ms = 1000 * seconds(r);
    if (end.exit != 0) remove_leftovers(r.item, r.child.pid);
    const ResultRecord record = record_of(plan_, r.item, end, ms, r.stats_path, r.stderr_path);
    log_.append(record);
    records.push_back(record);
    worst = std::max(worst, end.exit);
    const std::string message = record["error"].get<std::string>();
    progress_.item_end(r.item.input, end.exit == 0 ? "ok" : "error", ms, message);
    if (end.exit == 0) {
      ++ok;
    } else {
      ++failed;
      const bool placed = message.find(r.item.input) != std::string::npos;
      progress_.message("ffdtool: error: " + (placed ? std::string() : r.item.input + ": ") + message);
    }
  }

  const Plan& plan_;
  ResultsLog& log_;
  Progress& progress_;
  std::vector<Running> running_;
};

// The header line: what this process is doing.
void announce(const Plan& plan, std::size_t skipped, Progress& progress) {
  std::string shard;
  if (plan.shard)
    shard = ", shard " + std::to_string(plan.shard->index) + "/" + std::to_string(plan.shard->count) + " (" +
            plan.shard->source + ")";
  char line[512];
  std::snprintf(line, sizeof line, "ffdtool batch: %s meshes%s: %s here (%s done before), %zu at once x %zu threads",
                format_count(plan.total).c_str(), shard.c_str(), format_count(plan.items.size()).c_str(),
                format_count(skipped).c_str(), plan.jobs, plan.threads);
  progress.message(line);
  if (plan.shard)
    progress.event(JsonEvent("shard").integer("index", static_cast<long long>(plan.shard->index))
                       .integer("count", static_cast<long long>(plan.shard->count))
                       .text("source", plan.shard->source));
}

// Records of earlier batches by input, for --resume.
std::map<std::string, ResultRecord> earlier_records(const Plan& plan) {
  std::map<std::string, ResultRecord> out;
  if (!plan.options.resume) return out;
  for (ResultRecord& r : read_results(plan.options.output_folder)) {
    const std::string input = r["input"].get<std::string>();
    out[input] = std::move(r);
  }
  return out;
}

// The JUnit report of a batch's items (--junit): those skipped and those that ended, its
// wall time and start.
void write_batch_junit(const Plan& plan, const std::vector<ResultRecord>& skipped, const ItemPool& pool,
                       double ms, std::time_t started) {
  std::vector<ResultRecord> records = skipped;
  records.insert(records.end(), pool.records.begin(), pool.records.end());
  JUnitSuite suite = batch_junit(records, plan.options.output_folder);
  suite.seconds = ms / 1000;
  suite.timestamp = junit_timestamp(started);
  suite.hostname = junit_hostname();
  write_junit(plan.options.junit, suite);
}

// Runs the pending items, at most plan.jobs at once. With --junit, the items that ended
// are reported even when a failure (of the log, of starting a process) stops the batch.
void run_items(const Plan& plan, const std::vector<BatchItem>& pending, const std::vector<ResultRecord>& skipped,
               ItemPool& pool, const Stopwatch& clock, std::time_t started) {
  try {
    for (std::size_t next = 0; next < pending.size() || !pool.empty();) {
      while (!pool.full() && next < pending.size()) pool.start(pending[next++]);
      if (!pool.reap()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } catch (const std::exception&) {
    if (!plan.options.junit.empty()) {
      try {
        write_batch_junit(plan, skipped, pool, clock.ms(), started);
      } catch (const std::exception&) {  // the first failure is the one to report
      }
    }
    throw;
  }
  if (!plan.options.junit.empty()) write_batch_junit(plan, skipped, pool, clock.ms(), started);
}

}  // namespace

int run_batch(const BatchOptions& options) {
  Stopwatch clock;
  const std::time_t started = std::time(nullptr);
  Plan plan = plan_batch(options);
  const std::map<std::string, ResultRecord> earlier = earlier_records(plan);
  std::vector<BatchItem> pending;
  std::vector<ResultRecord> skipped;
  for (const BatchItem& item : plan.items) {
    if (!done_before(plan, item, earlier)) {
      pending.push_back(item);
      continue;
    }
    ResultRecord r = earlier.at(item.input);
    r["status"] = "skipped";
    r["ms"] = 0;
    skipped.push_back(std::move(r));
  }
  Progress progress(options.progress);
  announce(plan, skipped.size(), progress);
  const bool sharded = plan.shard.has_value();
  ResultsLog log((fs::path(options.output_folder) /
                  results_file_name(sharded, sharded ? plan.shard->index : 0, sharded ? plan.shard->count : 1))
                     .string(),
                 skipped);  // replaces the earlier log in one step: killed before, it is kept whole
  progress.begin(plan.items.size());
  for (const ResultRecord& r : skipped) progress.item_end(r["input"].get<std::string>(), "skipped", 0);
  // The children's stats and stderr: node-local, per process, never in the output folder.
  plan.temp = (fs::temp_directory_path() / ("ffdtool-batch-" + std::to_string(::getpid()))).string();
  fs::create_directories(plan.temp);
  ItemPool pool(plan, log, progress);
  run_items(plan, pending, skipped, pool, clock, started);
  std::error_code ec;
  fs::remove_all(plan.temp, ec);
  progress.finish();
  char line[512];
  std::snprintf(line, sizeof line, "ffdtool batch: %zu ok, %zu failed, %zu skipped in %.1f s; results in %s", pool.ok,
                pool.failed, skipped.size(), clock.ms() / 1000, log.path().c_str());
  progress.message(line);
  return pool.worst;
}

}  // namespace ffd
