// rove's exceptions as Python exceptions. Every one derives from rove.Error
// and from the built-in exception a Python user expects:
//   InvalidArgument -> rove.InvalidArgument (ValueError)
//   ParseError      -> rove.ParseError (ValueError), with source, line,
//                      offset and field attributes
//   ConfigError     -> rove.ConfigError (ValueError), with file, section, key
//   SelectionError  -> rove.SelectionError (ValueError)
//   IoError         -> rove.IoError (OSError), with path
//   ResourceError   -> rove.ResourceError (OSError)
//   NumericError    -> rove.NumericError (ArithmeticError)
//   Interrupted     -> KeyboardInterrupt
//   any other       -> rove.Error (RuntimeError)
// The exception's text is rove's message; its `trace` attribute lists the
// C++ frames it passed through ("function (file:line)").

#include <Python.h>

#include <string>

#include "bindings.h"
#include "rove/core/interrupt.h"
#include "rove/obs/selection_error.h"

namespace rove::python {

namespace {

struct ErrorTypes {
  py::object base, invalid_argument, parse, config, selection, io, resource, numeric;
};

ErrorTypes& types() {
  static ErrorTypes* t = new ErrorTypes();  // lives as long as the interpreter
  return *t;
}

py::object make_type(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("rove.") + name;
  PyObject* t = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (t == nullptr) throw py::error_already_set();
  py::object type = py::reinterpret_steal<py::object>(t);
  m.attr(name) = type;
  return type;
}

py::list trace_of(const Error& e) {
  py::list frames;
  for (const SourceFrame& f : e.trace())
    frames.append(f.function + " (" + f.file + ":" + std::to_string(f.line) + ")");
  return frames;
}

// Sets the Python error: an instance of `type` built from rove's message,
// with `trace` and the given extra attributes.
void raise(const py::object& type, const Error& e, const py::dict& attributes = py::dict()) {
  py::object instance = type(e.message());
  instance.attr("trace") = trace_of(e);
  for (const auto& [key, value] : attributes) instance.attr(key) = value;
  PyErr_SetObject(type.ptr(), instance.ptr());
}

py::object optional_int(const auto& v) {
  return v ? py::object(py::int_(*v)) : py::object(py::none());
}

void translate(std::exception_ptr p) {
  ErrorTypes& t = types();
  try {
    std::rethrow_exception(p);
  } catch (const Interrupted& e) {
    PyErr_SetString(PyExc_KeyboardInterrupt, e.message().c_str());
  } catch (const InvalidArgument& e) {
    raise(t.invalid_argument, e);
  } catch (const ParseError& e) {
    py::dict a;
    a["source"] = e.location().source;
    a["line"] = optional_int(e.location().line);
    a["offset"] = optional_int(e.location().offset);
    a["field"] = e.location().field;
    raise(t.parse, e, a);
  } catch (const ConfigError& e) {
    py::dict a;
    a["file"] = e.file();
    a["section"] = e.section();
    a["key"] = e.key();
    raise(t.config, e, a);
  } catch (const SelectionError& e) {
    raise(t.selection, e);
  } catch (const IoError& e) {
    py::dict a;
    a["path"] = e.path();
    raise(t.io, e, a);
  } catch (const ResourceError& e) {
    raise(t.resource, e);
  } catch (const NumericError& e) {
    raise(t.numeric, e);
  } catch (const Error& e) {
    raise(t.base, e);
  }
}

}  // namespace

void type_error(const std::string& message) { throw py::type_error(message); }
void value_error(const std::string& message) { throw py::value_error(message); }

void bind_errors(py::module_& m) {
  ErrorTypes& t = types();
  const auto builtin = [](PyObject* e) { return py::reinterpret_borrow<py::object>(e); };
  t.base = make_type(m, "Error", py::make_tuple(builtin(PyExc_RuntimeError)),
                     "Base of every error rove raises (its `trace` lists the C++ frames).");
  t.invalid_argument =
      make_type(m, "InvalidArgument", py::make_tuple(t.base, builtin(PyExc_ValueError)),
                "A precondition was violated: an argument outside the function's contract.");
  t.parse = make_type(m, "ParseError", py::make_tuple(t.base, builtin(PyExc_ValueError)),
                      "Malformed input; `source`, `line`, `offset` and `field` say where.");
  t.config = make_type(m, "ConfigError", py::make_tuple(t.base, builtin(PyExc_ValueError)),
                       "A configuration value is missing, malformed or unknown (`file`, "
                       "`section`, `key`).");
  t.selection = make_type(m, "SelectionError", py::make_tuple(t.base, builtin(PyExc_ValueError)),
                          "The input holds nothing the job can use (e.g. a log without scans).");
  t.io = make_type(m, "IoError", py::make_tuple(t.base, builtin(PyExc_OSError)),
                   "Reading or writing a file failed (`path` names it).");
  t.resource = make_type(m, "ResourceError", py::make_tuple(t.base, builtin(PyExc_OSError)),
                         "A request would exceed a stated limit (memory budget, file size).");
  t.numeric = make_type(m, "NumericError", py::make_tuple(t.base, builtin(PyExc_ArithmeticError)),
                        "A numerical failure the input could not have excluded beforehand.");
  py::register_exception_translator(&translate);
}

}  // namespace rove::python
