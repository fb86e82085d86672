// The OBJ reader's parallel path for plain files (obj_chunks.h) against the general
// reader: the same soup at any chunking where it reads a file, and a decline (the serial
// reader's turn) at anything else.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/numbers.h"
#include "fuzz/reader_paths.h"
#include "mesh/obj_chunks.h"
#include "mesh/obj_io.h"
#include "support/with_threads.h"

namespace ffd {
namespace {

// A plain OBJ: vertices and faces interleaved, with comments (on lines of their own and
// after values), blank lines, tabs, CRLF line ends and faces of 3 to 10 corners, each
// pointing only at vertices above it.
std::string plain_obj(int vertices, std::uint64_t seed, bool final_newline = true) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coordinate(-2, 2);
  std::string text = "# plain geometry\n\n";
  int defined = 0;
  while (defined < vertices) {
    const int run = 1 + static_cast<int>(rng() % 20);
    for (int k = 0; k < run && defined < vertices; ++k, ++defined) {
      text += rng() % 7 ? "v " : "v\t";
      for (int c = 0; c < 3; ++c) text += format_number(coordinate(rng)) + (c < 2 ? " " : "");
      text += rng() % 5 ? "\n" : rng() % 2 ? "\r\n" : " # a vertex\n";
    }
    for (int f = static_cast<int>(rng() % 4); f > 0 && defined >= 3; --f) {
      text += "f";
      const int corners = 3 + static_cast<int>(rng() % 8);
      for (int c = 0; c < corners; ++c) text += (rng() % 9 ? " " : " \t") + std::to_string(1 + rng() % defined);
      text += rng() % 11 ? "\n" : "  # a face\n";
    }
    if (rng() % 13 == 0) text += rng() % 2 ? "\n" : "   # a note\n";
  }
  text += "f 1 2 3";
  return final_newline ? text + "\n" : text;
}

PolygonSoup general(const std::string& text) { return read_obj_general(text, "plain.obj"); }

// The readers' paths agree on `text` (check_obj_paths_agree), whether they read it or
// refuse it alike: true unless they differ.
bool paths_agree(const std::string& text) {
  try {
    fuzz::check_obj_paths_agree(text);
  } catch (const InputError&) {  // refused alike
  } catch (const std::logic_error& e) {
    ADD_FAILURE() << e.what();
    return false;
  }
  return true;
}

TEST(ObjChunks, ReadsPlainFilesAsTheGeneralPathAtAnyChunking) {
  for (std::uint64_t seed : {1, 2, 3})
    for (bool final_newline : {true, false}) {
      const std::string text = plain_obj(3000, seed, final_newline);
      const PolygonSoup expected = general(text);
      ASSERT_EQ(expected.positions.size(), 3000u);
      for (int threads = 1; threads <= 6; ++threads) {
        const std::optional<PolygonSoup> soup = read_plain_obj_in_chunks(text, threads);
        ASSERT_TRUE(soup.has_value()) << seed << ' ' << threads;
        EXPECT_TRUE(fuzz::same_soup(*soup, expected)) << seed << ' ' << threads;
        EXPECT_FALSE(soup->obj);
      }
    }
}

TEST(ObjChunks, DeclinesEveryOtherLineWhereverItIs) {
  const std::string text = plain_obj(600, 4);
  for (const char* line : {"vn 0 0 1", "vt 0 0", "f 1/1/1 2/1/1 3/1/1", "f 1//1 2//1 3//1", "f -1 -2 -3", "o part",
                           "g part", "usemtl m", "s 1", "mtllib m.mtl", "l 1 2", "p 1", "v 1 2 3 4", "v 1 2 3 0.5 0.5 0.5",
                           "v 1 2", "v 1 2 3 x", "f 1 2 3 x", "f 1 2", "f 1 2 0", "f 1 2 3000", "f +1 2 3", "f 1 2 \\", "bevel on"})
    for (double where : {0.0, 0.3, 0.5, 0.77, 1.0}) {
      std::string changed = text;
      const std::size_t at = changed.find('\n', static_cast<std::size_t>(where * static_cast<double>(text.size() - 1)));
      changed.insert(at == std::string::npos ? changed.size() : at + 1, std::string(line) + "\n");
      for (int threads = 1; threads <= 4; ++threads)
        EXPECT_FALSE(read_plain_obj_in_chunks(changed, threads).has_value()) << line << " at " << where << ' ' << threads;
      EXPECT_TRUE(paths_agree(changed)) << line;
    }
}

// A face in the first chunk that points at a vertex of a later one: defined below it, so
// the serial reader refuses the file with its line number.
TEST(ObjChunks, AFaceAheadOfItsVerticesIsLeftToTheSerialReader) {
  std::string text = "v 0 0 0\nv 1 0 0\nf 1 2 400\n";
  for (int i = 0; i < 600; ++i) text += "v " + std::to_string(i) + " 1 2\n";
  for (int threads = 1; threads <= 4; ++threads) EXPECT_FALSE(read_plain_obj_in_chunks(text, threads).has_value());
  EXPECT_THROW(read_obj(text, "ahead.obj"), InputError);
  EXPECT_TRUE(paths_agree(text));
}

// Through read_obj, which takes the parallel path from 4 MB on with more than one thread:
// the soup of one thread, and of the general path.
TEST(ObjChunks, ReadObjReadsALargePlainFileAlikeAtOneAndTwoThreads) {
  const std::string text = plain_obj(110000, 5);
  ASSERT_GT(text.size(), std::size_t{4} << 20);
  const PolygonSoup one = test::with_threads(1, [&] { return read_obj(text, "large.obj"); });
  const PolygonSoup two = test::with_threads(2, [&] { return read_obj(text, "large.obj"); });
  EXPECT_TRUE(fuzz::same_soup(one, two));
  EXPECT_TRUE(fuzz::same_soup(two, general(text)));
}

}  // namespace
}  // namespace ffd
