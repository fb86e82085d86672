#include "json_mutator.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <set>

#include "script/schema.h"

namespace ffd::fuzz {
using json = nlohmann::json;

namespace {

// Collects the schema's property names, enum and const strings and numeric bounds.
void harvest(const json& schema, std::set<std::string>& keys, std::set<std::string>& words, std::set<double>& numbers) {
  if (schema.is_array()) {
    for (const json& item : schema) harvest(item, keys, words, numbers);
    return;
  }
  if (!schema.is_object()) return;
  for (const auto& [key, value] : schema.items()) {
    if (key == "properties" && value.is_object())
      for (const auto& [name, sub] : value.items()) keys.insert(name);
    if ((key == "enum" || key == "const") && !value.is_object()) {
      for (const json& v : value.is_array() ? value : json::array({value}))
        if (v.is_string()) words.insert(v.get<std::string>());
    }
    if ((key == "minimum" || key == "maximum" || key == "default") && value.is_number())
      numbers.insert(value.get<double>());
    harvest(value, keys, words, numbers);
  }
}

std::size_t pick(std::mt19937& rng, std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); }

// Every value in `doc`, the document itself included, depth first.
void collect(json& doc, std::vector<json*>& nodes) {
  nodes.push_back(&doc);
  if (doc.is_structured())
    for (json& child : doc) collect(child, nodes);
}

// v + d in two's complement, without the signed overflow that UBSan would report.
std::int64_t wrapped(std::int64_t v, std::uint64_t d) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(v) + d); }

json mutate_integer(std::int64_t v, std::mt19937& rng, const Grammar& g) {
  switch (pick(rng, 8)) {
    case 0: return wrapped(v, 1);
    case 1: return wrapped(v, ~std::uint64_t{0});
    case 2: return wrapped(v, static_cast<std::uint64_t>(v));
    case 3: return wrapped(0, ~static_cast<std::uint64_t>(v) + 1);
    case 4: return static_cast<std::int64_t>(pick(rng, 12));
    case 5: return static_cast<std::int64_t>(g.numbers[pick(rng, g.numbers.size())]);
    case 6: return std::int64_t{1} << pick(rng, 63);
    default: return std::numeric_limits<std::int64_t>::min() + static_cast<std::int64_t>(pick(rng, 2));
  }
}

json mutate_number(double v, std::mt19937& rng, const Grammar& g) {
  switch (pick(rng, 10)) {
    case 0: return v * std::uniform_real_distribution<double>(-2, 2)(rng);
    case 1: return v + std::uniform_real_distribution<double>(-1, 1)(rng);
    case 2: return std::nextafter(v, pick(rng, 2) ? 1e308 : -1e308);
    case 3: return v + 1e-9;
    case 4: return -0.0;
    case 5: return pick(rng, 2) ? 1e-300 : 5e-324;
    case 6: return pick(rng, 2) ? 1e300 : -1e300;
    case 7: return g.numbers[pick(rng, g.numbers.size())];
    case 8: return 0.5 * static_cast<double>(pick(rng, 5));
    default: return std::uniform_real_distribution<double>(-1.5, 1.5)(rng);
  }
}

void mutate_array(json& a, std::mt19937& rng) {
  if (a.empty()) return;
  const std::size_t i = pick(rng, a.size()), j = pick(rng, a.size());
  switch (pick(rng, 4)) {
    case 0: a.insert(a.begin() + static_cast<std::ptrdiff_t>(j), json(a[i])); break;
    case 1: a.erase(a.begin() + static_cast<std::ptrdiff_t>(i)); break;
    case 2: std::swap(a[i], a[j]); break;
    default: a.push_back(json(a[i])); break;
  }
}

// Removes a key (most often: its default comes back), renames one, or adds one with a
// copy of another value.
void mutate_object(json& o, const json& other, std::mt19937& rng, const Grammar& g) {
  const std::string key = g.keys[pick(rng, g.keys.size())];
  const std::size_t what = pick(rng, 5);
  if (o.empty() || what == 0) {
    o[key] = other;
    return;
  }
  auto it = o.begin();
  std::advance(it, static_cast<std::ptrdiff_t>(pick(rng, o.size())));
  json value = *it;
  const std::string old_key = it.key();
  o.erase(old_key);
  if (what == 1) o[key] = std::move(value);
}

// A string of the document (a name used elsewhere) or a word of the grammar.
json other_string(const std::vector<json*>& nodes, std::mt19937& rng, const Grammar& g) {
  std::vector<const json*> strings;
  for (const json* n : nodes)
    if (n->is_string()) strings.push_back(n);
  if (!strings.empty() && pick(rng, 2)) return *strings[pick(rng, strings.size())];
  return g.words[pick(rng, g.words.size())];
}

}  // namespace

const Grammar& script_grammar() {
  static const Grammar grammar = [] {
    std::set<std::string> keys, words;
    std::set<double> numbers{0, 1, -1};
    harvest(script_schema(), keys, words, numbers);
    for (const char* file : {"a.obj", "b.off", "c.ply", "d.stl", "f_{i}.obj", "{i}.ply", "x.txt", "../e.obj"})
      words.insert(file);
    Grammar g;
    g.keys.assign(keys.begin(), keys.end());
    g.words.assign(words.begin(), words.end());
    g.numbers.assign(numbers.begin(), numbers.end());
    return g;
  }();
  return grammar;
}

void mutate_json(json& doc, std::mt19937& rng, const Grammar& g) {
  std::vector<json*> nodes;
  collect(doc, nodes);
  json* chosen = nodes[pick(rng, nodes.size())];
  if (chosen->is_structured() && pick(rng, 2)) chosen = nodes[pick(rng, nodes.size())];  // values more often
  json& node = *chosen;
  const json other = *nodes[pick(rng, nodes.size())];
  if (&node != &doc && pick(rng, 8) == 0) {
    node = other;  // a copy of another part; never the whole document by a part of itself
    return;
  }
  switch (node.type()) {
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: node = mutate_integer(node.get<std::int64_t>(), rng, g); break;
    case json::value_t::number_float: node = mutate_number(node.get<double>(), rng, g); break;
    case json::value_t::string: node = other_string(nodes, rng, g); break;
    case json::value_t::boolean: node = !node.get<bool>(); break;
    case json::value_t::array: mutate_array(node, rng); break;
    case json::value_t::object: mutate_object(node, other, rng, g); break;
    default: node = 0; break;
  }
}

json cross_steps(const json& a, const json& b, std::mt19937& rng) {
  const auto steps_of = [](const json& doc) -> const json* {
    if (!doc.is_object() || !doc.contains("steps") || !doc["steps"].is_array()) return nullptr;
    return &doc["steps"];
  };
  const json *sa = steps_of(a), *sb = steps_of(b);
  if (!sa || !sb) return nullptr;
  json out = a;
  json& steps = out["steps"] = json::array();
  const std::size_t keep = sa->empty() ? 0 : 1 + pick(rng, sa->size());
  const std::size_t from = sb->empty() ? 0 : pick(rng, sb->size());
  for (std::size_t i = 0; i < keep; ++i) steps.push_back((*sa)[i]);
  for (std::size_t i = from; i < sb->size(); ++i) steps.push_back((*sb)[i]);
  return out;
}

}  // namespace ffd::fuzz
