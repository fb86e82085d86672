#include "mesh/gltf_repack.h"

#include <algorithm>

namespace ffd {

namespace {

const tinygltf::Value* meshopt_extension(const tinygltf::ExtensionMap& extensions) {
  for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    const auto it = extensions.find(name);
    if (it != extensions.end() && it->second.IsObject()) return &it->second;
  }
  return nullptr;
}

// The compressed-stream buffers (`compressed`) and the fallback buffers (`fallback`) of
// the model's meshopt extensions; false when it has none.
bool meshopt_buffers(const tinygltf::Model& model, std::vector<bool>& compressed, std::vector<bool>& fallback) {
  const std::size_t n = model.buffers.size();
  compressed.assign(n, false);
  fallback.assign(n, false);
  bool any = false;
  for (const tinygltf::BufferView& view : model.bufferViews) {
    const tinygltf::Value* ext = meshopt_extension(view.extensions);
    if (!ext || !ext->Get("buffer").IsNumber()) continue;
    const int source = ext->Get("buffer").GetNumberAsInt();
    if (source >= 0 && static_cast<std::size_t>(source) < n) compressed[static_cast<std::size_t>(source)] = any = true;
  }
  for (std::size_t b = 0; b < n; ++b) {
    const tinygltf::Value* ext = meshopt_extension(model.buffers[b].extensions);
    fallback[b] = ext && ext->Get("fallback").IsBool() && ext->Get("fallback").Get<bool>();
  }
  return any;
}

// Appends to `out` the bytes of `data` that the views `members` (indices into `views`,
// all of one buffer) cover: each run of touching or overlapping views together, at an
// offset equal to its old one modulo 8, zeros between. The views are re-pointed at
// buffer `target`. (Bytes a view claims past the data's end, which no reader accepted,
// are zeros.)
void pack_views(const std::vector<unsigned char>& data, std::vector<int> members,
                std::vector<tinygltf::BufferView>& views, int target, std::vector<unsigned char>& out) {
  std::sort(members.begin(), members.end(), [&](int a, int b) {
    return views[a].byteOffset != views[b].byteOffset ? views[a].byteOffset < views[b].byteOffset : a < b;
  });
  std::size_t k = 0;
  while (k < members.size()) {
    const std::size_t begin = views[members[k]].byteOffset;
    std::size_t end = begin + views[members[k]].byteLength, last = k + 1;
    for (; last < members.size() && views[members[last]].byteOffset <= end; ++last)
      end = std::max(end, views[members[last]].byteOffset + views[members[last]].byteLength);
    const std::size_t at = out.size() + (begin + 8 - out.size() % 8) % 8;
    out.resize(at + (end - begin), 0);
    if (begin < data.size())
      std::copy(data.begin() + static_cast<std::ptrdiff_t>(begin),
                data.begin() + static_cast<std::ptrdiff_t>(std::min(end, data.size())),
                out.begin() + static_cast<std::ptrdiff_t>(at));
    for (std::size_t j = k; j < last; ++j) {
      views[members[j]].byteOffset = at + (views[members[j]].byteOffset - begin);
      views[members[j]].buffer = target;
    }
    k = last;
  }
}

// Removes the buffers `gone` says, renumbering the views; returns each kept buffer's old
// index.
std::vector<int> drop_buffers(tinygltf::Model& model, const std::vector<bool>& gone) {
  std::vector<int> origin, renumbered(model.buffers.size(), -1);
  std::vector<tinygltf::Buffer> kept;
  for (std::size_t b = 0; b < model.buffers.size(); ++b) {
    if (gone[b]) continue;
    renumbered[b] = static_cast<int>(kept.size());
    origin.push_back(static_cast<int>(b));
    kept.push_back(std::move(model.buffers[b]));
  }
  model.buffers = std::move(kept);
  for (tinygltf::BufferView& view : model.bufferViews)
    if (view.buffer >= 0 && static_cast<std::size_t>(view.buffer) < renumbered.size())
      view.buffer = renumbered[static_cast<std::size_t>(view.buffer)];
  return origin;
}

}  // namespace

std::vector<int> repack_meshopt_buffers(tinygltf::Model& model, bool binary) {
  std::vector<bool> compressed, fallback;
  if (!meshopt_buffers(model, compressed, fallback)) return {};
  const std::size_t n = model.buffers.size();
  std::vector<std::vector<int>> members(n);
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    const int b = model.bufferViews[v].buffer;
    if (b >= 0 && static_cast<std::size_t>(b) < n) members[static_cast<std::size_t>(b)].push_back(static_cast<int>(v));
  }
  const auto merged = [&](std::size_t b) { return binary && b > 0 && fallback[b]; };
  for (std::size_t b = 0; b < n; ++b) {
    if (!compressed[b] || merged(b)) continue;
    std::vector<unsigned char> packed;
    pack_views(model.buffers[b].data, members[b], model.bufferViews, static_cast<int>(b), packed);
    model.buffers[b].data = std::move(packed);
  }
  std::vector<bool> gone(n, false);
  for (std::size_t b = 1; b < n; ++b) {
    if (!merged(b)) continue;
    pack_views(model.buffers[b].data, members[b], model.bufferViews, 0, model.buffers[0].data);
    if (!members[b].empty()) members[0].push_back(members[b].front());  // buffer 0 has a view now
    gone[b] = true;
  }
  for (std::size_t b = 0; b < n; ++b)
    if ((compressed[b] || fallback[b]) && members[b].empty()) gone[b] = true;
  return drop_buffers(model, gone);
}

}  // namespace ffd
