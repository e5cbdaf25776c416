// The parts of the extension module allanlot._allanlot, one registration function per file.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace allanlot::python {

namespace py = pybind11;

/// Samples as the kernels take them: 1-D float64, C-contiguous. pybind11 converts any other
/// array-like (lists, other dtypes, strided views) into one such array, once.
using Samples = py::array_t<double, py::array::c_style | py::array::forcecast>;

void bind_deviation(py::module_& m);  // deviation, gcodev, stats, max_m
void bind_records(py::module_& m);    // fit, read_results, read_lot_summary, read_lot_statistics
void bind_tools(py::module_& m);      // psd, simulate, diagnose

}  // namespace allanlot::python
