// JUnit XML reports, the test-result format CI systems (Jenkins, GitLab, GitHub Actions'
// reporters, ...) read: one <testsuite> of <testcase>s, each passed, failed, in error or
// skipped. `ffdtool batch --junit` and `report --junit` give one case per mesh, `compare
// --junit` one per compared pair. tests/data/junit.xsd is the schema the output is
// checked against.
#pragma once

#include <ctime>
#include <string>
#include <vector>

namespace ffd {

/// One <testcase>.
struct JUnitCase {
  enum class Outcome { Passed, Failed, Error, Skipped };
  std::string name;       // a mesh's input path, or a compared pair's relative path
  std::string classname;  // "ffdtool.batch", "ffdtool.compare"
  double seconds = 0;
  Outcome outcome = Outcome::Passed;
  std::string message;    // one line: the failure's, the error's or the skip's reason
  std::string detail;     // the element's text body; may be empty
};

/// One <testsuite> inside <testsuites>; tests/failures/errors/skipped/time computed from the cases.
struct JUnitSuite {
  std::string name;       // e.g. "ffdtool batch s.json"
  double seconds = 0;     // wall time of the whole run
  std::string timestamp;  // ISO 8601 local time without zone (e.g. 2026-12-02T06:30:00), "" to leave it out
  std::string hostname;   // "" to leave it out
  std::vector<JUnitCase> cases;
};

/// The JUnit XML document: <?xml ...?><testsuites ...><testsuite ...><testcase .../>...
/// in the cases' order, one element a line. Times are seconds with 3 decimals (a negative
/// or non-finite time is written as 0). Text is escaped for XML, and what XML 1.0 cannot
/// hold (control characters other than tab, newline and CR; bytes that are not UTF-8;
/// U+FFFE, U+FFFF) becomes U+FFFD, so any file name or message gives a well-formed
/// document. A failed case gets <failure message type="failure">detail</failure>, an
/// error <error ... type="error">, a skipped one <skipped message>; a passed case's
/// message and detail are not written.
std::string junit_xml(const JUnitSuite& suite);

/// `t` as a JUnitSuite's timestamp: local time, ISO 8601 without a zone
/// ("2026-12-02T06:30:00").
std::string junit_timestamp(std::time_t t);

/// This machine's name for a JUnitSuite's hostname; "" when it has none.
std::string junit_hostname();

/// Writes junit_xml(suite) to `path` whole or not at all (common/atomic_file.h).
/// \throw IoError if it cannot.
void write_junit(const std::string& path, const JUnitSuite& suite);

}  // namespace ffd
