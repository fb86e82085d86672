#include "warp/sensitivity.h"

#include <algorithm>
#include <charconv>
#include <string>
#include <vector>

namespace ffd {
namespace {

constexpr std::size_t kBatch = 1 << 13;  // vertices whose rows are gathered (and texts held) at once
constexpr std::size_t kChunk = 1 << 9;   // vertices formatted by one thread

/// Where each vertex's rows come from: the deformer's weights at its input position, the
/// columns of the movable points, and the inputs of the warps after the deformer.
struct Source {
  const Deformer& deformer;
  int level;
  std::vector<std::uint32_t> column;  // point id -> m, kFixedPoint for a fixed point
  ConstVec3Array input;         // the deformer's input positions
  std::vector<const Warp*> after;
  std::vector<ConstVec3Array> after_input;
};

/// One batch of vertices: per vertex its (column, weight) pairs, columns ascending, and
/// the Jacobian of the warps after the deformer.
struct Rows {
  std::vector<std::size_t> offsets{0};
  std::vector<std::pair<std::uint32_t, double>> weights;
  std::vector<Eigen::Matrix3d> after;
  void clear() {
    offsets.assign(1, 0);
    weights.clear();
    after.clear();
  }
};

/// Gathers vertices [first, last). Serial: a deformer's weights may fill caches.
void gather(const Source& s, std::size_t first, std::size_t last, Rows& rows, PointWeights& w) {
  rows.clear();
  for (std::size_t v = first; v < last; ++v) {
    const Eigen::Index c = static_cast<Eigen::Index>(v);
    s.deformer.movable_weights(s.level, s.input.col(c), w);
    const std::size_t begin = rows.weights.size();
    for (const auto& [id, weight] : w) rows.weights.emplace_back(s.column[id], weight);
    std::sort(rows.weights.begin() + static_cast<std::ptrdiff_t>(begin), rows.weights.end());
    rows.offsets.push_back(rows.weights.size());
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    if (!w.empty())
      for (std::size_t j = 0; j < s.after.size(); ++j) {
        Eigen::Matrix3d Jj;
        s.after[j]->apply(s.after_input[j].col(c), &Jj);
        J = Jj * J;
      }
    rows.after.push_back(J);
  }
}

/// Entries of vertex i of the batch: its weights times the non-zero entries of J.
std::size_t entries(const Rows& rows, std::size_t i) {
  const std::size_t n = rows.offsets[i + 1] - rows.offsets[i];
  return n * static_cast<std::size_t>((rows.after[i].array() != 0).count());
}

char* put_line(char* p, std::size_t row, std::size_t col, double value) {
  p = std::to_chars(p, p + 24, row).ptr;
  *p++ = ' ';
  p = std::to_chars(p, p + 24, col).ptr;
  *p++ = ' ';
  p = std::to_chars(p, p + 32, value, std::chars_format::general, 17).ptr;
  *p++ = '\n';
  return p;
}

/// The text of vertices [i0, i1) of the batch starting at vertex `first`.
void format(const Rows& rows, std::size_t first, std::size_t i0, std::size_t i1, std::string& text) {
  std::size_t lines = 0;
  for (std::size_t i = i0; i < i1; ++i) lines += entries(rows, i);
  text.resize(lines * 72);
  char* p = text.data();
  for (std::size_t i = i0; i < i1; ++i) {
    const Eigen::Matrix3d& J = rows.after[i];
    for (std::size_t r = 0; r < 3; ++r)
      for (std::size_t e = rows.offsets[i]; e < rows.offsets[i + 1]; ++e)
        for (std::size_t a = 0; a < 3; ++a) {
          const double value = J(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(a)) * rows.weights[e].second;
          if (value != 0) p = put_line(p, 3 * (first + i) + r + 1, 3 * std::size_t{rows.weights[e].first} + a + 1, value);
        }
  }
  text.resize(static_cast<std::size_t>(p - text.data()));
}

void write_batch(std::ostream& os, const Rows& rows, std::size_t first, std::vector<std::string>& texts) {
  const std::size_t n = rows.after.size(), chunks = (n + kChunk - 1) / kChunk;
  texts.resize(chunks);
#pragma omp parallel for schedule(dynamic)
  for (std::size_t c = 0; c < chunks; ++c) format(rows, first, c * kChunk, std::min(n, (c + 1) * kChunk), texts[c]);
  for (const std::string& t : texts) os.write(t.data(), static_cast<std::streamsize>(t.size()));
}

Source make_source(const WarpStack& stack, std::size_t k, const Deformer& deformer, int level, const Mesh& mesh,
                   std::size_t& points) {
  const auto input_of = [&](std::size_t j) {
    return j == 0 ? mesh.rest_positions() : mesh.vec3_attribute(WarpStack::input_attribute(j));
  };
  Source s{deformer, level, movable_columns(deformer, level), input_of(k), {}, {}};
  points = static_cast<std::size_t>(std::count_if(s.column.begin(), s.column.end(),
                                                   [](std::uint32_t c) { return c != kFixedPoint; }));
  for (std::size_t j = k + 1; j < stack.size(); ++j) {
    s.after.push_back(&stack.warp(j));
    s.after_input.push_back(input_of(j));
  }
  return s;
}

void write_header(std::ostream& os, const Source& s, const SensitivityCounts& counts) {
  os << "%%MatrixMarket matrix coordinate real general\n"
        "% dx/dp: row 3*v + axis + 1 for vertex v, column 3*m + axis + 1 for movable point m (axis 0-2: x, y, z)\n";
  std::string line;
  for (std::size_t id = 0; id < s.column.size(); ++id) {
    if (s.column[id] == kFixedPoint) continue;
    const PointIndex index = s.deformer.point_index(s.level, id);
    line = "% point " + std::to_string(s.column[id]) + " index ";
    line += index.grid ? std::to_string(index.ijk[0]) + " " + std::to_string(index.ijk[1]) + " " +
                             std::to_string(index.ijk[2])
                       : std::to_string(index.n);
    os << line << '\n';
  }
  os << counts.rows << ' ' << counts.columns << ' ' << counts.entries << '\n';
}

}  // namespace

std::vector<std::uint32_t> movable_columns(const Deformer& deformer, int level) {
  std::vector<std::uint32_t> column(deformer.num_points(level), kFixedPoint);
  std::uint32_t m = 0;
  for (std::size_t id = 0; id < column.size(); ++id)
    if (deformer.point_movable(level, id)) column[id] = m++;
  return column;
}

SensitivityCounts write_sensitivity(std::ostream& os, const WarpStack& stack, std::size_t k,
                                    const Deformer& deformer, int level, const Mesh& mesh) {
  SensitivityCounts counts;
  const Source s = make_source(stack, k, deformer, level, mesh, counts.points);
  const std::size_t n = mesh.num_vertices();
  counts.rows = 3 * n;
  counts.columns = 3 * counts.points;
  Rows rows;
  PointWeights w;
  // Two passes over the batches, so that the header can say how many entries follow
  // without holding them all: the first counts, the second writes.
  for (std::size_t first = 0; first < n; first += kBatch) {
    gather(s, first, std::min(n, first + kBatch), rows, w);
    for (std::size_t i = 0; i < rows.after.size(); ++i) counts.entries += entries(rows, i);
  }
  write_header(os, s, counts);
  std::vector<std::string> texts;
  for (std::size_t first = 0; first < n; first += kBatch) {
    gather(s, first, std::min(n, first + kBatch), rows, w);
    write_batch(os, rows, first, texts);
  }
  return counts;
}

}  // namespace ffd
