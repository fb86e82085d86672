// Typed errors shared by the library and the CLI (pmp-library's shape).
//
// - InputError: the user's data is invalid (a file, a script, a value); exit code 2.
// - TopologyError: the mesh is not what an op needs (an oriented 2-manifold); exit 2.
// - SolverError: a numerical solver failed on valid input; exit 3.
// - IoError: reading or writing failed at the system's level (disk full); exit 3.
//
// Each error's message speaks about the data ("the handles cover the whole support").
// Code below lib/script knows nothing of scripts: it says which of its own arguments the
// error concerns (its Subject: "support", or element 2 of "handles"). The script layer,
// whose op tables know which key feeds which argument, then sets the place
// ("bcm.json: /steps/3/handles/2/select"), and what() reads "place: message".
// An error that already names its place (a reader's "bunny.obj:12") is thrown placed.
#pragma once

#include <cstddef>
#include <exception>
#include <string>
#include <utility>

namespace ffd {

/// What an error concerns, in the words of the function that threw it: one of its
/// arguments, and for a list argument the element at fault.
struct Subject {
  static constexpr std::size_t kWhole = static_cast<std::size_t>(-1);
  std::string argument;          // empty: nothing in particular
  std::size_t element = kWhole;  // kWhole: the argument as a whole
};

/// Where an error happened, for the constructors that know it: `IoError(At{path}, "...")`.
struct At {
  std::string place;
};

/// The base of ffdtool's errors: a message about the data, what it concerns, and where
/// it happened once someone knows (file, line, JSON pointer).
class Error : public std::exception {
public:
  explicit Error(std::string message, Subject subject = {});
  /// An error whose place is known where it is thrown ("bunny.obj:12", a file's path).
  Error(At at, std::string message) : Error(std::move(message)) { set_place(std::move(at.place)); }
  /// "place: message", or the message alone while no place is set.
  const char* what() const noexcept override { return text_.c_str(); }
  const std::string& message() const { return message_; }
  const Subject& subject() const { return subject_; }
  const std::string& place() const { return place_; }
  bool placed() const { return !place_.empty(); }
  /// Sets where the error happened; catch by reference, set, then `throw;` keeps the type.
  void set_place(std::string place);
  /// Says what the error concerns, for a caller that knows better than the thrower.
  void set_subject(Subject subject) { subject_ = std::move(subject); }

private:
  std::string message_;
  Subject subject_;
  std::string place_;
  std::string text_;
};

/// Bad input: usage, file, mesh or script value. Exit code 2.
class InputError : public Error {
public:
  using Error::Error;
};

/// The mesh is not the oriented 2-manifold an op needs (non-manifold edge, flipped face,
/// degenerate face). Exit code 2: the input must change.
class TopologyError : public InputError {
public:
  using InputError::InputError;
};

/// A numerical solver failed on input that passed every check (a breakdown, no memory
/// for a factor). Exit code 3. Where a failure is really the user's data (a singular
/// system because part of a region touches no constraint), throw InputError instead.
class SolverError : public Error {
public:
  using Error::Error;
};

/// Reading or writing failed at the system's level (cannot create, disk full). Exit 3.
class IoError : public Error {
public:
  using Error::Error;
};

}  // namespace ffd
