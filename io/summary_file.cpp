// The lot summary files (docs/formats.md "Lot summary"): lot_summary.csv, lot_statistics.csv
// and the compound datasets /summary and /statistics of lot_summary.h5, all from the column
// tables of io/schema.hpp.
#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/isolation.hpp"
#include "io/results.hpp"
#include "io/schema_h5.hpp"
#include "io/seal.hpp"
#include "io/utf8.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <sstream>
#include <string_view>
#include <type_traits>

namespace allanlot::io {

using h5::check;
using h5::Handle;

namespace {

template <class T>
inline constexpr bool kIsArray = false;
template <class T, std::size_t N>
inline constexpr bool kIsArray<std::array<T, N>> = true;

template <class V>
using Element = std::remove_cvref_t<decltype(std::declval<V&>()[0])>;

// One column of the flattened table: a scalar member, or one term of a per-term array, at
// `offset` in the packed in-memory record (C layout, table order).
template <class Row>
struct FlatColumn {
  std::string name;
  const schema::RowColumn<Row>* column;
  std::size_t term;
  std::size_t offset;
};

template <class Row>
struct Layout {
  std::vector<FlatColumn<Row>> columns;  // in column order (the CSV's and the compound's)
  std::size_t record_size = 0;
};

// Size of one element of a member in the packed record (strings as char pointers).
template <class Row>
std::size_t element_size(const schema::RowColumn<Row>& c) {
  return std::visit(
      [](auto m) {
        using V = std::remove_cvref_t<decltype(std::declval<Row&>().*m)>;
        if constexpr (kIsArray<V>)
          return std::is_same_v<Element<V>, std::string> ? sizeof(const char*) : sizeof(Element<V>);
        else if constexpr (std::is_same_v<V, std::string> || std::is_same_v<V, ChannelStatus>)
          return sizeof(const char*);
        else
          return sizeof(V);
      },
      c.member);
}

template <class Row>
std::size_t element_count(const schema::RowColumn<Row>& c) {
  return std::visit(
      [](auto m) {
        using V = std::remove_cvref_t<decltype(std::declval<Row&>().*m)>;
        if constexpr (kIsArray<V>)
          return std::tuple_size_v<V>;
        else
          return std::size_t{1};
      },
      c.member);
}

// The same layout as a C struct of the table's members in table order: each member at the next
// multiple of its element size (every element here is 1 or 8 bytes), the whole rounded up to 8.
template <class Row>
Layout<Row> layout(std::span<const schema::RowColumn<Row>> table) {
  Layout<Row> l;
  std::vector<std::size_t> offset(table.size());
  std::size_t at = 0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const std::size_t size = element_size(table[i]);
    at = (at + size - 1) / size * size;
    offset[i] = at;
    at += size * element_count(table[i]);
  }
  l.record_size = (at + 7) / 8 * 8;
  for (std::size_t i = 0; i < table.size();) {
    if (table[i].block == 0) {
      l.columns.push_back({table[i].name, &table[i], 0, offset[i]});
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < table.size() && table[end].block == table[i].block)
      ++end;
    const auto& names = table[i].names ? *table[i].names : schema::kTermNames;
    for (std::size_t t = 0; t < names.size(); ++t)
      for (std::size_t k = i; k < end; ++k)
        l.columns.push_back({std::string(names[t]) + table[k].name, &table[k], t,
                             offset[k] + t * element_size(table[k])});
    i = end;
  }
  return l;
}

// Calls f with the element of `row` that column `c` stores.
template <class Row, class F>
void with_element(Row& row, const FlatColumn<std::remove_const_t<Row>>& c, F&& f) {
  std::visit(
      [&](auto m) {
        auto& v = row.*m;
        if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>)
          f(v[c.term]);
        else
          f(v);
      },
      c.column->member);
}

// The memory type of an element: `str` for strings and statuses.
template <class V>
hid_t memory_type(hid_t str) {
  if constexpr (std::is_same_v<V, double>)
    return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<V, std::int64_t>)
    return H5T_NATIVE_INT64;
  else if constexpr (std::is_same_v<V, std::uint8_t>)
    return H5T_NATIVE_UINT8;
  else if constexpr (std::is_same_v<V, std::int8_t>)
    return H5T_NATIVE_INT8;
  else
    return str;
}

template <class Row>
Handle compound_type(const Layout<Row>& l, const std::string& file, const std::string& object) {
  Handle str = h5::utf8_string_type(file, object);
  Handle t = check(H5Tcreate(H5T_COMPOUND, l.record_size), H5Tclose, file, object, "H5Tcreate");
  const Row probe{};
  for (const FlatColumn<Row>& c : l.columns)
    with_element(probe, c, [&](const auto& v) {
      using V = std::remove_cvref_t<decltype(v)>;
      check(H5Tinsert(t.get(), c.name.c_str(), c.offset, memory_type<V>(str.get())), file, object,
            "H5Tinsert(" + c.name + ")");
    });
  return t;
}

// Numbers in the lot summary with 7 significant digits (a datasheet needs 2 or 3, the
// uncertainty another).
constexpr int kSummaryDigits = 7;

template <class Row>
std::string csv_text(const std::vector<Row>& rows, std::span<const schema::RowColumn<Row>> table) {
  const Layout<Row> l = layout(table);
  std::ostringstream csv;
  for (std::size_t i = 0; i < l.columns.size(); ++i)
    csv << (i ? "," : "") << l.columns[i].name;
  csv << '\n';
  for (const Row& r : rows) {
    for (std::size_t i = 0; i < l.columns.size(); ++i) {
      const FlatColumn<Row>& c = l.columns[i];
      if (i) csv << ',';
      if (c.column->csv) {
        csv << c.column->csv(r, c.term);
        continue;
      }
      with_element(r, c, [&](const auto& v) {
        using V = std::remove_cvref_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::string>)
          csv << csv_field(v);
        else if constexpr (std::is_same_v<V, ChannelStatus>)
          csv << csv_field(to_string(v));
        else if constexpr (std::is_same_v<V, double>)
          csv << csv_number(v, kSummaryDigits);
        else
          csv << std::to_string(v);
      });
    }
    csv << '\n';
  }
  return csv.str();
}

// Writes `rows` as the 1-D compound dataset `name` of file `f`.
template <class Row>
void write_compound(hid_t f, const char* name, const std::vector<Row>& rows,
                    std::span<const schema::RowColumn<Row>> table, const std::string& file) {
  const std::string object = std::string("/") + name;
  const Layout<Row> l = layout(table);
  Handle type = compound_type(l, file, object);
  std::vector<unsigned char> buf(rows.size() * l.record_size, 0);
  std::deque<std::string> texts;  // strings as written (valid UTF-8), alive until H5Dwrite
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (const FlatColumn<Row>& c : l.columns)
      with_element(rows[r], c, [&](const auto& v) {
        using V = std::remove_cvref_t<decltype(v)>;
        unsigned char* at = buf.data() + r * l.record_size + c.offset;
        const char* p = nullptr;
        if constexpr (std::is_same_v<V, std::string>) {
          p = texts.emplace_back(valid_utf8(v)).c_str();
        } else if constexpr (std::is_same_v<V, ChannelStatus>) {
          p = texts.emplace_back(to_string(v)).c_str();
        } else {
          std::memcpy(at, &v, sizeof v);
          return;
        }
        std::memcpy(at, &p, sizeof p);
      });
  const hsize_t n = rows.size();
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, object, "H5Screate_simple");
  Handle dcpl = h5::dataset_create_plist(file, object);
  Handle ds =
      check(H5Dcreate2(f, name, type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
            H5Dclose, file, object, "H5Dcreate2");
  if (n > 0)
    check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), file, object,
          "H5Dwrite");
  if (ds.close() < 0) throw Error(file, object, "H5Dclose failed");
}

// The reading type of a file's compound: the table's columns the file has, at the table's
// offsets. A memory type with members the file lacks makes H5Dread fail, and HDF5 converts
// compounds by member name, so columns missing from older files keep their defaults.
template <class Row>
Handle reading_type(hid_t ds, const Layout<Row>& l, std::vector<bool>& present,
                    const std::string& file, const std::string& object) {
  Handle ftype = check(H5Dget_type(ds), H5Tclose, file, object, "H5Dget_type");
  if (H5Tget_class(ftype.get()) != H5T_COMPOUND) throw Error(file, object, "not a compound");
  Handle full = compound_type(l, file, object);
  Handle rtype = check(H5Tcreate(H5T_COMPOUND, l.record_size), H5Tclose, file, object, "H5Tcreate");
  present.assign(l.columns.size(), false);
  for (std::size_t i = 0; i < l.columns.size(); ++i) {
    const FlatColumn<Row>& c = l.columns[i];
    const int fi = H5Tget_member_index(ftype.get(), c.name.c_str());
    if (fi < 0) continue;
    present[i] = true;
    const unsigned mi = static_cast<unsigned>(H5Tget_member_index(full.get(), c.name.c_str()));
    Handle mt =
        check(H5Tget_member_type(full.get(), mi), H5Tclose, file, object, "H5Tget_member_type");
    // HDF5 does not convert between character sets: read a string in the file's own (an
    // older writer may have used ASCII); the bytes are the same for ASCII text.
    if (H5Tget_class(mt.get()) == H5T_STRING) {
      Handle fm = check(H5Tget_member_type(ftype.get(), static_cast<unsigned>(fi)), H5Tclose, file,
                        object, "H5Tget_member_type");
      if (H5Tget_class(fm.get()) == H5T_STRING) H5Tset_cset(mt.get(), H5Tget_cset(fm.get()));
    }
    check(H5Tinsert(rtype.get(), c.name.c_str(), c.offset, mt.get()), file, object,
          "H5Tinsert(" + c.name + ")");
  }
  return rtype;
}

template <class Row>
std::vector<Row> read_compound(hid_t f, const char* name,
                               std::span<const schema::RowColumn<Row>> table,
                               const std::string& file) {
  const std::string object = std::string("/") + name;
  Handle ds = check(H5Dopen2(f, name, H5P_DEFAULT), H5Dclose, file, object, "H5Dopen2");
  Handle space = check(H5Dget_space(ds.get()), H5Sclose, file, object, "H5Dget_space");
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(space.get()) != 1) throw Error(file, object, "not a 1-D dataset");
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  const Layout<Row> l = layout(table);
  std::vector<bool> present;
  Handle rtype = reading_type(ds.get(), l, present, file, object);
  std::vector<unsigned char> buf(static_cast<std::size_t>(n) * l.record_size, 0);
  const bool read = n > 0 && H5Tget_nmembers(rtype.get()) > 0;
  if (read)
    check(H5Dread(ds.get(), rtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), file, object,
          "H5Dread");
  std::vector<Row> rows(static_cast<std::size_t>(n));
  try {
    for (std::size_t r = 0; r < rows.size(); ++r)
      for (std::size_t i = 0; i < l.columns.size(); ++i) {
        if (!present[i]) continue;
        const FlatColumn<Row>& c = l.columns[i];
        const unsigned char* at = buf.data() + r * l.record_size + c.offset;
        with_element(rows[r], c, [&](auto& v) {
          using V = std::remove_cvref_t<decltype(v)>;
          if constexpr (std::is_same_v<V, std::string> || std::is_same_v<V, ChannelStatus>) {
            const char* p = nullptr;
            std::memcpy(&p, at, sizeof p);
            if constexpr (std::is_same_v<V, std::string>)
              v = p ? p : "";
            else
              v = parse_channel_status(p ? p : "", file, object + "/" + c.name);
          } else {
            std::memcpy(&v, at, sizeof v);
          }
        });
      }
  } catch (...) {
    if (read) H5Dvlen_reclaim(rtype.get(), space.get(), H5P_DEFAULT, buf.data());
    throw;
  }
  if (read) H5Dvlen_reclaim(rtype.get(), space.get(), H5P_DEFAULT, buf.data());
  return rows;
}

Handle open_summary_file(const std::string& file) {
  Handle f = h5::open_sealed(file, "lot summary");
  Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
  schema::check_version(root.get(), file);
  return f;
}

}  // namespace

std::vector<std::pair<std::string, std::vector<std::string>>>
schema::summary_text(const std::vector<SummaryRow>& rows) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (schema::TableColumn& c : schema::summary_table(rows)) {
    if (c.numeric)
      for (const double x : c.numbers) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.10g", x);
        c.text.push_back(std::isnan(x) ? "" : buf);
      }
    out.emplace_back(std::move(c.name), std::move(c.text));
  }
  return out;
}

namespace {

template <class Row>
std::vector<schema::TableColumn> table_of(const std::vector<Row>& rows,
                                          std::span<const schema::RowColumn<Row>> table) {
  const Layout<Row> l = layout(table);
  std::vector<schema::TableColumn> out;
  for (const FlatColumn<Row>& c : l.columns) {
    schema::TableColumn col;
    col.name = c.name;
    for (const Row& r : rows)
      with_element(r, c, [&](const auto& v) {
        using V = std::remove_cvref_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::string>) {
          col.text.push_back(v);
        } else if constexpr (std::is_same_v<V, ChannelStatus>) {
          col.text.push_back(to_string(v));
        } else {
          // A cell the CSV leaves empty (a flag without its value, a count not screened) is
          // NaN, so that the table reads as the CSV does (docs/python.md).
          const bool empty = c.column->csv && c.column->csv(r, c.term).empty();
          col.numeric = true;
          col.numbers.push_back(empty ? std::nan("") : static_cast<double>(v));
        }
      });
    out.push_back(std::move(col));
  }
  return out;
}

}  // namespace

std::vector<schema::TableColumn> schema::summary_table(const std::vector<SummaryRow>& rows) {
  return table_of(rows, summary_columns());
}

std::vector<schema::TableColumn> schema::statistics_table(const std::vector<StatisticsRow>& rows) {
  return table_of(rows, statistics_columns());
}

std::array<std::filesystem::path, 3> lot_summary_files(const std::filesystem::path& outdir) {
  return {outdir / "lot_summary.csv", outdir / "lot_statistics.csv", outdir / "lot_summary.h5"};
}

void write_lot_summary(const std::filesystem::path& outdir, const std::vector<SummaryRow>& rows,
                       const std::vector<StatisticsRow>& statistics,
                       const std::vector<std::pair<std::string, std::string>>& attributes) {
  h5::quiet_library();
  // The three files are one summary: each is written to its temporary, and none replaces the
  // earlier summary unless all three were written (io::commit_together).
  const auto names = lot_summary_files(outdir);
  AtomicFile csv(names[0]), stats(names[1]);
  write_text(csv, csv_text(rows, schema::summary_columns()));
  write_text(stats, csv_text(statistics, schema::statistics_columns()));
  const std::filesystem::path& h5path = names[2];
  const std::string file = h5path.string();
  AtomicFile atomic(h5path);
  {
    Handle f = h5::create_memory_file(file);
    write_compound(f.get(), "summary", rows, schema::summary_columns(), file);
    write_compound(f.get(), "statistics", statistics, schema::statistics_columns(), file);
    {
      Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
      for (const auto& [name, value] : attributes)
        h5::write_attribute(root.get(), name, value, file, "/");
      schema::write_version(root.get(), file);
    }
    h5::write_memory_file(f, atomic, file);
  }
  commit_together({&csv, &stats, &atomic});
}

std::vector<SummaryRow> read_lot_summary(const std::filesystem::path& h5_path) {
  const std::string file = h5_path.string();
  // A summary without a seal (an earlier version's) is read once in a child process first
  // (io/isolation.hpp), as results files are.
  if (!in_isolated_child() && !require_intact(h5_path))
    run_isolated(file, [&] {
      read_lot_summary(h5_path);
      read_lot_statistics(h5_path);
    });
  Handle f = open_summary_file(file);
  return read_compound(f.get(), "summary", schema::summary_columns(), file);
}

std::vector<StatisticsRow> read_lot_statistics(const std::filesystem::path& h5_path) {
  const std::string file = h5_path.string();
  if (!in_isolated_child() && !require_intact(h5_path))
    run_isolated(file, [&] { read_lot_statistics(h5_path); });
  Handle f = open_summary_file(file);
  if (H5Lexists(f.get(), "statistics", H5P_DEFAULT) <= 0) return {};
  return read_compound(f.get(), "statistics", schema::statistics_columns(), file);
}

std::string csv_number(double v, int digits) {
  if (std::isnan(v)) return "";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

namespace {

// A cell that a spreadsheet would run as a formula (=, +, -, @, or a tab or carriage return
// first: OWASP "CSV Injection"), unless the whole cell is a number such as -1.5e-3.
bool formula_like(const std::string& s) {
  if (s.empty() || std::string_view("=+-@\t\r").find(s[0]) == std::string_view::npos) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end != s.c_str() + s.size();
}

}  // namespace

std::string csv_field(const std::string& text) {
  std::string s = valid_utf8(text);
  // Neutralised as OWASP recommends: a single quote first, and the cell quoted, so that the
  // text reads as text (a device_id "=HYPERLINK(...)" stays that string, plus the quote).
  const bool formula = formula_like(s);
  if (formula) s.insert(s.begin(), '\'');
  if (!formula && s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

}  // namespace allanlot::io
