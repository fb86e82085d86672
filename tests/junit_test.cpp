// The JUnit XML writer (common/junit.h): documents that CI readers accept whatever the
// names and messages hold, checked with xmllint against tests/data/junit.xsd, with counts
// that match the cases.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/errors.h"
#include "common/junit.h"
#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using Outcome = JUnitCase::Outcome;
using test::read_file;
using test::temp_folder;
using test::xpath;

const std::string kReplacement = "\xEF\xBF\xBD";  // U+FFFD

JUnitCase make_case(const std::string& name, Outcome outcome, const std::string& message = "",
                    const std::string& detail = "", double seconds = 0.25) {
  JUnitCase c;
  c.name = name;
  c.classname = "ffdtool.batch";
  c.seconds = seconds;
  c.outcome = outcome;
  c.message = message;
  c.detail = detail;
  return c;
}

// Writes `suite` to DIR/NAME.xml and expects the file to validate; returns its path.
std::string written(const JUnitSuite& suite, const std::string& name) {
  const std::string path = temp_folder("junit_" + name) + "/" + name + ".xml";
  write_junit(path, suite);
  std::string why;
  EXPECT_TRUE(test::junit_valid(path, &why)) << why << "\n" << read_file(path);
  return path;
}

TEST(JUnit, ASmallSuiteIsThisDocument) {
  JUnitSuite suite;
  suite.name = "ffdtool batch out";
  suite.seconds = 1.23456;
  suite.timestamp = "2026-12-02T06:30:00";
  suite.hostname = "node7";
  suite.cases = {make_case("in/a.obj", Outcome::Passed, "not written", "not written either", 0.0004),
                 make_case("in/b.off", Outcome::Failed, "in/b.off:2: expected 3 vertices", "exit 2", 0.0125),
                 make_case("in/c.ply", Outcome::Skipped, "done before")};
  EXPECT_EQ(junit_xml(suite),
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<testsuites name=\"ffdtool batch out\" tests=\"3\" failures=\"1\" errors=\"0\" skipped=\"1\" time=\"1.235\">\n"
            "  <testsuite name=\"ffdtool batch out\" tests=\"3\" failures=\"1\" errors=\"0\" skipped=\"1\" time=\"1.235\""
            " timestamp=\"2026-12-02T06:30:00\" hostname=\"node7\">\n"
            "    <testcase name=\"in/a.obj\" classname=\"ffdtool.batch\" time=\"0.000\"/>\n"
            "    <testcase name=\"in/b.off\" classname=\"ffdtool.batch\" time=\"0.013\">\n"
            "      <failure message=\"in/b.off:2: expected 3 vertices\" type=\"failure\">exit 2</failure>\n"
            "    </testcase>\n"
            "    <testcase name=\"in/c.ply\" classname=\"ffdtool.batch\" time=\"0.250\">\n"
            "      <skipped message=\"done before\"/>\n"
            "    </testcase>\n"
            "  </testsuite>\n"
            "</testsuites>\n");
  written(suite, "small");
}

TEST(JUnit, CountsAndTimesComeFromTheCases) {
  JUnitSuite suite;
  suite.name = "counts";
  suite.seconds = 2;
  for (int i = 0; i < 2; ++i) suite.cases.push_back(make_case("pass" + std::to_string(i), Outcome::Passed));
  for (int i = 0; i < 3; ++i) suite.cases.push_back(make_case("fail" + std::to_string(i), Outcome::Failed, "bad"));
  suite.cases.push_back(make_case("error", Outcome::Error, "crashed", "killed by signal 11"));
  for (int i = 0; i < 4; ++i) suite.cases.push_back(make_case("skip" + std::to_string(i), Outcome::Skipped, "later"));
  suite.cases.push_back(make_case("negative", Outcome::Passed, "", "", -3));
  suite.cases.push_back(make_case("nan", Outcome::Passed, "", "", std::nan("")));
  const std::string path = written(suite, "counts");
  for (const std::string& element : std::vector<std::string>{"/testsuites", "/testsuites/testsuite"}) {
    EXPECT_EQ(xpath(path, "string(" + element + "/@tests)"), "12") << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@failures)"), "3") << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@errors)"), "1") << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@skipped)"), "4") << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@time)"), "2.000") << element;
  }
  EXPECT_EQ(xpath(path, "count(//testcase)"), "12");
  EXPECT_EQ(xpath(path, "count(//testcase/failure)"), "3");
  EXPECT_EQ(xpath(path, "count(//testcase/error)"), "1");
  EXPECT_EQ(xpath(path, "count(//testcase/skipped)"), "4");
  EXPECT_EQ(xpath(path, "string(//testcase[@name=\"error\"]/error)"), "killed by signal 11");
  EXPECT_EQ(xpath(path, "string(//testcase[@name=\"error\"]/error/@type)"), "error");
  EXPECT_EQ(xpath(path, "string(//testcase[@name=\"negative\"]/@time)"), "0.000");
  EXPECT_EQ(xpath(path, "string(//testcase[@name=\"nan\"]/@time)"), "0.000");
  // No timestamp or hostname given: none written.
  EXPECT_EQ(xpath(path, "count(//@timestamp | //@hostname)"), "0");
}

TEST(JUnit, HostileNamesAndMessagesStillValidate) {
  // What file names and error messages may hold: markup, both quotes, control
  // characters, a CR, bytes that are not UTF-8 (a stray byte, a cut sequence, an encoded
  // surrogate, an overlong slash), and the non-characters U+FFFE / U+FFFF.
  const std::string markup = "a\"b'c<d>&e]]>f &amp; <![CDATA[x]]>";
  const std::string controls = std::string("bell\x07 esc\x1b[31m nul") + '\0' + "end";
  const std::string bad_utf8 = "stray\xff cut\xc3 surrogate\xed\xa0\x80 overlong\xc0\xaf";
  const std::string nonchars = "fffe\xef\xbf\xbe ffff\xef\xbf\xbf";
  const std::string good_utf8 = "b\xc3\xa9zier \xe6\xa0\xbc \xf0\x9f\x90\x96";  // é, 格, 🐖
  JUnitSuite suite;
  suite.name = markup;
  suite.hostname = controls;
  suite.cases = {make_case(markup, Outcome::Failed, markup, markup),
                 make_case(controls, Outcome::Error, controls, controls + "\r\nline two\tcolumn"),
                 make_case(bad_utf8, Outcome::Skipped, bad_utf8, bad_utf8),
                 make_case(nonchars, Outcome::Failed, "tab\there\nnewline", nonchars),
                 make_case(good_utf8, Outcome::Passed)};
  const std::string path = written(suite, "hostile");
  // What a reader gets back: markup and quotes exactly, valid UTF-8 exactly, tab and
  // newline in an attribute kept, each character XML cannot hold as U+FFFD.
  EXPECT_EQ(xpath(path, "string(//testsuite/@name)"), markup);
  EXPECT_EQ(xpath(path, "string(//testcase[1]/@name)"), markup);
  EXPECT_EQ(xpath(path, "string(//testcase[1]/failure/@message)"), markup);
  EXPECT_EQ(xpath(path, "string(//testcase[1]/failure)"), markup);
  const std::string r = kReplacement;
  const std::string controls_read = "bell" + r + " esc" + r + "[31m nul" + r + "end";
  EXPECT_EQ(xpath(path, "string(//testsuite/@hostname)"), controls_read);
  EXPECT_EQ(xpath(path, "string(//testcase[2]/@name)"), controls_read);
  EXPECT_EQ(xpath(path, "string(//testcase[2]/error)"), controls_read + "\r\nline two\tcolumn");
  const std::string bad_read = "stray" + r + " cut" + r + " surrogate" + r + r + r + " overlong" + r + r;
  EXPECT_EQ(xpath(path, "string(//testcase[3]/@name)"), bad_read);
  EXPECT_EQ(xpath(path, "string(//testcase[3]/skipped/@message)"), bad_read);
  EXPECT_EQ(xpath(path, "string(//testcase[4]/@name)"), "fffe" + r + " ffff" + r);
  EXPECT_EQ(xpath(path, "string(//testcase[4]/failure/@message)"), "tab\there\nnewline");
  EXPECT_EQ(xpath(path, "string(//testcase[5]/@name)"), good_utf8);
  EXPECT_EQ(xpath(path, "count(//testcase)"), "5");
}

TEST(JUnit, AnUnwritableFileIsAnIoErrorAndLeavesNothing) {
  const std::string dir = temp_folder("junit_unwritable");
  JUnitSuite suite;
  suite.name = "x";
  EXPECT_THROW(write_junit(dir + "/missing/junit.xml", suite), IoError);
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace ffd
