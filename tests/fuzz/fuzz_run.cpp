// libFuzzer target for running a script: the runner and every op, on a small closed
// sphere, exactly as `ffdtool run` runs a script (tests/fuzz/run_input.h). Any of
// ffdtool's errors (InputError, TopologyError, SolverError, IoError) is an expected
// outcome; scripts over the harness's cost budget are skipped.
//
// Byte mutations of JSON mostly make scripts the loader refuses, so the mutations here
// are structural (tests/fuzz/json_mutator.h), and a mutation is tried again (up to 8
// times) until the loader takes it: most inputs run. At exit the target prints how many
// inputs had each outcome.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <string_view>

#include "common/errors.h"
#include "json_mutator.h"
#include "run_input.h"
#include "script/script.h"

namespace {

using Outcome = ffd::fuzz::RunSandbox::Outcome;
using json = nlohmann::json;

constexpr int kAttempts = 8;

struct Tally {
  std::array<std::size_t, 4> counts{};
  ~Tally() {
    std::fprintf(stderr, "fuzz_run: refused %zu, over budget %zu, failed while running %zu, ran %zu\n",
                 counts[static_cast<int>(Outcome::Refused)], counts[static_cast<int>(Outcome::OverBudget)],
                 counts[static_cast<int>(Outcome::Failed)], counts[static_cast<int>(Outcome::Ran)]);
  }
};

ffd::fuzz::RunSandbox& sandbox() {
  static ffd::fuzz::RunSandbox box;
  return box;
}

// Does the script loader take `text` (as the sandbox will load it)? Any other exception
// says yes, so that the input runs and the finding is saved.
bool loads(const std::string& text) {
  try {
    ffd::parse_script(text, sandbox().folder() + "/s.json");
  } catch (const ffd::InputError&) {
    return false;
  } catch (...) {
  }
  return true;
}

json parsed(const std::uint8_t* data, std::size_t size) {
  return json::parse(data, data + size, nullptr, false);
}

// Writes `doc` to `out` if it fits; its size, or 0.
std::size_t emit(const json& doc, std::uint8_t* out, std::size_t max_size) {
  const std::string text = doc.dump();
  if (text.size() > max_size) return 0;
  std::memcpy(out, text.data(), text.size());
  return text.size();
}

}  // namespace

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

// One to three structural changes to a script that parses as JSON, the first result the
// loader takes (or the last); libFuzzer's byte mutations for what does not parse.
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  const json original = parsed(data, size);
  if (original.is_discarded()) return LLVMFuzzerMutate(data, size, max_size);
  std::mt19937 rng(seed);
  const ffd::fuzz::Grammar& grammar = ffd::fuzz::script_grammar();
  json doc;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    doc = original;
    for (unsigned n = 1 + rng() % 3; n > 0; --n) ffd::fuzz::mutate_json(doc, rng, grammar);
    if (loads(doc.dump())) break;
  }
  const std::size_t written = emit(doc, data, max_size);
  return written ? written : LLVMFuzzerMutate(data, size, max_size);
}

// The first steps of one script and the last of another, the first the loader takes.
extern "C" std::size_t LLVMFuzzerCustomCrossOver(const std::uint8_t* data1, std::size_t size1,
                                                 const std::uint8_t* data2, std::size_t size2, std::uint8_t* out,
                                                 std::size_t max_out_size, unsigned int seed) {
  const json a = parsed(data1, size1), b = parsed(data2, size2);
  std::mt19937 rng(seed);
  json doc;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    doc = ffd::fuzz::cross_steps(a, b, rng);
    if (doc.is_null() || loads(doc.dump())) break;
  }
  return doc.is_null() ? 0 : emit(doc, out, max_out_size);
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Tally tally;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  ++tally.counts[static_cast<int>(sandbox().run(text))];
  return 0;
}
