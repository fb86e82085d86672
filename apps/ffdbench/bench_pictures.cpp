// glTF I/O and pictures, each against a baseline measured in the same run (medians over
// ctx.repeats after one warm-up; --quick: small sizes, one repeat):
// - gltf: the io suite's height-field grid (height_field) at 100k and 1M vertices (~200k
//   and ~2M triangles), written with write_mesh as .glb, as .gltf with its external .bin,
//   and as binary PLY (the baseline: our fastest mesh format so far). Per format, read_mesh
//   of that file and write_mesh of the mesh read back to another file (the round trip
//   ffdtool run makes; also the first write, from the generated mesh, which has no glTF
//   source), as MB/s (MB = 10^6 bytes of the files, a .gltf's .bin counted too) and as
//   the ratio to binary PLY's MB/s and time.
// - render: render_mesh (default options: shaded, iso view, orthographic) of grids of
//   ~100k and ~1M triangles at 640x480 and 1280x960, on one thread and on every core
//   (omp_set_num_threads). Baselines: `zbuffer_fill_ms`, one thread filling a W x H
//   buffer of doubles with +inf in a fresh mapping (the renderer's depth buffer alone:
//   the per-pixel floor), and `read_ply_ms`, read_mesh of the same mesh as binary PLY (the
//   per-triangle floor of rendering a file).
// - png: write_png of each mesh's 1280x960 image into memory, against writing the same
//   pixels uncompressed (a binary PPM: header + RGB bytes) into memory.
// The tables go to stderr (stdout is the JSON when there is no -o).
#include <omp.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "bench.h"
#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "render/png_io.h"
#include "render/render.h"

namespace ffd::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

/// A file format of the gltf rows: its row name and extension. Binary PLY is the baseline.
struct PictureFormat {
  const char* name;
  const char* ext;
};
constexpr PictureFormat kGlb{"glb", ".glb"}, kGltf{"gltf+bin", ".gltf"}, kPly{"ply_binary", ".ply"};

/// Grid sides of the gltf rows: 317 (100,489 vertices) and 1001 (1,002,001), the io
/// suite's; quick: 142 (20,164).
std::vector<int> gltf_sides(bool quick) { return quick ? std::vector<int>{142} : std::vector<int>{317, 1001}; }

/// Grid sides of the render rows: 225 (100,352 triangles) and 708 (999,698); quick: 100
/// (19,602).
std::vector<int> render_sides(bool quick) { return quick ? std::vector<int>{100} : std::vector<int>{225, 708}; }

/// The grid mesh of side n (n² vertices, 2 (n-1)² triangles).
Mesh grid(int n) { return build_mesh(height_field(n), "grid"); }

/// Writes `mesh` to `path` as write_mesh does (a .ply in binary); returns the bytes of
/// every file written (a .gltf's .bin files too).
double write_as(const std::string& path, const Mesh& mesh, WriteOptions::Encoding encoding) {
  WriteOptions options;
  options.encoding = encoding;
  std::size_t bytes = 0;
  for (StagedFile& f : stage_mesh_files(path, mesh, options, &bytes)) f.commit();
  return static_cast<double>(bytes);
}

/// One gltf row: `mesh` written as `f` (write_new_ms: from the generated mesh, which has
/// no glTF source), then read_mesh of that file and write_mesh of the mesh read back into
/// another file of the same format (write_ms: the round trip), medians over `repeats`.
json format_row(const PictureFormat& f, const Mesh& mesh, const TempFolder& dir, int repeats) {
  const std::string tag = "grid-" + std::to_string(mesh.num_vertices()) + "-" + (f.ext + 1);
  const std::string in = dir.file(tag + f.ext), out = dir.file(tag + "-out" + f.ext);
  double bytes = 0;
  const double new_ms = median_ms(repeats, [&] { bytes = write_as(in, mesh, WriteOptions::Encoding::Binary); });
  std::size_t read_vertices = 0;
  const double read_ms = median_ms(repeats, [&] { read_vertices = read_mesh(in).num_vertices(); });
  const Mesh back = read_mesh(in);
  double write_bytes = 0;
  const double write_ms = median_ms(repeats, [&] { write_bytes = write_as(out, back, WriteOptions::Encoding::Auto); });
  json r = {{"format", f.name},
            {"vertices", mesh.num_vertices()},
            {"triangles", mesh.num_faces()},
            {"bytes", bytes},
            {"read_ms", read_ms},
            {"read_mb_per_s", mb_per_s(bytes, read_ms)},
            {"write_ms", write_ms},
            {"write_bytes", write_bytes},
            {"write_mb_per_s", mb_per_s(write_bytes, write_ms)},
            {"write_new_ms", new_ms},
            {"write_new_mb_per_s", mb_per_s(bytes, new_ms)}};
  if (read_vertices != mesh.num_vertices()) r["vertices_read"] = read_vertices;
  return r;
}

/// Adds to `r` its ratios to the binary PLY row `ply` of the same mesh.
void add_ply_ratios(json& r, const json& ply) {
  const auto ratio = [&](const char* key) { return r[key].get<double>() / ply[key].get<double>(); };
  r["read_mb_per_s_vs_ply"] = ratio("read_mb_per_s");
  r["write_mb_per_s_vs_ply"] = ratio("write_mb_per_s");
  r["read_ms_vs_ply"] = ratio("read_ms");
  r["write_ms_vs_ply"] = ratio("write_ms");
  r["write_new_mb_per_s_vs_ply"] = ratio("write_new_mb_per_s");
  r["bytes_vs_ply"] = ratio("bytes");
}

/// The gltf rows: per grid size, binary PLY (the baseline), .glb and .gltf + .bin.
json gltf_rows(const Context& ctx, const TempFolder& dir) {
  json rows = json::array();
  for (int n : gltf_sides(ctx.quick)) {
    const Mesh mesh = grid(n);
    std::fprintf(stderr, "ffdbench: pictures: gltf, %zu vertices\n", mesh.num_vertices());
    json ply = format_row(kPly, mesh, dir, ctx.repeats);
    ply["case"] = "baseline";
    for (const PictureFormat& f : {kGlb, kGltf}) {
      json r = format_row(f, mesh, dir, ctx.repeats);
      add_ply_ratios(r, ply);
      rows.push_back(r);
    }
    rows.push_back(ply);
  }
  return rows;
}

/// Median ms of one thread filling `pixels` doubles with +inf in a fresh anonymous
/// mapping (page faults included, as the renderer's buffers pay them: malloc maps and
/// unmaps buffers this large), unmapped after.
double zbuffer_fill_ms(std::size_t pixels, int repeats) {
  const std::size_t bytes = pixels * sizeof(double);
  return median_ms(repeats, [&] {
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw IoError("mmap: " + std::string(std::strerror(errno)));
    std::fill_n(static_cast<double*>(p), pixels, std::numeric_limits<double>::infinity());
    asm volatile("" : : "r"(p) : "memory");  // keep the fill
    ::munmap(p, bytes);
  });
}

/// The render baselines of one mesh: read_mesh of it as binary PLY.
double read_ply_ms(const Mesh& mesh, const TempFolder& dir, int repeats) {
  const std::string path = dir.file("render-" + std::to_string(mesh.num_faces()) + ".ply");
  write_as(path, mesh, WriteOptions::Encoding::Binary);
  return median_ms(repeats, [&] { read_mesh(path); });
}

/// render_mesh of `mesh` at w x h on `threads` threads: median ms; `image` gets the picture.
double render_ms(const Mesh& mesh, int w, int h, int threads, int repeats, Image& image) {
  RenderOptions o;
  o.width = w;
  o.height = h;
  omp_set_num_threads(threads);
  const double ms = median_ms(repeats, [&] { image = render_mesh(mesh, o); });
  omp_set_num_threads(omp_get_num_procs());
  return ms;
}

/// The share of `image`'s pixels that differ from the (white) background.
double covered(const Image& image) {
  std::size_t n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += !(image.at(x, y) == Rgb{255, 255, 255});
  return double(n) / (double(image.width) * image.height);
}

/// The png row of `image`: write_png into memory against the same pixels as binary PPM.
json png_row(const Image& image, std::size_t triangles, double render_all_ms, int repeats) {
  std::size_t png_bytes = 0;
  const double png_ms = median_ms(repeats, [&] {
    std::ostringstream os;
    write_png(os, image);
    png_bytes = os.str().size();
  });
  std::size_t ppm_bytes = 0;
  const double ppm_ms = median_ms(repeats, [&] {
    std::ostringstream os;
    os << "P6\n" << image.width << " " << image.height << "\n255\n";
    os.write(reinterpret_cast<const char*>(image.rgb.data()), static_cast<std::streamsize>(image.rgb.size()));
    ppm_bytes = os.str().size();
  });
  return {{"triangles", triangles},   {"width", image.width},
          {"height", image.height},   {"png_bytes", png_bytes},
          {"write_png_ms", png_ms},   {"pixel_mb_per_s", mb_per_s(double(image.rgb.size()), png_ms)},
          {"write_ppm_ms", ppm_ms},   {"ppm_bytes", ppm_bytes},
          {"png_vs_ppm", png_ms / ppm_ms}, {"png_vs_render_all_threads", png_ms / render_all_ms}};
}

/// The render rows of one mesh (both sizes, one thread and every core), and its png row
/// (the 1280x960 picture) appended to `png`.
json render_rows(const Mesh& mesh, const TempFolder& dir, int repeats, json& png) {
  const double read_ms = read_ply_ms(mesh, dir, repeats);
  const int cores = omp_get_num_procs();
  json rows = json::array();
  for (const auto& [w, h] : {std::pair{640, 480}, std::pair{1280, 960}}) {
    const double fill_ms = zbuffer_fill_ms(std::size_t(w) * h, repeats);
    Image image;
    double one_ms = 0;
    for (int threads : {1, cores}) {
      if (threads == cores && cores == 1 && one_ms > 0) break;
      std::fprintf(stderr, "ffdbench: pictures: render %zu triangles, %dx%d, %d thread(s)\n", mesh.num_faces(), w, h,
                   threads);
      const double ms = render_ms(mesh, w, h, threads, repeats, image);
      if (threads == 1) one_ms = ms;
      rows.push_back({{"triangles", mesh.num_faces()}, {"vertices", mesh.num_vertices()},
                      {"width", w}, {"height", h}, {"threads", threads}, {"render_ms", ms},
                      {"mtriangles_per_s", mesh.num_faces() / ms / 1e3}, {"covered_pixels", covered(image)},
                      {"zbuffer_fill_ms", fill_ms}, {"render_vs_zbuffer_fill", ms / fill_ms},
                      {"read_ply_ms", read_ms}, {"render_vs_read_ply", ms / read_ms},
                      {"speedup_vs_one_thread", one_ms / ms}});
    }
    if (w == 1280) png.push_back(png_row(image, mesh.num_faces(), rows.back()["render_ms"].get<double>(), repeats));
  }
  return rows;
}

/// `x` printed with `digits` decimals.
std::string num(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

/// Prints `rows` under `header` to stderr, columns right-aligned to their widest cell.
void print_table(const std::string& title, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size() && c < width.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::fprintf(stderr, "\n%s\n", title.c_str());
  const auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t c = 0; c < cells.size(); ++c)
      std::fprintf(stderr, "%s%*s", c ? "  " : "", static_cast<int>(width[c]), cells[c].c_str());
    std::fprintf(stderr, "\n");
  };
  line(header);
  for (const auto& row : rows) line(row);
}

/// The value of `key` in `r` with `digits` decimals, or "-" when absent.
std::string cell(const json& r, const char* key, int digits) {
  return r.contains(key) ? num(r[key].get<double>(), digits) : "-";
}

void print_tables(const json& gltf, const json& render, const json& png) {
  std::vector<std::vector<std::string>> rows;
  for (const json& r : gltf)
    rows.push_back({r["format"].get<std::string>() + (r.contains("case") ? " (baseline)" : ""), std::to_string(r["vertices"].get<std::size_t>()), num(r["bytes"].get<double>() / 1e6, 1),
                    cell(r, "read_ms", 1), cell(r, "read_mb_per_s", 0), cell(r, "write_ms", 1),
                    cell(r, "write_mb_per_s", 0), cell(r, "write_new_ms", 1), cell(r, "read_mb_per_s_vs_ply", 2),
                    cell(r, "write_mb_per_s_vs_ply", 2), cell(r, "write_new_mb_per_s_vs_ply", 2)});
  print_table("pictures: glTF against binary PLY (MB = 10^6 file bytes; write: of the mesh read back; new: of the "
              "generated mesh; ratios of MB/s, PLY = 1)",
              {"format", "vertices", "MB", "read ms", "read MB/s", "write ms", "write MB/s", "new ms", "read/PLY",
               "write/PLY", "new/PLY"},
              rows);
  rows.clear();
  for (const json& r : render)
    rows.push_back({std::to_string(r["triangles"].get<std::size_t>()),
                    std::to_string(r["width"].get<int>()) + "x" + std::to_string(r["height"].get<int>()),
                    std::to_string(r["threads"].get<int>()), cell(r, "render_ms", 1), cell(r, "mtriangles_per_s", 2),
                    cell(r, "speedup_vs_one_thread", 2), cell(r, "zbuffer_fill_ms", 2),
                    cell(r, "render_vs_zbuffer_fill", 1), cell(r, "read_ply_ms", 1), cell(r, "render_vs_read_ply", 2)});
  print_table("pictures: render_mesh against a one-thread z-buffer fill (W x H doubles, fresh pages) and read_mesh of "
              "the mesh as binary PLY",
              {"triangles", "size", "threads", "ms", "Mtri/s", "speedup", "zfill ms", "vs zfill", "read ms", "vs read"},
              rows);
  rows.clear();
  for (const json& r : png)
    rows.push_back({std::to_string(r["triangles"].get<std::size_t>()),
                    std::to_string(r["width"].get<int>()) + "x" + std::to_string(r["height"].get<int>()),
                    num(r["png_bytes"].get<double>() / 1e3, 1), cell(r, "write_png_ms", 1), cell(r, "write_ppm_ms", 2),
                    cell(r, "png_vs_ppm", 1), cell(r, "png_vs_render_all_threads", 2)});
  print_table("pictures: write_png (into memory) against the same pixels as binary PPM",
              {"triangles", "size", "PNG kB", "png ms", "ppm ms", "vs ppm", "vs render"}, rows);
  std::fprintf(stderr, "\n");
}

}  // namespace

void bench_pictures(Context& ctx) {
  const TempFolder dir("pictures");
  const json gltf = gltf_rows(ctx, dir);
  json render = json::array(), png = json::array();
  for (int n : render_sides(ctx.quick)) {
    const Mesh mesh = grid(n);
    for (json& r : render_rows(mesh, dir, ctx.repeats, png)) render.push_back(std::move(r));
  }
  print_tables(gltf, render, png);
  ctx.out["pictures"] = {{"gltf", gltf}, {"render", render}, {"png", png}};
}

}  // namespace ffd::bench
