#include "mesh/xml_skeleton.h"

#include <algorithm>

namespace ffd {
namespace {

constexpr std::size_t kNone = std::string_view::npos;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Where the markup starting at text[at] == '<' ends (one past it), or the text's end when
// it is not closed (the parser then says what is wrong).
std::size_t markup_end(std::string_view text, std::size_t at) {
  const auto after = [&](std::string_view close, std::size_t from) {
    const std::size_t end = text.find(close, from);
    return end == kNone ? text.size() : end + close.size();
  };
  const std::string_view rest = text.substr(at);
  if (rest.compare(0, 4, "<!--") == 0) return after("-->", at + 4);
  if (rest.compare(0, 9, "<![CDATA[") == 0) return after("]]>", at + 9);
  if (rest.compare(0, 2, "<?") == 0) return after("?>", at + 2);
  char quote = 0;  // inside an attribute value (or a DOCTYPE's literal)
  int brackets = 0;  // inside a DOCTYPE's internal subset
  for (std::size_t i = at + 1; i < text.size(); ++i) {
    const char c = text[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[') {
      ++brackets;
    } else if (c == ']') {
      brackets -= brackets > 0;
    } else if (c == '>' && brackets == 0) {
      return i + 1;
    }
  }
  return text.size();
}

}  // namespace

std::size_t XmlSkeleton::text_offset(std::size_t at) const {
  const auto next = std::upper_bound(runs.begin(), runs.end(), at, [](std::size_t a, const Run& r) { return a < r.markup; });
  const Run& run = *(next - 1);
  return run.text + (at - run.markup);
}

XmlSkeleton xml_skeleton(std::string_view text, std::size_t keep) {
  XmlSkeleton s;
  s.runs.push_back({0, 0});
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t lt = text.find('<', at);
    if (lt == kNone) lt = text.size();
    if (lt - at > keep) {  // a long text: its leading spaces and first character, then a cut
      std::size_t head = at;
      while (head < lt && is_space(text[head])) ++head;
      head = head == lt ? at + 1 : head + 1;  // spaces only: one is enough
      s.markup.append(text.substr(at, head - at));
      s.runs.push_back({s.markup.size(), lt});
    } else {
      s.markup.append(text.substr(at, lt - at));
    }
    if (lt == text.size()) break;
    const std::size_t end = markup_end(text, lt);
    s.markup.append(text.substr(lt, end - lt));
    at = end;
  }
  return s;
}

}  // namespace ffd
