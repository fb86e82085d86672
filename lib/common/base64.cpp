#include "common/base64.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace ffd {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr std::size_t kNone = std::string_view::npos;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Each byte's value: 0..63, 64 for '=', -1 for any other.
const std::array<std::int8_t, 256> kValues = [] {
  std::array<std::int8_t, 256> v{};
  v.fill(-1);
  for (int i = 0; i < 64; ++i) v[static_cast<std::uint8_t>(kAlphabet[i])] = static_cast<std::int8_t>(i);
  v['='] = 64;
  return v;
}();

// Each byte's 6 bits shifted for its place k in a group of four, or kBad for a byte
// outside the alphabet ('=' and spaces included): a group is plain when the OR of its
// four entries has no kBad bit.
constexpr std::uint32_t kBad = 1u << 24;
const std::array<std::array<std::uint32_t, 256>, 4> kPlaced = [] {
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (int k = 0; k < 4; ++k) {
    t[k].fill(kBad);
    for (int i = 0; i < 64; ++i) t[k][static_cast<std::uint8_t>(kAlphabet[i])] = static_cast<std::uint32_t>(i) << (6 * (3 - k));
  }
  return t;
}();

}  // namespace

std::size_t decode_base64_groups(const char* in, std::size_t groups, char* out) {
  const auto* c = reinterpret_cast<const std::uint8_t*>(in);
  for (std::size_t g = 0; g < groups; ++g, c += 4, out += 3) {
    const std::uint32_t bits = kPlaced[0][c[0]] | kPlaced[1][c[1]] | kPlaced[2][c[2]] | kPlaced[3][c[3]];
    if (bits & kBad) return g;
    out[0] = static_cast<char>(bits >> 16);
    out[1] = static_cast<char>(bits >> 8);
    out[2] = static_cast<char>(bits);
  }
  return groups;
}

namespace {

constexpr std::size_t kBlockGroups = std::size_t{1} << 16;  // 256 KB of text

// The same over every thread, in fixed blocks; a block after one that stopped short is
// skipped (its groups are not counted, whatever it wrote).
std::size_t decode_plain_groups_parallel(const char* in, std::size_t groups, char* out) {
  const std::int64_t blocks = static_cast<std::int64_t>((groups + kBlockGroups - 1) / kBlockGroups);
  std::vector<std::size_t> done(static_cast<std::size_t>(blocks), 0);
  std::atomic<std::int64_t> stopped{blocks};
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t b = 0; b < blocks; ++b) {
    if (b > stopped.load(std::memory_order_relaxed)) continue;
    const std::size_t first = static_cast<std::size_t>(b) * kBlockGroups;
    const std::size_t count = std::min(kBlockGroups, groups - first);
    done[static_cast<std::size_t>(b)] = decode_base64_groups(in + 4 * first, count, out + 3 * first);
    if (done[static_cast<std::size_t>(b)] < count) {
      std::int64_t seen = stopped.load();
      while (b < seen && !stopped.compare_exchange_weak(seen, b)) {
      }
    }
  }
  std::size_t total = 0;
  for (std::int64_t b = 0; b < blocks; ++b) {
    total += done[static_cast<std::size_t>(b)];
    if (done[static_cast<std::size_t>(b)] < kBlockGroups) break;
  }
  return std::min(total, groups);
}

// Decodes whole groups from text[i] on into out + size, in parallel while that pays: a
// text broken into lines stops each try after a line, so after two short tries the rest
// is decoded on one thread. Returns the groups decoded.
struct PlainRuns {
  int short_tries = 0;
  std::size_t decode(std::string_view text, std::size_t i, char* out) {
    const std::size_t groups = (text.size() - i) / 4;
    if (groups < 4 * kBlockGroups || short_tries >= 2) return decode_base64_groups(text.data() + i, groups, out);
    const std::size_t done = decode_plain_groups_parallel(text.data() + i, groups, out);
    if (done < groups) ++short_tries;
    return done;
  }
};

}  // namespace

void append_base64(std::string_view data, std::string& out) {
  out.reserve(out.size() + (data.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < data.size(); i += 3) {
    const std::size_t left = data.size() - i;
    std::uint32_t bits = static_cast<std::uint32_t>(static_cast<std::uint8_t>(data[i])) << 16;
    if (left > 1) bits |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(data[i + 1])) << 8;
    if (left > 2) bits |= static_cast<std::uint8_t>(data[i + 2]);
    out += kAlphabet[bits >> 18];
    out += kAlphabet[(bits >> 12) & 63];
    out += left > 1 ? kAlphabet[(bits >> 6) & 63] : '=';
    out += left > 2 ? kAlphabet[bits & 63] : '=';
  }
}

std::size_t decode_base64(std::string_view text, DecodedBytes& out) {
  out.data.reset(new char[text.size() / 4 * 3 + 3]);
  char* bytes = out.data.get();
  std::size_t size = 0;
  PlainRuns plain;
  int group[4];
  std::size_t at[4];
  int n = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (n == 0 && i + 4 <= text.size()) {  // the bulk: whole groups, no space, no padding
      const std::size_t groups = plain.decode(text, i, bytes + size);
      size += 3 * groups;
      i += 4 * groups;
      if (i >= text.size()) break;
    }
    if (is_space(text[i])) continue;
    const int v = kValues[static_cast<std::uint8_t>(text[i])];
    if (v < 0 || (v == 64 && n < 2) || (n == 3 && group[2] == 64 && v != 64)) {
      out.size = size;
      return i;
    }
    at[n] = i;
    group[n++] = v;
    if (n < 4) continue;
    const int pads = (group[2] == 64) + (group[3] == 64);
    const std::uint32_t bits = (group[0] << 18) | (group[1] << 12) | ((group[2] & 63) << 6) | (group[3] & 63);
    bytes[size++] = static_cast<char>(bits >> 16);
    if (pads < 2) bytes[size++] = static_cast<char>((bits >> 8) & 255);
    if (pads < 1) bytes[size++] = static_cast<char>(bits & 255);
    n = 0;
  }
  out.size = size;
  return n == 0 ? kNone : at[0];
}

}  // namespace ffd
