// A structure-aware mutator for the `run` fuzz target: most byte-level mutations of a JSON
// script are refused by the loader, so this one changes a parsed script and writes it
// back — a number, a string, a key, an element or a step — with the words of the
// script's grammar, taken from its JSON Schema, so that most inputs load and run.
#pragma once

#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ffd::fuzz {

/// The words of the script grammar: every property name, every enum and const string,
/// and every numeric bound in the JSON Schema (script/schema.h), plus file names with
/// each mesh extension.
struct Grammar {
  std::vector<std::string> keys, words;
  std::vector<double> numbers;
};
const Grammar& script_grammar();

/// Applies one random change to `doc`: a value replaced by a nearby, extreme or grammar
/// value or by a copy of another part of the document; an array element duplicated,
/// removed or swapped (steps included); an object key removed, renamed or added.
void mutate_json(nlohmann::json& doc, std::mt19937& rng, const Grammar& grammar);

/// A script of `a`'s first steps and `b`'s last ones (at least one step from either when
/// it has any); null unless both are objects with a "steps" array.
nlohmann::json cross_steps(const nlohmann::json& a, const nlohmann::json& b, std::mt19937& rng);

}  // namespace ffd::fuzz
