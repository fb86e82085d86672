// Typed errors shared by the library and the CLI.
// InputError: the user's input is wrong (file, script, arguments); the CLI exits 2.
// RunError: a step failed while running on valid input; the CLI exits 3.
// Messages are one line and name the file and the place in it ("bunny.obj:12: ...",
// "script.json: /steps/2/cells: ...").
#pragma once

#include <stdexcept>
#include <string>

namespace ffd {

/// Bad input: usage, file, mesh or script. Maps to exit code 2.
class InputError : public std::runtime_error {
public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// Failure while running a valid script (solver breakdown, I/O failure on write).
/// Maps to exit code 3.
class RunError : public std::runtime_error {
public:
  explicit RunError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace ffd
