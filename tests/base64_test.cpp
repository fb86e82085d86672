// Base64 (common/base64.h): RFC 4648's test vectors, round trips through the parallel
// path and the one for text broken into lines, padded runs one after another, and the
// offset of the first character that is not base64.
#include <gtest/gtest.h>
#include <omp.h>

#include <random>
#include <string>

#include "common/base64.h"

namespace ffd {
namespace {

std::string decoded(std::string_view text, std::size_t* bad = nullptr) {
  DecodedBytes out;
  const std::size_t at = decode_base64(text, out);
  if (bad) *bad = at;
  return std::string(out.view());
}

std::string encoded(std::string_view data) {
  std::string out;
  append_base64(data, out);
  return out;
}

std::string random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng() & 255);
  return s;
}

// Every `width` characters a line end, as some writers wrap base64.
std::string wrapped(const std::string& text, std::size_t width) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); i += width) out += text.substr(i, width) + "\n";
  return out;
}

TEST(Base64, Rfc4648Vectors) {
  const char* pairs[][2] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},        {"foo", "Zm9v"},
                            {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}};
  for (const auto& p : pairs) {
    EXPECT_EQ(encoded(p[0]), p[1]);
    std::size_t bad = 0;
    EXPECT_EQ(decoded(p[1], &bad), p[0]);
    EXPECT_EQ(bad, std::string_view::npos);
  }
}

TEST(Base64, RoundTripsSmallAndLarge) {
  for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 100u, 1001u})
    EXPECT_EQ(decoded(encoded(random_bytes(n, 1))), random_bytes(n, 1)) << n;
  // 3 MB: 4 MB of text, past the size decoded in parallel blocks.
  const std::string big = random_bytes(3'000'001, 2);
  const std::string text = encoded(big);
  EXPECT_EQ(decoded(text), big);
  EXPECT_EQ(decoded(wrapped(text, 76)), big);    // lines: the one-thread path after two tries
  EXPECT_EQ(decoded(" \n" + text + "\n "), big);  // spaces around
}

TEST(Base64, SameBytesForAnyThreadCount) {
  const std::string text = encoded(random_bytes(2'500'000, 3));
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::string one = decoded(text);
  omp_set_num_threads(std::max(2, threads));
  EXPECT_EQ(decoded(text), one);
  omp_set_num_threads(threads);
}

TEST(Base64, PaddedRunsOneAfterAnother) {
  // VTK encodes an array's header apart from its data: "BAAAAA==" then the data.
  const std::string header = std::string("\x04\0\0\0", 4), data = random_bytes(2'000'000, 4);
  EXPECT_EQ(decoded(encoded(header) + encoded(data)), header + data);
  EXPECT_EQ(decoded(encoded("a") + encoded("bc") + encoded("def")), "abcdef");
}

TEST(Base64, FirstBadCharacter) {
  const std::string text = encoded(random_bytes(3'000'000, 5));
  for (const std::size_t at : {std::size_t{0}, std::size_t{5}, std::size_t{2'621'441}, text.size() - 1}) {
    std::string bad = text;
    bad[at] = '*';
    std::size_t where = 0;
    decoded(bad, &where);
    EXPECT_EQ(where, at);
  }
  std::size_t where = 0;
  decoded("Zm9v=Zm9v", &where);  // '=' where no padding can be
  EXPECT_EQ(where, 4u);
  decoded("Zm9vZ", &where);  // a group cut short: its first character
  EXPECT_EQ(where, 4u);
  decoded("Zg==Zm9v" + wrapped(text, 64) + "Zm=v", &where);  // after the lines: data after padding
  EXPECT_EQ(where, 8 + wrapped(text, 64).size() + 3);
}

}  // namespace
}  // namespace ffd
