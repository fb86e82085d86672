// The markup of an XML text with its long texts cut short, and the map from offsets in it
// back to offsets in the text. A VTU file is mostly base64 between tags; an XML parser
// (pugixml, in place) only needs the tags, so it is given the skeleton: no copy of the
// whole file and no parse of hundreds of MB of text. A reader that gets a text's start
// from the parser finds the text itself in the file's bytes (mesh/vtu_io.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ffd {

struct XmlSkeleton {
  std::string markup;  // what a parser reads
  /// Where each copied run starts in `markup` and in the text, in order; the first is {0, 0}.
  struct Run {
    std::size_t markup = 0, text = 0;
  };
  std::vector<Run> runs;

  /// The text's offset of markup[at] (at == markup.size(): the end of what was copied).
  std::size_t text_offset(std::size_t at) const;
};

/// The skeleton of `text`: tags, comments, CDATA sections, processing instructions and
/// texts up to `keep` bytes as they are; a longer text keeps its leading spaces and its
/// first other character (a text of spaces only, one space), so a parser sees the same
/// nodes, with the same starts.
XmlSkeleton xml_skeleton(std::string_view text, std::size_t keep = 256);

}  // namespace ffd
