// ffdtool's typed errors (common/errors.h) as Python exceptions carrying the CLI's one
// line: ffdtool.Error and its subclasses InputError (also a ValueError), TopologyError,
// SolverError and IoError (also an OSError), each with .message and .place.
#include <omp.h>

#include "common/errors.h"
#include "py_module.h"

namespace ffd::py {
namespace {

struct ErrorTypes {
  pb::object base, input, topology, solver, io;
};

// Made once and kept for the process's life: the translator runs until exit.
ErrorTypes& error_types() {
  static auto* types = new ErrorTypes();
  return *types;
}

pb::object new_type(pb::module_& m, const char* name, pb::tuple bases, const char* doc) {
  pb::dict attrs;
  attrs["__doc__"] = doc;
  attrs["__module__"] = "ffdtool";
  pb::object type = pb::reinterpret_borrow<pb::object>(reinterpret_cast<PyObject*>(&PyType_Type))(name, bases, attrs);
  m.attr(name) = type;
  return type;
}

// Raises `type` with the error's line as its text, and its message and place as attributes.
void raise(const pb::object& type, const Error& e) {
  pb::object error = type(e.what());
  error.attr("message") = e.message();
  error.attr("place") = e.place();
  PyErr_SetObject(type.ptr(), error.ptr());
}

}  // namespace

ThreadScope::ThreadScope(int threads) : old_(threads > 0 ? omp_get_max_threads() : 0) {
  if (threads > 0) omp_set_num_threads(threads);
}

ThreadScope::~ThreadScope() {
  if (old_ > 0) omp_set_num_threads(old_);
}

void bind_errors(pb::module_& m) {
  ErrorTypes& t = error_types();
  const pb::object exception = pb::reinterpret_borrow<pb::object>(PyExc_Exception);
  t.base = new_type(m, "Error", pb::make_tuple(exception),
                    "An ffdtool error: str() is the CLI's one line, 'place: message'; .message is what went wrong "
                    "and .place where (a file and line, or a script's JSON pointer), '' when nowhere in particular.");
  t.input = new_type(m, "InputError", pb::make_tuple(t.base, pb::reinterpret_borrow<pb::object>(PyExc_ValueError)),
                     "Bad input: a file, a script, a value (the CLI's exit code 2).");
  t.topology = new_type(m, "TopologyError", pb::make_tuple(t.input),
                        "The mesh is not the oriented 2-manifold an op needs (exit code 2).");
  t.solver = new_type(m, "SolverError", pb::make_tuple(t.base),
                      "A numerical solver failed on valid input (exit code 3).");
  t.io = new_type(m, "IoError", pb::make_tuple(t.base, pb::reinterpret_borrow<pb::object>(PyExc_OSError)),
                  "Reading or writing failed at the system's level (exit code 3).");
  pb::register_exception_translator([](std::exception_ptr p) {
    const ErrorTypes& types = error_types();
    try {
      if (p) std::rethrow_exception(p);
    } catch (const TopologyError& e) {
      raise(types.topology, e);
    } catch (const InputError& e) {
      raise(types.input, e);
    } catch (const SolverError& e) {
      raise(types.solver, e);
    } catch (const IoError& e) {
      raise(types.io, e);
    } catch (const Error& e) {
      raise(types.base, e);
    }
  });
}

}  // namespace ffd::py
