// The shape of every fuzz target: one input of bytes read by a reader, which must either
// succeed or throw InputError. Anything else (a crash, a sanitizer report, another
// exception) is a finding; libFuzzer stops and saves the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/errors.h"

namespace ffd::fuzz {

/// Runs `read` on the bytes; InputError is the expected way to refuse them.
template <class Read>
int one_input(const std::uint8_t* data, std::size_t size, Read read) {
  try {
    read(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace ffd::fuzz
