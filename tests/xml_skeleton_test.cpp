// The XML skeleton (mesh/xml_skeleton.h): pugixml reads the same elements, attributes
// and text starts from the skeleton as from the whole text, at the same offsets once
// mapped back, and markup that holds '<' or '>' (attribute values, comments, CDATA)
// is kept whole.
#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <string>
#include <vector>

#include "mesh/xml_skeleton.h"

namespace ffd {
namespace {

// Each node of a parse, in document order: its name, its attributes, and the offsets
// (in `base`'s buffer, mapped by `offset`) of its value and its attributes' values.
template <class Offset>
std::vector<std::string> nodes_of(char* buffer, std::size_t size, const Offset& offset) {
  pugi::xml_document doc;
  EXPECT_TRUE(doc.load_buffer_inplace(buffer, size, pugi::parse_minimal | pugi::parse_cdata, pugi::encoding_utf8));
  std::vector<std::string> out;
  struct Walker : pugi::xml_tree_walker {
    std::vector<std::string>* out;
    const char* base;
    const Offset* offset;
    bool for_each(pugi::xml_node& node) override {
      std::string line = std::to_string(node.type()) + " " + node.name();
      const char* v = node.value();
      if (*v) line += " @" + std::to_string((*offset)(static_cast<std::size_t>(v - base)));
      for (const pugi::xml_attribute a : node.attributes())
        line += std::string(" ") + a.name() + "=" + a.value() + "@" +
                std::to_string((*offset)(static_cast<std::size_t>(a.value() - base)));
      out->push_back(line);
      return true;
    }
  } walker;
  walker.out = &out;
  walker.base = buffer;
  walker.offset = &offset;
  doc.traverse(walker);
  return out;
}

std::vector<std::string> parsed_whole(std::string text) {
  return nodes_of(text.data(), text.size(), [](std::size_t at) { return at; });
}

std::vector<std::string> parsed_skeleton(const std::string& text, std::size_t keep) {
  XmlSkeleton s = xml_skeleton(text, keep);
  return nodes_of(s.markup.data(), s.markup.size(), [&](std::size_t at) { return s.text_offset(at); });
}

TEST(XmlSkeleton, SameNodesAndOffsetsAsTheWholeText) {
  const std::string long_text(5000, 'A');
  const std::string text =
      "<?xml version=\"1.0\"?>\n<!-- a <comment> with > and < -->\n"
      "<VTKFile type=\"UnstructuredGrid\" note='a > b'>\n"
      "  <Piece NumberOfPoints=\"4\">\n"
      "    <DataArray Name=\"x\">\n      " + long_text + "\n    </DataArray>\n"
      "    <DataArray Name=\"spaces\">" + std::string(3000, ' ') + "</DataArray>\n"
      "    <DataArray Name=\"short\">1 2 3</DataArray>\n"
      "    <DataArray Name=\"indented\">" + std::string(700, '\n') + "BBBB" + long_text + "</DataArray>\n"
      "    <![CDATA[ <not a tag> ]]>\n"
      "  </Piece>\n</VTKFile>\n";
  const std::vector<std::string> whole = parsed_whole(text);
  EXPECT_EQ(parsed_skeleton(text, 256), whole);
  EXPECT_EQ(parsed_skeleton(text, 0), whole);
  const XmlSkeleton s = xml_skeleton(text);
  EXPECT_LT(s.markup.size(), text.size() - 2 * long_text.size());
  EXPECT_EQ(xml_skeleton(text, text.size()).markup, text);  // nothing long enough to cut
}

TEST(XmlSkeleton, ErrorOffsetsMapBack) {
  const std::string text = "<a>" + std::string(10000, 'x') + "</a><b x=\"1>";
  XmlSkeleton s = xml_skeleton(text);
  pugi::xml_document doc;
  const pugi::xml_parse_result r =
      doc.load_buffer_inplace(s.markup.data(), s.markup.size(), pugi::parse_minimal, pugi::encoding_utf8);
  ASSERT_FALSE(r);
  std::string copy = text;
  pugi::xml_document whole;
  const pugi::xml_parse_result w = whole.load_buffer_inplace(copy.data(), copy.size(), pugi::parse_minimal, pugi::encoding_utf8);
  EXPECT_EQ(s.text_offset(static_cast<std::size_t>(r.offset)), static_cast<std::size_t>(w.offset));
}

}  // namespace
}  // namespace ffd
