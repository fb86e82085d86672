// put_ordered: the writers' lines formatted by a team in blocks and written in order, the
// same bytes whatever the thread count; and the OBJ, OFF, PLY and STL text writers through it.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/obj_io.h"
#include "mesh/text_sink.h"
#include "support/with_threads.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using test::with_threads;

// Item i: its number, a shortest round-trip double, and i % 7 letters (lines of varied length).
std::string ordered_text(std::size_t first, std::size_t last) {
  std::ostringstream os;
  TextSink out(os);
  out.put("head\n");
  put_ordered(out, first, last, [](TextSink& line, std::size_t i) {
    line.integer(static_cast<std::uint64_t>(i));
    line.put(' ');
    line.number(1.0 / static_cast<double>(i + 3));
    line.put(std::string(i % 7, 'x'));
    line.put('\n');
  });
  out.put("tail\n");
  out.flush();
  return os.str();
}

TEST(PutOrdered, WritesTheSameBytesWhateverTheThreadCount) {
  for (const auto& range : std::vector<std::pair<std::size_t, std::size_t>>{
           {0, 0}, {0, 1}, {0, 16383}, {0, 16384}, {5, 4096 * 7 + 5}, {0, 4096 * 9 + 1}, {3, 100003}}) {
    const std::size_t first = range.first, last = range.second;  // (a lambda cannot capture a binding in C++17)
    SCOPED_TRACE(std::to_string(first) + ".." + std::to_string(last));
    const std::string one = with_threads(1, [&] { return ordered_text(first, last); });
    EXPECT_EQ(one.substr(0, 5), "head\n");
    EXPECT_EQ(std::count(one.begin(), one.end(), '\n'), static_cast<long>(last - first + 2));
    for (int threads : {2, 3, 5}) EXPECT_EQ(with_threads(threads, [&] { return ordered_text(first, last); }), one) << threads;
  }
}

// A stream whose writes fail after `room` bytes, with badbit throwing as the staged files' do.
class FailingBuffer : public std::streambuf {
public:
  explicit FailingBuffer(std::size_t room) : room_(room) {}

protected:
  std::streamsize xsputn(const char*, std::streamsize n) override {
    if (static_cast<std::size_t>(n) > room_) return 0;
    room_ -= static_cast<std::size_t>(n);
    return n;
  }
  int overflow(int c) override { return room_ ? (--room_, c) : traits_type::eof(); }

private:
  std::size_t room_;
};

TEST(PutOrdered, AFormatterOrAWriteThatFailsThrowsOutOfTheTeam) {
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    const auto format_fails = [] {
      std::ostringstream os;
      TextSink out(os);
      put_ordered(out, 0, 50000, [](TextSink& line, std::size_t i) {
        if (i == 31234) throw std::runtime_error("item 31234");
        line.integer(static_cast<std::uint64_t>(i));
      });
      return 0;
    };
    EXPECT_THROW(with_threads(threads, format_fails), std::runtime_error);
    const auto write_fails = [] {
      FailingBuffer buffer(100000);
      std::ostream os(&buffer);
      os.exceptions(std::ios::badbit);
      TextSink out(os);
      put_ordered(out, 0, 50000, [](TextSink& line, std::size_t i) {
        line.integer(static_cast<std::uint64_t>(i));
        line.put('\n');
      });
      out.flush();
      return 0;
    };
    EXPECT_THROW(with_threads(threads, write_fails), std::ios::failure);
  }
}

// An OBJ of 40k vertices with w components, UVs and normals on the faces, groups changing
// along the faces, and statements before the vertices and after the last face; and the
// same with a statement between two faces, which the writer keeps in place.
std::string big_obj(bool statement_between) {
  std::ostringstream os;
  os << "# made by the test\nmtllib m.mtl\n";
  const int n = 200;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) os << "v " << i * 0.1 << ' ' << j * 0.3 << ' ' << (i * j) % 7 << (i % 3 ? "" : " 0.5") << '\n';
  os << "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
  for (int j = 0; j + 1 < n; ++j) {
    if (j % 40 == 0) os << "g band" << j / 40 << "\nusemtl m" << j % 3 << '\n';
    if (statement_between && j == 100) os << "bevel on\n";  // kept, between faces
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i + 1, b = a + 1, c = a + n;
      os << "f " << a << "/1/1 " << b << "/2/1 " << c << "/3/1\n";
    }
  }
  os << "# the end\n";
  return os.str();
}

std::string written(const Mesh& mesh, const std::string& format) {
  std::ostringstream os;
  const MeshFormat kind = format == "obj"   ? MeshFormat::Obj
                          : format == "off" ? MeshFormat::Off
                          : format == "ply" ? MeshFormat::Ply
                                            : MeshFormat::Stl;
  write_mesh(os, kind, mesh);  // PLY and STL in ASCII, as the OBJ source is
  return os.str();
}

TEST(PutOrdered, TextWritersGiveTheSameFileWhateverTheThreadCount) {
  for (bool between : {false, true}) {
    SCOPED_TRACE(between);
    const std::string text = big_obj(between);
    const Mesh mesh = build_mesh(read_obj(text, "big.obj"), "big.obj");
    ASSERT_EQ(mesh.num_vertices(), 40000u);
    for (const std::string format : {"obj", "off", "ply", "stl"}) {
      const std::string one = with_threads(1, [&] { return written(mesh, format); });
      for (int threads : {2, 3})  // (EXPECT_TRUE: a failed EXPECT_EQ would diff megabytes)
        EXPECT_TRUE(with_threads(threads, [&] { return written(mesh, format); }) == one) << format << ' ' << threads;
      if (format != "obj") continue;
      // Everything the file said is written back: read again, the file is written the same.
      const Mesh again = build_mesh(read_obj(one, "again.obj"), "again.obj");
      EXPECT_TRUE(with_threads(2, [&] { return written(again, format); }) == one);
      if (between) {  // in place: after the first face, before the last
        const std::size_t at = one.find("bevel on\n");
        ASSERT_NE(at, std::string::npos);
        EXPECT_LT(one.find("\nf "), at);
        EXPECT_GT(one.rfind("\nf "), at);
      }
    }
  }
}

}  // namespace
}  // namespace ffd
