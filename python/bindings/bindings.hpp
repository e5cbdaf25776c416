// The parts of the extension module allanlot._allanlot, one registration function per file.
#pragma once

#include "kernels/common/thread_cap.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <span>
#include <stdexcept>
#include <string>

namespace allanlot::python {

namespace py = pybind11;

/// Samples as the kernels take them: 1-D float64, C-contiguous. pybind11 converts any other
/// array-like (lists, other dtypes, strided views) into one such array, once.
using Samples = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// The samples as the kernels read them; std::invalid_argument (ValueError) unless 1-D.
inline std::span<const double> samples_of(const Samples& data) {
  if (data.ndim() != 1)
    throw std::invalid_argument("data must be one-dimensional, got " + std::to_string(data.ndim()) +
                                " dimensions");
  return {data.data(), static_cast<std::size_t>(data.size())};
}

/// The thread count the kernels get for the module's `threads` (0: OMP_NUM_THREADS or every
/// core): std::invalid_argument (ValueError) outside 0 .. kMaxThreads, and at most thread_cap()
/// either way, as on the command line (kernels/common/thread_cap.hpp).
inline int kernel_threads(int threads) {
  if (threads < 0 || threads > kernels::kMaxThreads)
    throw std::invalid_argument("threads must be from 1 to " +
                                std::to_string(kernels::kMaxThreads) + " (None: every core), got " +
                                std::to_string(threads));
  return kernels::capped_threads(threads);
}

void bind_deviation(py::module_& m);    // deviation, gcodev, stats, max_m
void bind_records(py::module_& m);      // fit, read_results, read_lot_summary, read_lot_statistics
void bind_tools(py::module_& m);        // psd, simulate, diagnose
void bind_uncertainty(py::module_& m);  // edf_greenhall, chi2_quantile
void bind_plan(py::module_& m);         // plan, watch, look_quantile
void bind_recording(py::module_& m);    // read_recording

}  // namespace allanlot::python
