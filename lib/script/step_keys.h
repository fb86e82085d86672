// Key tables: each key of a step declared once, with its JSON path within the step, its
// JSON Schema (type, range or enum), its default, a one-line doc, and where its value goes
// in the op's typed step (PDAL's `args.add(name, doc, member, default)`). From one table
// come the step's parser, its part of the JSON Schema, the defaults `validate --resolved`
// fills in, and its section of `ffdtool schema --markdown`.
//
//   key<RemeshStep>("/theta_max_deg", schema_number(0, 90), 25.7, "Refine an edge ...",
//                   [](auto& s) -> auto& { return s.options.theta_max_deg; })
//
// The accessor is a generic lambda returning the member, so one function both fills the
// step (parsing) and reads a default-constructed one back (the defaults test).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "script/script_values.h"

namespace ffd {

struct TableInfo;

/// One key of a step, or of the objects in a list key: what the schema, the reference
/// and the error placement need, without the parser.
struct KeyInfo {
  std::string path;              // JSON pointer within the step: "/k", "/continuity/outer"
  nlohmann::json schema;         // the value's JSON Schema: type and range, enum, or a $ref
  nlohmann::json default_value;  // filled in when the key is absent; null: none
  bool required = false;
  bool group = false;            // an object that only holds the keys under its path
  std::string doc;               // one line
  std::string argument;          // errors about this argument of the op's algorithm go here
  std::string element_suffix;    // for a list argument: element i goes to path + "/i" + suffix
  std::shared_ptr<const TableInfo> items;  // a list of objects with keys of their own
};

/// The keys of a step (or of a list key's objects) and the key groups of which exactly
/// one must be given (`move`: "points", or "select" with "transform").
struct TableInfo {
  std::vector<KeyInfo> keys;
  std::vector<std::vector<std::string>> alternatives;
};

/// The JSON Schema of an object with these keys: properties nested by path, `required`,
/// `additionalProperties: false`, defaults and descriptions, and a oneOf of the
/// alternatives' `required` lists.
nlohmann::json object_schema(const TableInfo& table);

/// The key (a JSON pointer relative to the step) that an error about `subject` concerns,
/// by the table's `about` entries; "" when no key claims it (the step as a whole).
std::string key_of(const TableInfo& table, const Subject& subject);

/// A key of a typed step (or list item) `Spec`: its description and how its value is read
/// into a `Spec` and, for keys with a default, read back out of one.
template <class Spec>
struct Key {
  KeyInfo info;
  std::function<void(Spec&, const nlohmann::json&, const ScriptPlace&)> read;
  std::function<nlohmann::json(const Spec&)> write;  // set for keys with a default

  /// The key must be given.
  Key& required() {
    info.required = true;
    return *this;
  }
  /// Errors the op's algorithm raises about `argument` belong to this key; for a list
  /// argument, element i's errors to "<key>/i<element_suffix>".
  Key& about(std::string argument, std::string element_suffix = "") {
    info.argument = std::move(argument);
    info.element_suffix = std::move(element_suffix);
    return *this;
  }
};

/// The keys of `Spec` in order, and the key groups of which exactly one must be given.
template <class Spec>
struct KeyTable {
  KeyTable(std::vector<Key<Spec>> keys_in, std::vector<std::vector<std::string>> alternatives_in = {})
      : keys(std::move(keys_in)), alternatives(std::move(alternatives_in)) {}

  std::vector<Key<Spec>> keys;
  std::vector<std::vector<std::string>> alternatives;

  TableInfo info() const {
    TableInfo t;
    for (const Key<Spec>& k : keys) t.keys.push_back(k.info);
    t.alternatives = alternatives;
    return t;
  }
  /// Fills `spec` from a schema-checked object with its defaults filled in.
  /// \throw InputError placed at the key for what the schema cannot say (a zero
  /// rotation axis, an unreadable selection file).
  void read(const nlohmann::json& object, Spec& spec, const ScriptPlace& place) const {
    for (const Key<Spec>& k : keys) {
      if (k.info.group) continue;
      const nlohmann::json::json_pointer pointer(k.info.path);
      if (object.contains(pointer)) k.read(spec, object.at(pointer), place.at(k.info.path));
    }
  }
};

/// Whether write_value can give a T back as JSON (keys with a default need it).
template <class T, class = void>
struct has_write_value : std::false_type {};
template <class T>
struct has_write_value<T, std::void_t<decltype(write_value(std::declval<const T&>()))>> : std::true_type {};

/// A key's description, with no conversion yet.
template <class Spec>
Key<Spec> bare_key(std::string path, nlohmann::json schema, nlohmann::json default_value, std::string doc) {
  Key<Spec> k;
  k.info.path = std::move(path);
  k.info.schema = std::move(schema);
  k.info.default_value = std::move(default_value);
  k.info.doc = std::move(doc);
  return k;
}

/// A key whose value lands in the member that `at` returns for a Spec (a generic lambda
/// `[](auto& s) -> auto& { return s.member; }`), converted by read_value/write_value.
template <class Spec, class Access>
Key<Spec> key(std::string path, nlohmann::json schema, nlohmann::json default_value, std::string doc, Access at) {
  using T = std::decay_t<decltype(at(std::declval<Spec&>()))>;
  Key<Spec> k = bare_key<Spec>(std::move(path), std::move(schema), std::move(default_value), std::move(doc));
  k.read = [at](Spec& s, const nlohmann::json& v, const ScriptPlace& p) { read_value(v, at(s), p); };
  if constexpr (has_write_value<T>::value)
    if (!k.info.default_value.is_null()) k.write = [at](const Spec& s) { return write_value(at(s)); };
  return k;
}

/// A key whose value is one of `names`, each standing for a value of the enum `E`.
template <class Spec, class E, class Access>
Key<Spec> enum_key(std::string path, std::vector<std::pair<std::string, E>> names, nlohmann::json default_value,
                   std::string doc, Access at) {
  nlohmann::json words = nlohmann::json::array();
  for (const auto& n : names) words.push_back(n.first);
  Key<Spec> k = bare_key<Spec>(std::move(path), {{"enum", words}}, std::move(default_value), std::move(doc));
  k.read = [at, names](Spec& s, const nlohmann::json& v, const ScriptPlace&) {
    for (const auto& n : names)
      if (v == n.first) at(s) = n.second;
  };
  if (!k.info.default_value.is_null())
    k.write = [at, names](const Spec& s) {
      for (const auto& n : names)
        if (at(s) == n.second) return nlohmann::json(n.first);
      return nlohmann::json();
    };
  return k;
}

/// The name that stands for `value` in an enum key's `names`.
template <class E>
std::string name_of(const std::vector<std::pair<std::string, E>>& names, E value) {
  for (const auto& n : names)
    if (n.second == value) return n.first;
  return "";
}

/// Runs `f`; an error it raises with no place and no subject is said to concern
/// `argument`, so the op table places it (a box the warp code cannot build: "box").
template <class F>
decltype(auto) concerning(const std::string& argument, F&& f) {
  try {
    return f();
  } catch (Error& e) {
    if (!e.placed() && e.subject().argument.empty()) e.set_subject({argument});
    throw;
  }
}

/// A key with its own conversion: `read` fills the step, `write` (for a key with a
/// default) gives a default-constructed step's value as JSON.
template <class Spec>
Key<Spec> custom_key(std::string path, nlohmann::json schema, nlohmann::json default_value, std::string doc,
                     std::function<void(Spec&, const nlohmann::json&, const ScriptPlace&)> read,
                     std::function<nlohmann::json(const Spec&)> write = nullptr) {
  Key<Spec> k = bare_key<Spec>(std::move(path), std::move(schema), std::move(default_value), std::move(doc));
  k.read = std::move(read);
  k.write = std::move(write);
  return k;
}

/// An object key that only groups the keys under its path ("/continuity").
template <class Spec>
Key<Spec> group_key(std::string path, std::string doc) {
  Key<Spec> k;
  k.info.path = std::move(path);
  k.info.group = true;
  k.info.doc = std::move(doc);
  return k;
}

/// A non-empty list of objects, each read by `items` into an `Item` appended to the
/// vector that `at` returns.
template <class Spec, class Item, class Access>
Key<Spec> list_key(std::string path, KeyTable<Item> items, std::string doc, Access at) {
  Key<Spec> k;
  k.info.path = std::move(path);
  k.info.doc = std::move(doc);
  k.info.items = std::make_shared<TableInfo>(items.info());
  k.read = [at, items](Spec& s, const nlohmann::json& v, const ScriptPlace& p) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      Item item;
      items.read(v[i], item, p.at("/" + std::to_string(i)));
      at(s).push_back(std::move(item));
    }
  };
  return k;
}

// Schema fragments for key tables.
nlohmann::json schema_number(std::optional<double> min = {}, std::optional<double> max = {});
nlohmann::json schema_integer(std::optional<long> min = {}, std::optional<long> max = {});
/// A non-empty string.
nlohmann::json schema_text();
nlohmann::json schema_boolean();
/// A reference to a type of the shared grammar ("vec3", "selection", "transform", "box").
nlohmann::json schema_ref(const std::string& type);

}  // namespace ffd
