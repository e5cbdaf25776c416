// allanlot._allanlot: the equivalent degrees of freedom and chi-square quantiles behind the
// confidence intervals, for AllanTools' edf_greenhall and confidence_interval
// (python/allanlot/ci.py).
#include "python/bindings/bindings.hpp"

#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/edf.hpp"

#include <cstdint>

namespace allanlot::python {
namespace {

double edf_greenhall(int alpha, int d, std::int64_t m, std::int64_t n_phase, bool overlapping,
                     bool modified) {
  const kernels::FiniteDifferenceKind kind{d, overlapping, modified};
  return kernels::edf_greenhall(alpha, kind, m, n_phase);
}

}  // namespace

void bind_uncertainty(py::module_& m) {
  m.def("edf_greenhall", &edf_greenhall, py::arg("alpha"), py::arg("d"), py::arg("m"),
        py::arg("n_phase"), py::arg("overlapping"), py::arg("modified"));
  m.def("chi2_quantile", &kernels::chi2_quantile, py::arg("p"), py::arg("dof"));
}

}  // namespace allanlot::python
