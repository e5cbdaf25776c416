// Conversions between the C++ records and Python objects, for the module's bindings: vectors
// to numpy arrays (copied once), and any record the results schema describes (io/schema.hpp,
// the one owner of the names) to a dict keyed by the schema's own names.
#pragma once

#include "io/schema.hpp"
#include "io/status.hpp"
#include "kernels/model/fit.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace allanlot::python {

namespace py = pybind11;

template <class T>
py::array_t<T> to_array(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

inline py::object to_py(double v) {
  return py::float_(v);
}
inline py::object to_py(std::int64_t v) {
  return py::int_(v);
}
inline py::object to_py(int v) {
  return py::int_(v);
}
inline py::object to_py(std::uint8_t v) {
  return py::int_(v);
}
inline py::object to_py(std::int8_t v) {
  return py::int_(v);
}
inline py::object to_py(bool v) {
  return py::bool_(v);
}
inline py::object to_py(const std::string& v) {
  return py::str(v);
}
inline py::object to_py(kernels::FitStatus v) {
  return py::str(std::string(kernels::fit_status_name(v)));
}
inline py::object to_py(const io::ChannelStatus& v) {
  return py::str(io::to_string(v));
}
inline py::object to_py(const std::vector<double>& v) {
  return to_array(v);
}
inline py::object to_py(const std::vector<std::int64_t>& v) {
  return to_array(v);
}
inline py::object to_py(const std::vector<int>& v) {
  return to_array(v);
}
inline py::object to_py(const std::vector<std::uint8_t>& v) {
  return to_array(v);
}
inline py::object to_py(const std::vector<std::string>& v) {
  py::list l;
  for (const auto& s : v)
    l.append(py::str(s));
  return l;
}

/// The fields of record `r` that the schema writes for it, by the schema's names.
template <class Rec>
py::dict fields_dict(const Rec& r, std::span<const io::schema::Field<Rec>> fields) {
  py::dict d;
  for (const auto& f : fields) {
    if (f.written && !f.written(r)) continue;
    std::visit([&](auto member) { d[f.name] = to_py(r.*member); }, f.member);
  }
  return d;
}

/// A table of rows as one column per schema column: numbers as numpy arrays, strings as lists.
template <class Row>
py::dict columns_dict(const std::vector<Row>& rows,
                      std::span<const io::schema::Column<Row>> columns) {
  py::dict d;
  for (const auto& c : columns)
    std::visit(
        [&](auto member) {
          using T = std::decay_t<decltype(std::declval<Row>().*member)>;
          std::vector<T> v;
          for (const Row& row : rows)
            v.push_back(row.*member);
          if constexpr (std::is_same_v<T, bool>) {
            std::vector<std::uint8_t> b(v.begin(), v.end());
            d[c.name] = to_array(b).attr("astype")("bool");
          } else {
            d[c.name] = to_py(v);
          }
        },
        c.member);
  return d;
}

/// The fit/ (or psd_fit/) record as a dict: its fields, "terms" (one column per term field),
/// "readouts" and "effects" (a poor fit's model, fit/effects/; likewise).
py::dict fit_dict(const io::FitRecord& f);

}  // namespace allanlot::python
