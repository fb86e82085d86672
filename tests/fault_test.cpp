// Faults (issue #13, item 8): a run killed by SIGKILL at any moment leaves no partial
// output and its inputs intact; a write that fails (a file size limit, a full disk) is
// exit 3 with one line naming the file and nothing left behind; StagedFile's own
// promises (commit replaces in one step, no commit leaves nothing); and the batch's
// results log keeps whole lines through a failed append or a torn one.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "batch/results_log.h"
#include "test_meshes.h"

namespace ffd {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Staging = StagedFile::Staging;
using test::files_in;
using test::read_file;
using test::temp_folder;
using test::write_file;

const std::string kOld = "the output of an earlier run, to be replaced whole or not at all\n";

// Whether `folder`'s file system has unnamed files (O_TMPFILE), which the promise about
// kills rests on; where it has none, StagedFile falls back to a named temporary file.
bool has_unnamed_files(const std::string& folder) {
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

ino_t inode_of(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? st.st_ino : 0;
}

// Starts `ffdtool args...` with stdout to /dev/null and stderr to `err_path`; with
// `max_file_bytes` > 0, under that file size limit with SIGXFSZ ignored, so that a write
// past it fails with EFBIG instead of killing the process.
pid_t start_tool(const std::vector<std::string>& args, const std::string& err_path, rlim_t max_file_bytes = 0) {
  std::vector<std::string> all = {FFD_TOOL};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {  // async-signal-safe calls only, up to exec
    const int null = ::open("/dev/null", O_WRONLY);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null < 0 || err < 0 || ::dup2(null, 1) < 0 || ::dup2(err, 2) < 0) ::_exit(126);
    if (max_file_bytes > 0) {
      ::signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{max_file_bytes, max_file_bytes};
      if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(126);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits for `pid`: its exit code, or minus the signal that ended it.
int wait_for(pid_t pid) {
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1000;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// What the open files of `pid` inside `folder` are (the targets of /proc/PID/fd links).
std::vector<std::string> files_open_in(pid_t pid, const std::string& folder) {
  std::vector<std::string> open;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const std::string target = fs::read_symlink(entry.path(), ec).string();
    if (!ec && target.rfind(folder + "/", 0) == 0) open.push_back(target);
  }
  return open;
}

// ---------------------------------------------------------------------------------------
// Killed runs

// in/big.obj, a grid of 361,201 vertices (20 MB of OBJ); s.json, which saves it as
// out/mid.obj; the run's output out/out.obj, there from before; and its stats.
struct KillCase {
  std::string dir, input, script, out, target;
  std::string input_bytes, script_bytes;
  std::string mid, out_obj;  // what a complete run writes

  explicit KillCase(const std::string& name) : dir(fs::canonical(temp_folder(name)).string()) {
    input = dir + "/in/big.obj";
    script = dir + "/in/s.json";
    out = dir + "/out";
    target = out + "/out.obj";
    fs::create_directories(dir + "/in");
    fs::create_directories(out);
    write_file(input, test::grid_obj(600));
    write_file(script, R"({"version": 1, "steps": [{"op": "save", "path": "mid.obj"}]})");
    input_bytes = read_file(input);
    script_bytes = read_file(script);
    reset();
  }
  std::vector<std::string> args() const {
    return {"run", input, script, "-o", target, "--stats", out + "/stats.json", "--quiet"};
  }
  // Back to the state before a run: only the earlier out.obj.
  void reset() const {
    for (const std::string& name : files_in(out)) fs::remove(out + "/" + name);
    write_file(target, kOld);
  }
};

// After a kill: out/ holds out.obj as it was before or whole as a complete run writes it,
// mid.obj and stats.json missing or whole, and nothing else; the inputs are unchanged.
void expect_whole_or_nothing(const KillCase& c, const std::string& when) {
  SCOPED_TRACE(when);
  for (const std::string& name : files_in(c.out)) {
    const std::string bytes = read_file(c.out + "/" + name);
    if (name == "out.obj")
      EXPECT_TRUE(bytes == kOld || bytes == c.out_obj) << "out.obj is neither the old file nor the new one";
    else if (name == "mid.obj")
      EXPECT_TRUE(bytes == c.mid) << "mid.obj is partial";
    else if (name == "stats.json")
      EXPECT_FALSE(nlohmann::json::parse(bytes, nullptr, false).is_discarded()) << "stats.json is partial";
    else
      ADD_FAILURE() << "left behind: " << name;
  }
  EXPECT_TRUE(files_in(c.out).count("out.obj"));
  EXPECT_TRUE(read_file(c.input) == c.input_bytes) << "the input mesh changed";
  EXPECT_EQ(read_file(c.script), c.script_bytes);
}

// Starts a run, waits until it has `writing` files open in out/ (each still without a
// name: the files it is writing), checks out/ still holds only out.obj, and kills it.
void kill_while_writing(const KillCase& c, std::size_t writing) {
  const pid_t pid = start_tool(c.args(), c.dir + "/stderr");
  std::vector<std::string> open;
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(20);
  while ((open = files_open_in(pid, c.out)).size() < writing && Clock::now() < give_up) {
    if (::waitpid(pid, nullptr, WNOHANG) == pid) FAIL() << "the run ended before it wrote " << writing << " files";
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  ::kill(pid, SIGKILL);
  EXPECT_EQ(wait_for(pid), -SIGKILL);
  ASSERT_GE(open.size(), writing) << "the run never had " << writing << " files open in " << c.out;
  for (const std::string& file : open)
    EXPECT_NE(file.find(" (deleted)"), std::string::npos) << "a file being written has a name: " << file;
  SCOPED_TRACE("killed while writing file " + std::to_string(writing));
  EXPECT_EQ(files_in(c.out), std::set<std::string>{"out.obj"});
  EXPECT_TRUE(read_file(c.target) == kOld) << "the earlier out.obj changed";
  expect_whole_or_nothing(c, "killed while writing");
}

// A run killed while it writes, and at five moments spread over a whole run's time
// (reading, saving, writing, committing), leaves out/ as it was or with whole files only.
TEST(Faults, KillAtAnyMomentLeavesNoPartialOutput) {
  KillCase c("kill");
  if (!has_unnamed_files(c.out)) GTEST_SKIP() << c.out << ": no O_TMPFILE here; a kill may leave a named temp file";
  const Clock::time_point start = Clock::now();
  ASSERT_EQ(wait_for(start_tool(c.args(), c.dir + "/stderr")), 0) << read_file(c.dir + "/stderr");
  const double run_s = std::chrono::duration<double>(Clock::now() - start).count();
  c.mid = read_file(c.out + "/mid.obj");
  c.out_obj = read_file(c.target);
  ASSERT_TRUE(c.mid == c.out_obj) << "mid.obj and out.obj differ";
  ASSERT_GT(c.mid.size(), std::size_t{10} << 20);
  c.reset();

  for (std::size_t writing : {std::size_t{1}, std::size_t{2}}) {  // mid.obj, then out.obj too
    kill_while_writing(c, writing);
    c.reset();
  }
  std::size_t before_commit = 0;
  for (double fraction : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const pid_t pid = start_tool(c.args(), c.dir + "/stderr");
    std::this_thread::sleep_for(std::chrono::duration<double>(fraction * run_s));
    ::kill(pid, SIGKILL);
    wait_for(pid);  // killed, or done already on a loaded machine
    expect_whole_or_nothing(c, "killed at " + std::to_string(fraction) + " of " + std::to_string(run_s) + " s");
    before_commit += read_file(c.target) == kOld;
    c.reset();
  }
  RecordProperty("run_ms", static_cast<int>(1000 * run_s));
  RecordProperty("timed_kills_before_commit", static_cast<int>(before_commit));
}

// ---------------------------------------------------------------------------------------
// Failed writes

// A file size limit stands in for a full disk: the run's output, or a save mid-script,
// that cannot be written is exit 3 with one line naming it, and out/ is as it was.
TEST(Faults, FileSizeLimitIsExitThreeAndLeavesNothing) {
  const std::string dir = fs::canonical(temp_folder("fsize")).string();
  write_file(dir + "/grid.obj", test::grid_obj(100));
  fs::create_directories(dir + "/out");
  const std::string lattice = R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {lattice, "out.obj"}, {lattice + R"(, {"op": "save", "path": "mid.obj"})", "mid.obj"}};
  for (const auto& [steps, failing] : cases) {
    SCOPED_TRACE(failing);
    write_file(dir + "/s.json", R"({"version": 1, "steps": [)" + steps + "]}");
    write_file(dir + "/out/out.obj", kOld);
    const pid_t pid = start_tool({"run", dir + "/grid.obj", dir + "/s.json", "-o", dir + "/out/out.obj", "--stats",
                                  dir + "/out/stats.json", "--quiet"},
                                 dir + "/stderr", 64 << 10);
    EXPECT_EQ(wait_for(pid), 3);
    EXPECT_EQ(read_file(dir + "/stderr"),
              "ffdtool: error: " + dir + "/out/" + failing + ": cannot write: File too large\n");
    EXPECT_EQ(files_in(dir + "/out"), std::set<std::string>{"out.obj"});
    EXPECT_EQ(read_file(dir + "/out/out.obj"), kOld);
  }
}

// A tmpfs of 1 MiB, mounted for the test, is a real full disk (skipped where mounting is
// not allowed): exit 3, one line, out.obj as it was, and every block free again.
TEST(Faults, FullDiskIsExitThreeAndLeavesNothing) {
  const std::string dir = fs::canonical(temp_folder("full_disk")).string();
  const std::string disk = dir + "/disk";
  fs::create_directories(disk);
  if (::geteuid() != 0 || ::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  struct Unmount {
    std::string at;
    ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
  } unmount{disk};
  write_file(dir + "/grid.obj", test::grid_obj(200));  // about 3 MB as output
  write_file(dir + "/s.json", R"({"version": 1, "steps": [{"op": "lattice", "name": "b", "cells": [4, 4, 4]}]})");
  write_file(disk + "/out.obj", kOld);
  struct statvfs before {}, after {};
  ASSERT_EQ(::statvfs(disk.c_str(), &before), 0);
  const pid_t pid = start_tool({"run", dir + "/grid.obj", dir + "/s.json", "-o", disk + "/out.obj", "--stats",
                                disk + "/stats.json", "--quiet"},
                               dir + "/stderr");
  EXPECT_EQ(wait_for(pid), 3);
  EXPECT_EQ(read_file(dir + "/stderr"),
            "ffdtool: error: " + disk + "/out.obj: cannot write: No space left on device\n");
  EXPECT_EQ(files_in(disk), std::set<std::string>{"out.obj"});
  EXPECT_EQ(read_file(disk + "/out.obj"), kOld);
  ASSERT_EQ(::statvfs(disk.c_str(), &after), 0);
  EXPECT_EQ(after.f_bfree, before.f_bfree) << "blocks still in use after the failed run";
}

// ---------------------------------------------------------------------------------------
// StagedFile

// Lowers this process's file size limit (soft) for a scope, with SIGXFSZ ignored.
struct FileSizeLimit {
  rlimit saved{};
  struct sigaction saved_action {};
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved);
    const rlimit limit{bytes, saved.rlim_max};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &saved_action);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved);
    ::sigaction(SIGXFSZ, &saved_action, nullptr);
  }
};

// Commit puts a new file in the target's place in one step: before it the old file is
// untouched, after it a reader of the old file still reads it whole, and the folder holds
// the target alone. Also for a target that did not exist.
TEST(StagedFile, CommitReplacesTheTargetInOneStep) {
  for (Staging staging : {Staging::Auto, Staging::NamedTemp}) {
    const std::string dir = temp_folder("commit");
    const bool unnamed = staging == Staging::Auto && has_unnamed_files(dir);
    const std::string target = dir + "/mesh.obj", fresh = dir + "/fresh.obj";
    write_file(target, "old");
    const ino_t old_inode = inode_of(target);
    std::ifstream reader(target);
    StagedFile staged(target, staging), staged_fresh(fresh, staging);
    EXPECT_EQ(staged.write([](std::ostream& os) { os << "new content"; }), 11u);
    staged_fresh.write([](std::ostream& os) { os << "fresh"; });
    EXPECT_EQ(read_file(target), "old");
    EXPECT_EQ(staged.temp_path().empty(), unnamed);
    // The target alone, or the target and two named temp files.
    EXPECT_EQ(files_in(dir).size(), unnamed ? 1u : 3u);

    staged.commit();
    staged_fresh.commit();
    EXPECT_EQ(read_file(target), "new content");
    EXPECT_EQ(read_file(fresh), "fresh");
    EXPECT_NE(inode_of(target), old_inode) << "the old file was rewritten in place";
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(reader), {}), "old");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"fresh.obj", "mesh.obj"}));
  }
}

// Over a regular file commit exchanges the two names and removes the old file; over
// anything else it renames, so a target that is a directory is refused (and kept, with
// nothing left beside it), and a symbolic link is replaced by the file, not followed.
TEST(StagedFile, CommitOverADirectoryOrASymlinkIsARename) {
  for (Staging staging : {Staging::Auto, Staging::NamedTemp}) {
    const std::string dir = temp_folder("commit_kinds");
    fs::create_directory(dir + "/folder.obj");
    write_file(dir + "/folder.obj/inside", "kept");
    EXPECT_THROW(write_file_atomically(dir + "/folder.obj", [](std::ostream& os) { os << "new"; }), IoError);
    EXPECT_EQ(read_file(dir + "/folder.obj/inside"), "kept");
    EXPECT_EQ(files_in(dir), std::set<std::string>{"folder.obj"});

    write_file(dir + "/real.obj", "real");
    fs::create_symlink("real.obj", dir + "/link.obj");
    StagedFile staged(dir + "/link.obj", staging);
    staged.write([](std::ostream& os) { os << "new"; });
    staged.commit();
    EXPECT_FALSE(fs::is_symlink(dir + "/link.obj"));
    EXPECT_EQ(read_file(dir + "/link.obj"), "new");
    EXPECT_EQ(read_file(dir + "/real.obj"), "real");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"folder.obj", "link.obj", "real.obj"}));
  }
}

// A staged file dropped without commit, written or not, leaves the folder as it was;
// so does a writer that throws its own error, which passes through unchanged.
TEST(StagedFile, DestructionWithoutCommitLeavesNothing) {
  for (Staging staging : {Staging::Auto, Staging::NamedTemp}) {
    const std::string dir = temp_folder("no_commit");
    write_file(dir + "/mesh.obj", "old");
    {
      StagedFile written(dir + "/mesh.obj", staging), unwritten(dir + "/mesh.obj", staging);
      StagedFile other(dir + "/other.obj", staging);
      written.write([](std::ostream& os) { os << std::string(1 << 20, 'x'); });
      other.write([](std::ostream& os) { os << "other"; });
    }
    EXPECT_THROW(write_file_atomically(dir + "/mesh.obj", [](std::ostream& os) {
                   os << "half a mesh";
                   throw InputError("the writer's own error");
                 }),
                 InputError);
    EXPECT_EQ(files_in(dir), std::set<std::string>{"mesh.obj"});
    EXPECT_EQ(read_file(dir + "/mesh.obj"), "old");
  }
}

// A write that fails (EFBIG under a file size limit), in small pieces or in one large
// one, is IoError "target: cannot write: File too large", and the folder is as it was.
TEST(StagedFile, FailedWriteLeavesTheFolderUnchanged) {
  const FileSizeLimit limit(64 << 10);
  for (Staging staging : {Staging::Auto, Staging::NamedTemp})
    for (bool pieces : {true, false}) {
      const std::string dir = temp_folder("failed_write");
      const std::string target = dir + "/mesh.obj";
      write_file(target, "old");
      const auto fill = [pieces](std::ostream& os) {
        if (pieces)
          for (int i = 0; i < 100000; ++i) os << "v " << i << " 0.5 0.25\n";
        else
          os << std::string(4 << 20, 'x');
      };
      try {
        StagedFile staged(target, staging);
        staged.write(fill);
        ADD_FAILURE() << "no IoError";
      } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), target + ": cannot write: File too large");
      }
      EXPECT_THROW(write_file_atomically(target, fill), IoError);
      EXPECT_EQ(files_in(dir), std::set<std::string>{"mesh.obj"});
      EXPECT_EQ(read_file(target), "old");
    }
}

// More files waiting for commit than half the open-file limit (64 here, in a child
// process) are still all written and committed: past the budget they wait under
// temporary names instead of holding a descriptor each.
TEST(StagedFile, ManyWaitingFilesFitTheOpenFileLimit) {
  const std::string dir = temp_folder("many");
  constexpr int kFiles = 200;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit limit{64, 64};
    if (::setrlimit(RLIMIT_NOFILE, &limit) != 0) ::_exit(2);
    try {
      std::vector<StagedFile> staged;
      for (int i = 0; i < kFiles; ++i) {
        staged.emplace_back(dir + "/frame_" + std::to_string(i) + ".obj");
        staged.back().write([i](std::ostream& os) { os << "frame " << i << "\n"; });
      }
      for (StagedFile& file : staged) file.commit();
    } catch (const std::exception&) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  ASSERT_EQ(wait_for(pid), 0);
  EXPECT_EQ(files_in(dir).size(), static_cast<std::size_t>(kFiles));
  for (int i = 0; i < kFiles; ++i)
    EXPECT_EQ(read_file(dir + "/frame_" + std::to_string(i) + ".obj"), "frame " + std::to_string(i) + "\n");
}


// ---------------------------------------------------------------------------------------
// The batch's results log

ResultRecord result(const std::string& input, std::size_t padding = 0) {
  ResultRecord r;
  r["input"] = input;
  r["status"] = "ok";
  r["note"] = std::string(padding, 'x');
  return r;
}

// A last line cut short (a batch killed, or out of disk, while appending it) is skipped,
// so that --resume and report still read the log; a bad line elsewhere is an error.
TEST(ResultsLog, ATornLastLineIsSkipped) {
  const std::string dir = temp_folder("torn");
  const std::string whole = result("a.obj").dump() + "\n" + result("b.obj").dump() + "\n";
  const std::string last = result("c.obj").dump();
  write_file(dir + "/results.jsonl", whole + last.substr(0, last.size() / 2));
  const std::vector<ResultRecord> records = read_results(dir);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[1]["input"], "b.obj");
  write_file(dir + "/results.jsonl", whole + last);  // whole but for its newline: kept
  EXPECT_EQ(read_results(dir).size(), 3u);
  write_file(dir + "/results.jsonl", last.substr(0, 10) + "\n" + whole);
  test::expect_input_error([&] { read_results(dir); }, dir + "/results.jsonl:1: ", {"not a results record"});
}

// An append that fails (EFBIG past a file size limit, after a short write) is cut off
// again: the log keeps whole lines only, and later appends go on from there.
TEST(ResultsLog, AFailedAppendLeavesWholeLines) {
  const std::string dir = temp_folder("failed_append");
  const std::string path = dir + "/results.jsonl";
  ResultsLog log(path, {result("a.obj")});
  log.append(result("b.obj"));
  const std::string before = read_file(path);
  {
    const FileSizeLimit limit(before.size() + 100);
    try {
      log.append(result("c.obj", 1000));
      ADD_FAILURE() << "no IoError";
    } catch (const IoError& e) {
      EXPECT_EQ(std::string(e.what()), path + ": cannot write: File too large");
    }
  }
  EXPECT_EQ(read_file(path), before);
  log.append(result("d.obj"));
  const std::vector<ResultRecord> records = read_results(dir);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[2]["input"], "d.obj");
}

// A new log (a --resume batch's, with the records it carries over) replaces the earlier
// one in one step rather than truncating it first: until then the earlier one is whole.
TEST(ResultsLog, ANewLogReplacesTheEarlierOneInOneStep) {
  const std::string dir = temp_folder("new_log");
  const std::string path = dir + "/results.jsonl";
  const std::string earlier = result("a.obj").dump() + "\n" + result("b.obj").dump() + "\n";
  write_file(path, earlier);
  const ino_t old_inode = inode_of(path);
  std::ifstream reader(path);
  ResultsLog log(path, {result("b.obj")});
  EXPECT_NE(inode_of(path), old_inode);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(reader), {}), earlier);
  EXPECT_EQ(read_file(path), result("b.obj").dump() + "\n");
  EXPECT_EQ(files_in(dir), std::set<std::string>{"results.jsonl"});
}

}  // namespace
}  // namespace ffd
