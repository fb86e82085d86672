#include "support/gltf_encode.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

namespace ffd::test {

namespace {

using json = nlohmann::ordered_json;
constexpr int kFloat = 5126, kUInt = 5125, kUShort = 5123, kByte = 5120;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// A document under construction with one buffer of real data (`bin`).
struct Doc {
  json j = json::object();
  std::vector<unsigned char> bin;

  Doc() {
    j["asset"] = {{"version", "2.0"}, {"generator", "ffdtool tests (gltf_encode)"}};
    j["bufferViews"] = json::array();
    j["accessors"] = json::array();
  }
  // Appends bytes to the buffer (4-byte aligned); returns their offset.
  std::size_t put(const void* data, std::size_t n) {
    bin.resize((bin.size() + 3) / 4 * 4, 0);
    const std::size_t at = bin.size();
    bin.resize(at + n);
    if (n) std::memcpy(bin.data() + at, data, n);
    return at;
  }
  int view(const void* data, std::size_t n, int target, std::size_t stride = 0) {
    json v = {{"buffer", 0}, {"byteOffset", put(data, n)}, {"byteLength", n}};
    if (stride) v["byteStride"] = stride;
    if (target) v["target"] = target;
    j["bufferViews"].push_back(v);
    return static_cast<int>(j["bufferViews"].size() - 1);
  }
  int accessor(json a) {
    j["accessors"].push_back(std::move(a));
    return static_cast<int>(j["accessors"].size() - 1);
  }
};

json bounds(const std::vector<float>& xyz) {
  std::vector<float> lo(3, INFINITY), hi(3, -INFINITY);
  for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
  return {{"min", lo}, {"max", hi}};
}

json float_accessor(int view, std::size_t count, const char* type) {
  return {{"bufferView", view}, {"componentType", kFloat}, {"count", count}, {"type", type}};
}

std::string base64(const std::vector<unsigned char>& p) {
  static const char d[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < p.size(); i += 3) {
    const unsigned v = (p[i] << 16) | (i + 1 < p.size() ? p[i + 1] << 8 : 0) | (i + 2 < p.size() ? p[i + 2] : 0);
    out += d[(v >> 18) & 63];
    out += d[(v >> 12) & 63];
    out += i + 1 < p.size() ? d[(v >> 6) & 63] : '=';
    out += i + 2 < p.size() ? d[v & 63] : '=';
  }
  return out;
}

void finish_scene(Doc& doc, json primitive, json node = json::object()) {
  doc.j["meshes"] = json::array({{{"primitives", json::array({std::move(primitive)})}}});
  node["mesh"] = 0;
  doc.j["nodes"] = json::array({std::move(node)});
  doc.j["scenes"] = json::array({{{"nodes", {0}}}});
  doc.j["scene"] = 0;
}

void plain(Doc& doc, const PlainGeometry& g) {
  const std::size_t n = g.positions.size() / 3;
  json p = float_accessor(doc.view(g.positions.data(), 4 * g.positions.size(), kArrayBuffer), n, "VEC3");
  p.update(bounds(g.positions));
  json prim = {{"attributes", {{"POSITION", doc.accessor(p)},
                               {"NORMAL", doc.accessor(float_accessor(doc.view(g.normals.data(), 4 * g.normals.size(), kArrayBuffer), n, "VEC3"))},
                               {"TEXCOORD_0", doc.accessor(float_accessor(doc.view(g.uvs.data(), 4 * g.uvs.size(), kArrayBuffer), n, "VEC2"))}}},
               {"indices", doc.accessor({{"bufferView", doc.view(g.triangles.data(), 4 * g.triangles.size(), kElementArrayBuffer)},
                                         {"componentType", kUInt}, {"count", g.triangles.size()}, {"type", "SCALAR"}})}};
  finish_scene(doc, prim);
}

int draco_attribute(draco::Mesh& m, draco::GeometryAttribute::Type type, const std::vector<float>& v, int n) {
  const std::size_t points = v.size() / n;
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, static_cast<std::uint8_t>(n), draco::DT_FLOAT32, false, sizeof(float) * n, 0);
  const int id = m.AddAttribute(ga, true, static_cast<std::uint32_t>(points));
  for (std::size_t i = 0; i < points; ++i)
    m.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)), &v[n * i]);
  return id;
}

void draco_coded(Doc& doc, const PlainGeometry& g, DracoOptions options) {
  draco::Mesh mesh;
  mesh.set_num_points(static_cast<std::uint32_t>(g.positions.size() / 3));
  const int pos = draco_attribute(mesh, draco::GeometryAttribute::POSITION, g.positions, 3);
  const int nrm = draco_attribute(mesh, draco::GeometryAttribute::NORMAL, g.normals, 3);
  const int tex = draco_attribute(mesh, draco::GeometryAttribute::TEX_COORD, g.uvs, 2);
  for (std::size_t t = 0; t + 2 < g.triangles.size(); t += 3)
    mesh.AddFace({draco::PointIndex(g.triangles[t]), draco::PointIndex(g.triangles[t + 1]), draco::PointIndex(g.triangles[t + 2])});
  draco::Encoder encoder;
  if (options.lossless) {
    encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  } else {
    encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  }
  draco::EncoderBuffer encoded;
  if (!encoder.EncodeMeshToBuffer(mesh, &encoded).ok()) throw std::runtime_error("Draco could not encode the mesh");
  // The accessors' counts are the decoded mesh's, as encoders of glTF files write them.
  draco::DecoderBuffer in;
  in.Init(encoded.data(), encoded.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok()) throw std::runtime_error("Draco could not decode its own mesh");
  const std::size_t points = decoded.value()->num_points(), corners = 3 * decoded.value()->num_faces();
  const int view = doc.view(encoded.data(), encoded.size(), 0);
  json p = {{"componentType", kFloat}, {"count", points}, {"type", "VEC3"}};
  p.update(bounds(g.positions));
  json ext = {{"bufferView", view}, {"attributes", {{"POSITION", mesh.attribute(pos)->unique_id()},
                                                   {"NORMAL", mesh.attribute(nrm)->unique_id()},
                                                   {"TEXCOORD_0", mesh.attribute(tex)->unique_id()}}}};
  json prim = {{"attributes", {{"POSITION", doc.accessor(p)},
                               {"NORMAL", doc.accessor({{"componentType", kFloat}, {"count", points}, {"type", "VEC3"}})},
                               {"TEXCOORD_0", doc.accessor({{"componentType", kFloat}, {"count", points}, {"type", "VEC2"}})}}},
               {"indices", doc.accessor({{"componentType", kUInt}, {"count", corners}, {"type", "SCALAR"}})},
               {"extensions", {{"KHR_draco_mesh_compression", ext}}}};
  finish_scene(doc, prim);
  doc.j["extensionsUsed"] = doc.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
}

// meshopt: compressed streams in buffer 0, their views in the fallback buffer 1.
struct MeshoptStreams {
  Doc& doc;
  std::size_t fallback = 0;
  std::size_t vertices = 0;

  int stream(const void* data, std::size_t count, std::size_t stride, bool indices) {
    std::vector<unsigned char> out(indices ? meshopt_encodeIndexBufferBound(count, vertices)
                                           : meshopt_encodeVertexBufferBound(count, stride));
    const std::size_t size = indices ? meshopt_encodeIndexBuffer(out.data(), out.size(), static_cast<const unsigned*>(data), count)
                                     : meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride);
    const std::size_t at = doc.put(out.data(), size);
    fallback = (fallback + 3) / 4 * 4;
    json v = {{"buffer", 1}, {"byteOffset", fallback}, {"byteLength", count * stride},
              {"target", indices ? kElementArrayBuffer : kArrayBuffer}};
    if (!indices) v["byteStride"] = stride;
    v["extensions"] = {{"EXT_meshopt_compression", {{"buffer", 0}, {"byteOffset", at}, {"byteLength", size},
                                                    {"byteStride", stride}, {"count", count},
                                                    {"mode", indices ? "TRIANGLES" : "ATTRIBUTES"}}}};
    fallback += count * stride;
    doc.j["bufferViews"].push_back(v);
    return static_cast<int>(doc.j["bufferViews"].size() - 1);
  }
};

json meshopt_coded(Doc& doc, const PlainGeometry& g) {
  const std::size_t n = g.positions.size() / 3;
  MeshoptStreams s{doc, 0, n};
  json p = float_accessor(s.stream(g.positions.data(), n, 12, false), n, "VEC3");
  p.update(bounds(g.positions));
  json prim = {{"attributes", {{"POSITION", doc.accessor(p)},
                               {"NORMAL", doc.accessor(float_accessor(s.stream(g.normals.data(), n, 12, false), n, "VEC3"))},
                               {"TEXCOORD_0", doc.accessor(float_accessor(s.stream(g.uvs.data(), n, 8, false), n, "VEC2"))}}},
               {"indices", doc.accessor({{"bufferView", s.stream(g.triangles.data(), g.triangles.size(), 4, true)},
                                         {"componentType", kUInt}, {"count", g.triangles.size()}, {"type", "SCALAR"}})}};
  finish_scene(doc, prim);
  doc.j["extensionsUsed"] = doc.j["extensionsRequired"] = {"EXT_meshopt_compression"};
  return {{"byteLength", s.fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
}

// KHR_mesh_quantization as gltfpack writes it: 14-bit unsigned positions under a node
// that scales and translates them back, normalized byte normals and short UVs.
void quantized(Doc& doc, const PlainGeometry& g) {
  const std::size_t n = g.positions.size() / 3;
  const json b = bounds(g.positions);
  std::vector<float> lo = b["min"], hi = b["max"];
  const float extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const float scale = extent / 16383.0f;
  std::vector<std::uint16_t> q(4 * n, 0), uv(2 * n);
  std::vector<std::int8_t> nq(4 * n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      q[4 * i + k] = static_cast<std::uint16_t>(std::lround((g.positions[3 * i + k] - lo[k]) / scale));
      nq[4 * i + k] = static_cast<std::int8_t>(std::lround(g.normals[3 * i + k] * 127.0f));
    }
  for (std::size_t i = 0; i < 2 * n; ++i) uv[i] = static_cast<std::uint16_t>(std::lround(std::clamp(g.uvs[i], 0.0f, 1.0f) * 65535.0f));
  std::vector<int> qlo(3, 65535), qhi(3, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) qlo[k] = std::min<int>(qlo[k], q[4 * i + k]), qhi[k] = std::max<int>(qhi[k], q[4 * i + k]);
  json prim = {{"attributes", {{"POSITION", doc.accessor({{"bufferView", doc.view(q.data(), 2 * q.size(), kArrayBuffer, 8)},
                                                          {"componentType", kUShort}, {"count", n}, {"type", "VEC3"},
                                                          {"min", qlo}, {"max", qhi}})},
                               {"NORMAL", doc.accessor({{"bufferView", doc.view(nq.data(), nq.size(), kArrayBuffer, 4)},
                                                        {"componentType", kByte}, {"normalized", true}, {"count", n}, {"type", "VEC3"}})},
                               {"TEXCOORD_0", doc.accessor({{"bufferView", doc.view(uv.data(), 2 * uv.size(), kArrayBuffer)},
                                                            {"componentType", kUShort}, {"normalized", true}, {"count", n}, {"type", "VEC2"}})}}},
               {"indices", doc.accessor({{"bufferView", doc.view(g.triangles.data(), 4 * g.triangles.size(), kElementArrayBuffer)},
                                         {"componentType", kUInt}, {"count", g.triangles.size()}, {"type", "SCALAR"}})}};
  finish_scene(doc, prim, {{"translation", lo}, {"scale", {scale, scale, scale}}});
  doc.j["extensionsUsed"] = doc.j["extensionsRequired"] = {"KHR_mesh_quantization"};
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out += static_cast<char>((v >> (8 * k)) & 0xff);
}

// The document as a GLB (buffer 0 the BIN chunk) or .gltf (data URIs); `more` are
// buffers after buffer 0 (a meshopt fallback).
std::string container(Doc& doc, bool binary, const json& more) {
  json b0 = {{"byteLength", doc.bin.size()}};
  if (!binary) b0["uri"] = "data:application/octet-stream;base64," + base64(doc.bin);
  doc.j["buffers"] = json::array({b0});
  if (!more.is_null()) doc.j["buffers"].push_back(more);
  if (!binary) return doc.j.dump(1);
  std::string text = doc.j.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  std::string bin(doc.bin.begin(), doc.bin.end());
  bin.append((4 - bin.size() % 4) % 4, '\0');
  std::string out = "glTF";
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  put_u32(out, static_cast<std::uint32_t>(text.size()));
  out += "JSON" + text;
  put_u32(out, static_cast<std::uint32_t>(bin.size()));
  out += std::string("BIN\0", 4) + bin;
  return out;
}

}  // namespace

const char* coding_name(GltfCoding coding) {
  switch (coding) {
    case GltfCoding::Plain: return "plain";
    case GltfCoding::Draco: return "draco";
    case GltfCoding::Meshopt: return "meshopt";
    default: return "quantized";
  }
}

std::string encode_gltf(const PlainGeometry& g, GltfCoding coding, bool binary, DracoOptions draco) {
  Doc doc;
  json more;
  switch (coding) {
    case GltfCoding::Plain: plain(doc, g); break;
    case GltfCoding::Draco: draco_coded(doc, g, draco); break;
    case GltfCoding::Meshopt: more = meshopt_coded(doc, g); break;
    case GltfCoding::Quantized: quantized(doc, g); break;
  }
  return container(doc, binary, more);
}

PlainGeometry obj_geometry(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  PlainGeometry g;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "v") {
      float x, y, z;
      s >> x >> y >> z;
      g.positions.insert(g.positions.end(), {x, y, z});
    } else if (key == "f") {
      std::vector<std::uint32_t> f;
      for (std::string c; s >> c;) f.push_back(static_cast<std::uint32_t>(std::stoul(c.substr(0, c.find('/')))) - 1);
      for (std::size_t k = 1; k + 1 < f.size(); ++k) g.triangles.insert(g.triangles.end(), {f[0], f[k], f[k + 1]});
    }
  }
  const std::size_t n = g.positions.size() / 3;
  std::vector<double> nrm(3 * n, 0.0);
  auto p = [&](std::uint32_t v, int k) { return static_cast<double>(g.positions[3 * v + k]); };
  for (std::size_t t = 0; t < g.triangles.size(); t += 3) {
    const std::uint32_t a = g.triangles[t], b = g.triangles[t + 1], c = g.triangles[t + 2];
    const double e[2][3] = {{p(b, 0) - p(a, 0), p(b, 1) - p(a, 1), p(b, 2) - p(a, 2)},
                            {p(c, 0) - p(a, 0), p(c, 1) - p(a, 1), p(c, 2) - p(a, 2)}};
    const double cr[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                          e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    for (std::uint32_t v : {a, b, c})
      for (int k = 0; k < 3; ++k) nrm[3 * v + k] += cr[k];
  }
  g.normals.resize(3 * n);
  g.uvs.resize(2 * n);
  const json bb = bounds(g.positions);
  const std::vector<float> lo = bb["min"], hi = bb["max"];
  for (std::size_t v = 0; v < n; ++v) {
    const double len = std::max(std::sqrt(nrm[3 * v] * nrm[3 * v] + nrm[3 * v + 1] * nrm[3 * v + 1] + nrm[3 * v + 2] * nrm[3 * v + 2]), 1e-30);
    for (int k = 0; k < 3; ++k) g.normals[3 * v + k] = static_cast<float>(nrm[3 * v + k] / len);
    for (int k = 0; k < 2; ++k) g.uvs[2 * v + k] = (g.positions[3 * v + k] - lo[k]) / std::max(hi[k] - lo[k], 1e-30f);
  }
  return g;
}

}  // namespace ffd::test
