// The OFF reader's parallel path for plain files (off_chunks.h) against the general
// reader: the same soup at any chunking where it reads a file, and a decline (the serial
// reader's turn) at anything else.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "common/numbers.h"
#include "fuzz/reader_paths.h"
#include "mesh/off_chunks.h"
#include "mesh/off_io.h"
#include "support/with_threads.h"

namespace ffd {
namespace {

// The lines after a plain OFF's counts: vertices, then faces of 3 to 9 corners, with
// comments (on lines of their own and after values), blank lines, tabs and CRLF ends.
std::string plain_off_body(int vertices, int faces, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coordinate(-2, 2);
  const char* ends[] = {"\n", "\n", "\n", "\r\n", " # a note\n", "\t\n"};
  std::string text;
  for (int v = 0; v < vertices; ++v) {
    for (int c = 0; c < 3; ++c) text += format_number(coordinate(rng)) + (c < 2 ? (rng() % 9 ? " " : "\t") : "");
    text += ends[rng() % 6];
    if (rng() % 97 == 0) text += rng() % 2 ? "\n" : "# between\n";
  }
  for (int f = 0; f < faces; ++f) {
    const int corners = 3 + static_cast<int>(rng() % 7);
    text += std::to_string(corners);
    for (int c = 0; c < corners; ++c) text += " " + std::to_string(rng() % vertices);
    text += ends[rng() % 6];
    if (rng() % 97 == 0) text += rng() % 2 ? "\n" : "  # between\n";
  }
  return text + "# the end\n";
}

std::string plain_off(int vertices, int faces, const std::string& body) {
  return "OFF\n" + std::to_string(vertices) + " " + std::to_string(faces) + " 0\n" + body;
}

TEST(OffChunks, ReadsPlainFilesAsTheGeneralPathAtAnyChunking) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const std::string body = plain_off_body(2000, 3000, seed);
    const std::string text = plain_off(2000, 3000, body);
    const PolygonSoup expected = read_off_general(text, "plain.off");
    ASSERT_EQ(expected.elements.size(), 3000u);
    for (int threads = 1; threads <= 6; ++threads) {
      const std::optional<PolygonSoup> soup = read_plain_off_in_chunks({body, 2, 2000, 3000}, threads);
      ASSERT_TRUE(soup.has_value()) << seed << ' ' << threads;
      EXPECT_TRUE(fuzz::same_soup(*soup, expected)) << seed << ' ' << threads;  // line numbers from the file's start
    }
  }
}

TEST(OffChunks, DeclinesEveryOtherLineWhereverItIs) {
  const std::string body = plain_off_body(400, 600, 4);
  for (const char* line : {"1 2 3 4", "1 2", "3 0 1", "3 0 1 2 255 0 0", "3 0 1 2 0.5", "3 0 1 400", "3 0 1 -1",
                           "2 0 1", "+3 0 1 2", "3 0 1 2 x", "1 2 x", "OFF"})
    for (double where : {0.0, 0.3, 0.5, 0.77, 1.0}) {
      std::string changed = body;
      const std::size_t at = changed.find('\n', static_cast<std::size_t>(where * static_cast<double>(body.size() - 1)));
      changed.insert(at == std::string::npos ? changed.size() : at + 1, std::string(line) + "\n");
      for (int threads = 1; threads <= 4; ++threads)
        EXPECT_FALSE(read_plain_off_in_chunks({changed, 2, 400, 600}, threads).has_value())
            << line << " at " << where << ' ' << threads;
    }
}

TEST(OffChunks, DeclinesOtherCountsThanTheBodyHolds) {
  const std::string body = plain_off_body(400, 600, 5);
  for (const auto& [vertices, faces] : {std::pair{399, 600}, {401, 600}, {400, 599}, {400, 601}, {0, 0}})
    for (int threads = 1; threads <= 3; ++threads)
      EXPECT_FALSE(read_plain_off_in_chunks({body, 2, vertices, faces}, threads).has_value()) << vertices << ' ' << faces;
}

// Through read_off, which takes the parallel path from 4 MB on with more than one thread:
// the soup of one thread, and of the general path.
TEST(OffChunks, ReadOffReadsALargePlainFileAlikeAtOneAndTwoThreads) {
  const std::string text = plain_off(60000, 110000, plain_off_body(60000, 110000, 6));
  ASSERT_GT(text.size(), std::size_t{4} << 20);
  const PolygonSoup one = test::with_threads(1, [&] { return read_off(text, "large.off"); });
  const PolygonSoup two = test::with_threads(2, [&] { return read_off(text, "large.off"); });
  EXPECT_TRUE(fuzz::same_soup(one, two));
  EXPECT_TRUE(fuzz::same_soup(two, read_off_general(text, "large.off")));
}

}  // namespace
}  // namespace ffd
