#include "common/junit.h"

#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/utf8.h"

namespace ffd {
namespace {

const char* kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The escape of an ASCII byte in XML text (`attribute`: inside a double-quoted
// attribute, where tab, newline and CR must be character references to survive the
// reader's normalization), "" if it stands for itself, U+FFFD if XML 1.0 forbids it.
std::string ascii_escape(unsigned char c, bool attribute) {
  switch (c) {
    case '&': return "&amp;";
    case '<': return "&lt;";
    case '>': return "&gt;";  // also keeps "]]>" out of text
    case '"': return attribute ? "&quot;" : "";
    case '\'': return attribute ? "&apos;" : "";
    case '\t': return attribute ? "&#9;" : "";
    case '\n': return attribute ? "&#10;" : "";
    case '\r': return "&#13;";  // a raw CR would be read as a newline
    default: break;
  }
  return c < 0x20 ? kReplacement : "";
}

// `text` as XML character data: escaped, and every character XML 1.0 cannot hold
// (see junit.h) replaced by U+FFFD.
std::string xml_escape(const std::string& text, bool attribute) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      const std::string escape = ascii_escape(c, attribute);
      out += escape.empty() ? std::string(1, static_cast<char>(c)) : escape;
      ++i;
      continue;
    }
    const std::size_t length = utf8_sequence(text, i);
    // U+FFFE and U+FFFF are UTF-8 but not XML characters.
    const bool noncharacter = length == 3 && text.compare(i, 2, "\xEF\xBF") == 0 &&
                              static_cast<unsigned char>(text[i + 2]) >= 0xBE;
    out += length && !noncharacter ? text.substr(i, length) : kReplacement;
    i += length ? length : 1;
  }
  return out;
}

// ` key="value"`, the value escaped.
std::string attribute(const char* key, const std::string& value) {
  return std::string(" ") + key + "=\"" + xml_escape(value, true) + "\"";
}

// Seconds with three decimals; 0 for what is not a time.
std::string seconds_text(double seconds) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", std::isfinite(seconds) && seconds > 0 ? seconds : 0.0);
  return buf;
}

// tests="..." failures="..." errors="..." skipped="..." time="...": the counts of the cases.
std::string count_attributes(const JUnitSuite& suite) {
  std::size_t failed = 0, errors = 0, skipped = 0;
  for (const JUnitCase& c : suite.cases) {
    failed += c.outcome == JUnitCase::Outcome::Failed;
    errors += c.outcome == JUnitCase::Outcome::Error;
    skipped += c.outcome == JUnitCase::Outcome::Skipped;
  }
  return attribute("tests", std::to_string(suite.cases.size())) + attribute("failures", std::to_string(failed)) +
         attribute("errors", std::to_string(errors)) + attribute("skipped", std::to_string(skipped)) +
         attribute("time", seconds_text(suite.seconds));
}

// One <testcase> element with its outcome's child, indented for <testsuite>.
std::string testcase_xml(const JUnitCase& c) {
  const std::string open = "    <testcase" + attribute("name", c.name) + attribute("classname", c.classname) +
                           attribute("time", seconds_text(c.seconds));
  const char* element = c.outcome == JUnitCase::Outcome::Failed    ? "failure"
                        : c.outcome == JUnitCase::Outcome::Error   ? "error"
                        : c.outcome == JUnitCase::Outcome::Skipped ? "skipped"
                                                                   : nullptr;
  if (!element) return open + "/>\n";
  std::string child = std::string("      <") + element + attribute("message", c.message);
  if (c.outcome != JUnitCase::Outcome::Skipped) child += attribute("type", element);
  child += c.detail.empty() ? "/>\n" : ">" + xml_escape(c.detail, false) + "</" + element + ">\n";
  return open + ">\n" + child + "    </testcase>\n";
}

}  // namespace

std::string junit_xml(const JUnitSuite& suite) {
  const std::string counts = count_attributes(suite);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuites" + attribute("name", suite.name) + counts + ">\n";
  out += "  <testsuite" + attribute("name", suite.name) + counts;
  if (!suite.timestamp.empty()) out += attribute("timestamp", suite.timestamp);
  if (!suite.hostname.empty()) out += attribute("hostname", suite.hostname);
  out += ">\n";
  for (const JUnitCase& c : suite.cases) out += testcase_xml(c);
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

std::string junit_timestamp(std::time_t t) {
  std::tm local{};
  char buf[32];
  if (!::localtime_r(&t, &local) || std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &local) == 0) return "";
  return buf;
}

std::string junit_hostname() {
  char buf[HOST_NAME_MAX + 1] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "";
  return buf;
}

void write_junit(const std::string& path, const JUnitSuite& suite) {
  const std::string xml = junit_xml(suite);
  write_file_atomically(path, [&](std::ostream& os) { os << xml; });
}

}  // namespace ffd
