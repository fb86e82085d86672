// libFuzzer target for the script loader and validator: JSON syntax, the schema, the
// typed steps and the checks between them.
#include <string>

#include "fuzz_target.h"
#include "script/script.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view text) { ffd::parse_script(std::string(text), "fuzz.json"); });
}
