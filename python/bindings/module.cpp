// The extension module allanlot._allanlot (docs/python.md): the command line's kernels and
// readers for Python. The public API, its argument conventions and docstrings are in
// python/allanlot/*.py; this module only converts and releases the GIL around the kernels.
#include "python/bindings/bindings.hpp"

#include "io/error.hpp"
#include "io/usage_error.hpp"
#include "src/lot/model.hpp"

#include <allanlot/version.hpp>
#include <pybind11/pybind11.h>

#include <exception>

namespace py = pybind11;

PYBIND11_MODULE(_allanlot, m) {
  m.doc() = "allanlot's kernels (use the package allanlot, not this module directly)";
  m.attr("version") = allanlot::kVersion;
  // The command line's errors keep their messages: a file that cannot be read or is damaged is
  // an OSError (exit status 1 on the command line), a bad model or argument a ValueError (2).
  // std::invalid_argument is pybind11's ValueError already.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const allanlot::io::UsageError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const allanlot::io::Error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const allanlot::model::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  allanlot::python::bind_deviation(m);
  allanlot::python::bind_records(m);
  allanlot::python::bind_tools(m);
  allanlot::python::bind_plan(m);
  allanlot::python::bind_uncertainty(m);
  allanlot::python::bind_recording(m);
}
