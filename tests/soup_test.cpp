// Real-world polygon soups through the CLI: a clean mesh (the bunny) and soups derived
// from it with the same vertices (flipped faces; fins and duplicate faces; degenerate
// faces, OBJ lines and points; a point cloud). A plain FFD keeps every element and moves
// every vertex exactly as it moves the clean mesh's; remesh and bcm refuse each soup with
// exit 2 and the offending element's line.
#include <gtest/gtest.h>

#include <sstream>

#include "common/numbers.h"
#include "mesh/obj_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using test::quoted;

// The bunny as the soups' common vertices and clean faces.
struct Source {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::vector<std::uint32_t>> faces;
};

Source bunny_source() {
  const PolygonSoup soup = read_obj(test::read_file(test::data("bunny.obj")), "bunny.obj");
  Source s;
  s.positions = soup.positions;
  for (const test::SoupFace& f : test::soup_faces(soup)) s.faces.push_back(f.vertices);
  return s;
}

// OBJ text: the positions with shortest round-trip numbers, then `elements` as written.
std::string obj_text(const std::vector<Eigen::Vector3d>& positions, const std::string& elements) {
  std::string text;
  for (const Eigen::Vector3d& p : positions) {
    text += "v";
    for (int k = 0; k < 3; ++k) {
      text += ' ';
      append_number(text, p[k]);
    }
    text += '\n';
  }
  return text + elements;
}

// "f a b c\n" with 1-based indices.
std::string face_line(const std::vector<std::uint32_t>& f, const char* key = "f") {
  std::string line = key;
  for (std::uint32_t v : f) line += " " + std::to_string(v + 1);
  return line + "\n";
}

std::string faces_text(const std::vector<std::vector<std::uint32_t>>& faces) {
  std::string text;
  for (const auto& f : faces) text += face_line(f);
  return text;
}

// The soups, by name: OBJ element text after the vertex lines, and what the 2-manifold
// check says about each (the first offending element).
struct Soup {
  std::string name, elements, problem;
};

std::vector<Soup> soups(const Source& s) {
  std::vector<Soup> out;
  auto flipped = s.faces;
  for (std::size_t f = 7; f < flipped.size(); f += 50) std::reverse(flipped[f].begin(), flipped[f].end());
  out.push_back({"flipped", faces_text(flipped), "is flipped against its neighbour face"});
  // Fins (a third face on an edge) and duplicate faces, appended.
  auto fins = s.faces;
  fins.push_back(s.faces[10]);
  fins.push_back({s.faces[100][0], s.faces[100][1], s.faces[900][2]});
  fins.push_back(s.faces[20]);
  // On the closed bunny a duplicate is already a third face on its edges.
  out.push_back({"fins_duplicates", faces_text(fins), "non-manifold edge"});
  std::string degenerate = faces_text(s.faces);
  degenerate += "l 1 2 3 4 5\n";
  degenerate += face_line({s.faces[3][0], s.faces[3][0], s.faces[3][1]});
  degenerate += "p 7 8 9\n";
  degenerate += face_line({s.faces[5][0], s.faces[5][1], s.faces[5][1]});
  degenerate += "l 10 11\n";
  out.push_back({"degenerate_lines", degenerate, "degenerate face"});
  out.push_back({"point_cloud", "", "no faces"});
  return out;
}

const char* kPlainFfd = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "l", "cells": [6, 6, 6]},
  {"op": "move", "lattice": "l", "points": [{"index": [3, 4, 3], "by": [0.3, 0.4, -0.2]}]},
  {"op": "drag", "lattice": "l", "points": [{"vertex": 5, "to": [0.2, 0.3, 3.1]}]}]})";

const char* kRemesh = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "l", "cells": [6, 6, 6]},
  {"op": "move", "lattice": "l", "points": [{"index": [3, 4, 3], "by": [0.3, 0.4, -0.2]}]},
  {"op": "remesh", "l_max": 0.5}]})";

const char* kBcm = R"({"version": 1, "steps": [
  {"op": "bcm", "name": "back", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 3.0}},
   "handles": [{"name": "hump", "select": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 0.7}}}], "k": 2},
  {"op": "transform", "editor": "back", "handle": "hump", "transform": {"translate": [0, 0.5, 0]}}]})";

std::vector<std::string> keyed_lines(const std::string& text, const std::string& keys) {
  std::vector<std::string> out;
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line))
    if (!line.empty() && keys.find(line[0]) != std::string::npos && line.size() > 1 && line[1] == ' ')
      out.push_back(line);
  return out;
}

std::size_t count_of(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

// Runs `script` on `obj_text` written as dir/name.obj; returns the exit code, the output
// text (dir/name_out.obj) and stderr.
int run_on(const std::string& dir, const std::string& name, const std::string& text, const char* script,
           std::string* output, std::string* err) {
  test::write_file(dir + "/" + name + ".obj", text);
  test::write_file(dir + "/" + name + ".json", script);
  const int code = test::run_tool("run " + quoted(dir + "/" + name + ".obj") + " " + quoted(dir + "/" + name + ".json") +
                                      " -o " + quoted(dir + "/" + name + "_out.obj"),
                                  nullptr, err);
  if (output) *output = test::read_file(dir + "/" + name + "_out.obj");
  return code;
}

TEST(Soups, APlainFfdKeepsEveryElementAndMovesVerticesAsOnTheCleanMesh) {
  const std::string dir = test::temp_folder("soups_ffd");
  const Source source = bunny_source();
  std::string clean_out, err;
  ASSERT_EQ(run_on(dir, "clean", obj_text(source.positions, faces_text(source.faces)), kPlainFfd, &clean_out, &err), 0)
      << err;
  const PolygonSoup clean = read_obj(clean_out, "clean_out.obj");
  ASSERT_EQ(clean.positions.size(), source.positions.size());
  std::size_t moved = 0;
  for (std::size_t v = 0; v < source.positions.size(); ++v) moved += clean.positions[v] != source.positions[v];
  EXPECT_GT(moved, source.positions.size() / 4);
  for (const Soup& soup : soups(source)) {
    SCOPED_TRACE(soup.name);
    const std::string input = obj_text(source.positions, soup.elements);
    std::string out;
    ASSERT_EQ(run_on(dir, soup.name, input, kPlainFfd, &out, &err), 0) << err;
    EXPECT_EQ(keyed_lines(out, "flp"), keyed_lines(input, "flp"));  // every element, in order
    const PolygonSoup moved_soup = read_obj(out, soup.name + "_out.obj");
    ASSERT_EQ(moved_soup.positions.size(), clean.positions.size());
    for (std::size_t v = 0; v < clean.positions.size(); ++v)
      ASSERT_TRUE(moved_soup.positions[v] == clean.positions[v]) << "vertex " << v;  // bit for bit
  }
}

TEST(Soups, RemeshAndBcmRefuseEachSoupNamingTheElement) {
  const std::string dir = test::temp_folder("soups_refused");
  const Source source = bunny_source();
  for (const Soup& soup : soups(source)) {
    for (const auto& [op, script] : {std::pair{"remesh", kRemesh}, std::pair{"bcm", kBcm}}) {
      SCOPED_TRACE(soup.name + " " + op);
      std::string err;
      const std::string name = soup.name + "_" + op;
      EXPECT_EQ(run_on(dir, name, obj_text(source.positions, soup.elements), script, nullptr, &err), 2);
      EXPECT_NE(err.find(dir + "/" + name + ".obj"), std::string::npos) << err;
      EXPECT_NE(err.find(soup.problem), std::string::npos) << err;
      EXPECT_EQ(count_of(err, "error:"), 1u) << err;
      EXPECT_FALSE(std::filesystem::exists(dir + "/" + name + "_out.obj"));
      if (soup.name != "point_cloud") {
        // The file line of the element: "<file>:<line>: ".
        const std::string prefix = "error: " + dir + "/" + name + ".obj:";
        const std::size_t at = err.find(prefix);
        ASSERT_NE(at, std::string::npos) << err;
        EXPECT_GT(std::atoi(err.c_str() + at + prefix.size()), static_cast<int>(source.positions.size())) << err;
      }
    }
  }
}

// Lines and points beside a manifold surface: remesh and bcm act on the faces and leave
// the other elements as they were.
TEST(Soups, RemeshAndBcmLeaveLinesAndPointsAsTheyWere) {
  const std::string dir = test::temp_folder("soups_lines");
  const Source source = bunny_source();
  const std::string extra = "l 1 2 3 4 5\np 7 8 9\nl 10 11\n";
  std::string elements = faces_text(source.faces);
  elements.insert(elements.find('\n', elements.size() / 2) + 1, extra);  // halfway through the faces
  const std::string input = obj_text(source.positions, elements);
  for (const auto& [op, script] : {std::pair{"remesh", kRemesh}, std::pair{"bcm", kBcm}}) {
    SCOPED_TRACE(op);
    std::string out, err;
    ASSERT_EQ(run_on(dir, op, input, script, &out, &err), 0) << err;
    EXPECT_EQ(keyed_lines(out, "lp"), keyed_lines(extra, "lp"));
    const PolygonSoup before = read_obj(input, "in.obj"), after = read_obj(out, "out.obj");
    if (std::string(op) == "remesh") {
      EXPECT_GT(after.positions.size(), before.positions.size());
    }
    for (const std::string& line : keyed_lines(extra, "lp")) EXPECT_NE(out.find(line + "\n"), std::string::npos);
  }
  // OFF cannot hold lines: saving there is refused before anything is written.
  std::string err;
  test::write_file(dir + "/in.obj", input);
  test::write_file(dir + "/ffd.json", kPlainFfd);
  EXPECT_EQ(test::run_tool("run " + quoted(dir + "/in.obj") + " " + quoted(dir + "/ffd.json") + " -o " +
                               quoted(dir + "/out.off"),
                           nullptr, &err),
            2);
  EXPECT_NE(err.find("out.off"), std::string::npos) << err;
  EXPECT_NE(err.find("save it as .obj"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.off"));
}

}  // namespace
}  // namespace ffd
