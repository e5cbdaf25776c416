// Walks the tables of io/schema.hpp over HDF5 groups: the only code that turns a schema field
// into a dataset or an attribute and back. Private to io/ (includes hdf5.h).
#pragma once

#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/schema.hpp"

#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace allanlot::io::schema {

/// Which reader walks a table: the full one reads every field, the summary one only those
/// marked `summary`.
enum class Depth { Full, Summary };

namespace detail {

template <class T>
inline constexpr bool kIsVector = false;
template <class T>
inline constexpr bool kIsVector<std::vector<T>> = true;

[[noreturn]] inline void bad_field(const char* name) {
  throw std::logic_error(std::string("schema: no HDF5 form for field '") + name + "'");
}

template <class V>
void write_value(hid_t g, const char* name, Kind kind, const V& v, const std::string& file,
                 const std::string& object) {
  if constexpr (kIsVector<V>) {
    if (kind == Kind::Dataset)
      h5::write_dataset(g, name, v, file, object);
    else if constexpr (std::is_same_v<V, std::vector<double>>)
      h5::write_attribute(g, name, v, file, object);
    else
      bad_field(name);
  } else if (kind == Kind::Dataset) {
    bad_field(name);
  } else if constexpr (std::is_same_v<V, int>) {
    h5::write_attribute(g, name, static_cast<std::int64_t>(v), file, object);
  } else if constexpr (std::is_same_v<V, kernels::FitStatus> || std::is_same_v<V, ChannelStatus>) {
    h5::write_attribute(g, name, to_string(v), file, object);
  } else {
    h5::write_attribute(g, name, v, file, object);
  }
}

template <class V>
void read_dataset(hid_t g, const char* name, V& v, const std::string& file,
                  const std::string& object) {
  if constexpr (std::is_same_v<V, std::vector<double>>) {
    v = h5::read_doubles(g, name, file, object);
  } else if constexpr (std::is_same_v<V, std::vector<std::string>>) {
    v = h5::read_strings(g, name, file, object);
  } else if constexpr (kIsVector<V>) {
    const auto w = h5::read_int64s(g, name, file, object);
    v.assign(w.begin(), w.end());
  } else {
    bad_field(name);
  }
}

template <class V>
void read_attribute(hid_t g, const char* name, V& v, const std::string& file,
                    const std::string& object) {
  if constexpr (std::is_same_v<V, int>) {
    std::int64_t x = v;
    if (h5::read_attribute(g, name, x, file, object)) v = static_cast<int>(x);
  } else if constexpr (std::is_same_v<V, kernels::FitStatus> || std::is_same_v<V, ChannelStatus>) {
    std::string text;
    if (!h5::read_attribute(g, name, text, file, object)) return;
    const std::string where = object + "@" + name;
    if constexpr (std::is_same_v<V, ChannelStatus>)
      v = parse_channel_status(text, file, where);
    else
      v = parse_fit_status(text, file, where);
  } else if constexpr (kIsVector<V> && !std::is_same_v<V, std::vector<double>>) {
    bad_field(name);
  } else {
    h5::read_attribute(g, name, v, file, object);
  }
}

inline bool exists(hid_t g, const char* name, Kind kind) {
  return kind == Kind::Dataset ? H5Lexists(g, name, H5P_DEFAULT) > 0 : H5Aexists(g, name) > 0;
}

}  // namespace detail

/// Writes the fields of `r` to group `g` (`object` its path), in table order.
template <class Rec>
void write_fields(hid_t g, const Rec& r, std::span<const Field<Rec>> fields,
                  const std::string& file, const std::string& object) {
  for (const Field<Rec>& f : fields) {
    if (f.written && !f.written(r)) continue;
    std::visit([&](auto m) { detail::write_value(g, f.name, f.kind, r.*m, file, object); },
               f.member);
  }
}

/// Reads the fields of group `g` into `r`: required datasets must be there (io::Error naming
/// the dataset otherwise), the others are read when present.
template <class Rec>
void read_fields(hid_t g, Rec& r, std::span<const Field<Rec>> fields, Depth depth,
                 const std::string& file, const std::string& object) {
  for (const Field<Rec>& f : fields) {
    if (depth == Depth::Summary && !f.summary) continue;
    if (!f.required() && !detail::exists(g, f.name, f.kind)) continue;
    std::visit(
        [&](auto m) {
          if (f.kind == Kind::Dataset)
            detail::read_dataset(g, f.name, r.*m, file, object);
          else
            detail::read_attribute(g, f.name, r.*m, file, object);
        },
        f.member);
  }
}

/// Writes `rows` to `g` as one 1-D dataset per column (bool as u8).
template <class Row>
void write_columns(hid_t g, const std::vector<Row>& rows, std::span<const Column<Row>> columns,
                   const std::string& file, const std::string& object) {
  for (const Column<Row>& c : columns)
    std::visit(
        [&](auto m) {
          using V = std::remove_cvref_t<decltype(rows[0].*m)>;
          using Stored = std::conditional_t<std::is_same_v<V, bool>, std::uint8_t, V>;
          std::vector<Stored> v;
          v.reserve(rows.size());
          for (const Row& r : rows)
            v.push_back(static_cast<Stored>(r.*m));
          h5::write_dataset(g, c.name, v, file, object);
        },
        c.member);
}

/// Reads the column datasets of `g` back into rows; the first column gives the row count and
/// every other column present must have as many values.
template <class Row>
std::vector<Row> read_columns(hid_t g, std::span<const Column<Row>> columns, Depth depth,
                              const std::string& file, const std::string& object) {
  std::vector<Row> rows;
  bool sized = false;
  for (const Column<Row>& c : columns) {
    if (depth == Depth::Summary && !c.summary) continue;
    if (c.need == Need::IfPresent && H5Lexists(g, c.name, H5P_DEFAULT) <= 0) {
      // Absent (a file from before the column): numbers have no value, not a zero.
      std::visit(
          [&](auto m) {
            if constexpr (std::is_same_v<std::remove_cvref_t<decltype(rows[0].*m)>, double>)
              for (Row& r : rows)
                r.*m = std::numeric_limits<double>::quiet_NaN();
          },
          c.member);
      continue;
    }
    std::visit(
        [&](auto m) {
          using V = std::remove_cvref_t<decltype(std::declval<Row&>().*m)>;
          using Read =
              std::conditional_t<std::is_same_v<V, std::string>, std::vector<std::string>,
                                 std::conditional_t<std::is_same_v<V, double>, std::vector<double>,
                                                    std::vector<std::int64_t>>>;
          Read v;
          detail::read_dataset(g, c.name, v, file, object);
          if (!sized) rows.resize(v.size());
          sized = true;
          if (v.size() != rows.size())
            throw Error(file, object + "/" + c.name,
                        "has " + std::to_string(v.size()) + " values for " +
                            std::to_string(rows.size()) + " rows");
          for (std::size_t i = 0; i < v.size(); ++i)
            rows[i].*m = static_cast<V>(std::move(v[i]));  // bool: non-zero
        },
        c.member);
  }
  return rows;
}

/// Creates group `name` under `parent` (object time tracking off: same inputs, same bytes).
h5::Handle create_group(hid_t parent, const char* name, const std::string& file,
                        const std::string& object);
/// Opens group `name` under `parent`.
h5::Handle open_group(hid_t parent, const char* name, const std::string& file,
                      const std::string& object);
/// Whether `parent` has a link `name`.
bool has_link(hid_t parent, const char* name);

/// Writes schema_version at the root of `f`; reads it (1 when absent) and refuses a newer one
/// with io::Error naming the file.
void write_version(hid_t root, const std::string& file);
void check_version(hid_t root, const std::string& file);

/// The diagnosis/ group of a channel group (io/diagnosis.cpp): the table's datasets and the free
/// number and string attributes.
void write_diagnosis_group(hid_t channel_group, const DiagnosisRecord& r, const std::string& file);
DiagnosisRecord read_diagnosis_group(hid_t g, const std::string& channel, const std::string& file);

/// The drift/, edits/ and dynamic/ groups of a channel group (io/schema_editing.cpp), each
/// written when the channel has it and read at the full depth only.
void write_editing_groups(hid_t channel_group, const ChannelResult& ch, const std::string& file);
void read_editing_groups(hid_t channel_group, ChannelResult& ch, Depth depth,
                         const std::string& file);

}  // namespace allanlot::io::schema
