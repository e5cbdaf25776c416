#include "io/text_recording.hpp"

#include "io/error.hpp"
#include "io/line_reader.hpp"
#include "io/recording.hpp"
#include "io/rostopic_csv.hpp"
#include "io/text_fields.hpp"
#include "io/time_axis.hpp"
#include "io/usage_error.hpp"
#include "io/utf8.hpp"
#include "kernels/model/units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <new>

namespace allanlot::io {
namespace {

// A field in a message: its first 40 bytes, control bytes (a NUL) and bytes that are not UTF-8
// shown as \xNN.
std::string quoted(std::string_view field) {
  std::string s("'");
  s.append(printable(field.substr(0, 40)));
  if (field.size() > 40) s += "...";
  s += "'";
  return s;
}

std::string at_line(std::int64_t line) {
  return "line " + std::to_string(line);
}

// Rows the file's text holds if its lines are `line_bytes` long, with 10 % to spare: the
// channels' arrays are reserved once instead of doubling (which would copy them and leave up
// to twice their size allocated).
std::size_t expected_rows(const std::string& path, double line_bytes) {
  const auto text = static_cast<double>(text_size_hint(path));
  return static_cast<std::size_t>(text / std::max(line_bytes, 1.0) * 1.1) + 16;
}

// The most rows of `columns` values that `limit` bytes hold (InputOptions::memory_limit; 0 is
// no bound).
std::size_t rows_within(std::uint64_t limit, std::size_t columns) {
  if (limit == 0 || columns == 0) return std::numeric_limits<std::size_t>::max();
  return static_cast<std::size_t>(limit / (sizeof(double) * columns));
}

// A text recording is parsed whole: its values, 8 bytes each, must fit the memory limit as they
// grow, so that a gzip bomb (4 MB that decode to gigabytes of rows) ends with an error naming
// the file and the limit rather than an allocation failure, and the memory stays bounded.
void check_rows(const std::string& path, std::int64_t line, std::size_t rows, std::size_t columns,
                std::uint64_t limit) {
  if (rows < rows_within(limit, columns)) return;
  throw Error(path, at_line(line),
              "its values need more than the memory limit of " + memory_text(limit) +
                  " (--memory-limit) allows: " + std::to_string(rows + 1) + " rows of " +
                  std::to_string(columns) + " value(s), 8 bytes each");
}

// push_back that, past the estimate, reserves at once the room the memory limit leaves
// (`max_rows`): address space of which only the values written become resident, so that no
// doubling copies a vector near the limit (old and new arrays together, up to twice the limit).
// Without a limit, or where that much address space is refused, it doubles.
void push_within(std::vector<double>& v, double x, std::size_t max_rows) {
  if (v.size() == v.capacity()) {
    const std::size_t doubled = std::max<std::size_t>(2 * v.capacity(), 16);
    try {
      v.reserve(max_rows != std::numeric_limits<std::size_t>::max() && max_rows > v.size()
                    ? max_rows
                    : doubled);
    } catch (const std::bad_alloc&) {
      v.reserve(doubled);
    }
  }
  v.push_back(x);
}

// Frees what an estimate reserved beyond the samples when it is more than half as much again:
// below that the copy would cost more memory at its peak than the pages never touched (which
// are never resident) do.
void fit_capacity(std::vector<double>& v) {
  if (v.capacity() > v.size() + v.size() / 2) v.shrink_to_fit();
}

// What the head of the file says: a header line or none, the delimiter, the columns.
struct Layout {
  bool header = false;
  char delim = ' ';
  std::vector<HeaderCell> cells;  // with a header
  std::int64_t header_line = 0;
  std::size_t n_fields = 0;  // fields of the first data line (headerless files)
  std::string pending;       // the first data line of a headerless file, already read
  std::int64_t pending_line = 0;
  int time_col = -1;   // with a header: the time column, -1 when there is none
  int value_col = -1;  // headerless: the 0-based column of the values
  // Columns a known header says are no channel (io/rostopic_csv.hpp).
  std::vector<bool> not_channel;
};

char delimiter_for(const std::string& path, std::string_view line) {
  std::string name = ascii_lower(std::filesystem::path(path).filename().string());
  if (name.ends_with(".gz")) name.resize(name.size() - 3);
  if (name.ends_with(".tsv")) return '\t';
  return detect_delimiter(line);
}

int find_time_column(const std::string& path, const Layout& l, const InputOptions& opt) {
  for (std::size_t i = 0; i < l.cells.size(); ++i) {
    const bool named = opt.time_column.empty() ? is_time_name(l.cells[i].name)
                                               : l.cells[i].name == opt.time_column;
    if (named) return static_cast<int>(i);
  }
  if (!opt.time_column.empty())
    throw UsageError(path, "",
                     "--time-column '" + opt.time_column + "': no such column in the header (" +
                         at_line(l.header_line) + ")");
  return -1;
}

// Reads up to the header (if any) and the first data line of a headerless file, and checks
// that the command line gives what the file cannot say.
Layout sniff(LineReader& in, const std::string& path, const InputOptions& opt) {
  Layout l;
  std::string_view line;
  bool found = false;
  while (in.next(line)) {
    if (in.line_number() == 1 && line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);
    if (!is_comment(line) || is_rostopic_header(line)) {
      found = true;
      break;
    }
  }
  if (!found) throw Error(path, "", "no data: every line is empty or a comment");
  l.delim = delimiter_for(path, line);
  std::vector<std::string_view> fields;
  split_fields(line, l.delim, fields);
  double v = 0;
  // A field written as a number that is none (1e999, 0x1p3) makes no header: the line is data,
  // and the field an error naming its line and column.
  l.header = !std::all_of(fields.begin(), fields.end(), [&](std::string_view f) {
    return !f.empty() && (parse_number(f, v) || looks_numeric(f));
  });
  if (l.header) {
    l.header_line = in.line_number();
    for (const auto f : fields)
      l.cells.push_back(parse_header_cell(f));
    if (is_rostopic_header(line)) l.not_channel = rostopic_cells(l.cells);
    l.time_col = find_time_column(path, l, opt);
    if (l.time_col < 0 && !(opt.sample_rate_hz > 0))
      throw UsageError(path, "",
                       "needs --sample-rate HZ (or --tau0 S): its header names no time column "
                       "(time, timestamp, t, stamp, *_time, sec, seconds; or --time-column)");
    return l;
  }
  l.n_fields = fields.size();
  l.pending.assign(line);
  l.pending_line = in.line_number();
  if (opt.column > 0) {
    if (static_cast<std::size_t>(opt.column) > l.n_fields)
      throw UsageError(path, "",
                       "--column " + std::to_string(opt.column) + ": " + at_line(l.pending_line) +
                           " has only " + std::to_string(l.n_fields) + " column(s)");
    l.value_col = opt.column - 1;
  } else if (l.n_fields <= 2) {
    l.value_col = static_cast<int>(l.n_fields) - 1;  // a leading time tag, then the value
  } else {
    throw UsageError(path, "",
                     "needs --column N: " + at_line(l.pending_line) + " has " +
                         std::to_string(l.n_fields) + " columns and no header names them");
  }
  if (!opt.data_type)
    throw UsageError(path, "",
                     "needs --data-type rate|phase: a single-column text file does not say "
                     "whether it holds rate (frequency) or phase (time error) data");
  if (!(opt.sample_rate_hz > 0))
    throw UsageError(path, "",
                     "needs --sample-rate HZ (or --tau0 S): a single-column text file does not "
                     "say its sample rate");
  return l;
}

// The unit of the column that is channel `path` (io/input_options.hpp, InputOptions::units):
// a --units glob that matches it, over its header's; else the header's; else a bare --units.
std::string column_units(const std::string& path, const std::string& header,
                         const InputOptions& opt, std::vector<std::string>& notes) {
  for (const ColumnUnits& r : opt.units) {
    if (r.glob.empty() || !channel_glob_matches(r.glob, path)) continue;
    const auto same = [](const std::string& a, const std::string& b) {
      const auto ka = kernels::units::parse_channel_units(a);
      const auto kb = kernels::units::parse_channel_units(b);
      return ka && kb
                 ? ka->canonical == kb->canonical && ka->scale == kb->scale
                 : kernels::units::normalize_spelling(a) == kernels::units::normalize_spelling(b);
    };
    if (!header.empty() && !same(header, r.unit))
      notes.push_back("column '" + path.substr(1) + "': --units '" + r.glob + "=" + r.unit +
                      "' replaces the header's unit '" + header + "'");
    return r.unit;
  }
  if (!header.empty()) return header;
  for (const ColumnUnits& r : opt.units)
    if (r.glob.empty()) return r.unit;
  return "";
}

void read_single_column(LineReader& in, const std::string& path, const Layout& l,
                        const InputOptions& opt, TextRecording& rec) {
  TextChannel ch;
  ch.path = "/data";
  ch.units = column_units(ch.path, "", opt, rec.notes);
  std::vector<std::string_view> fields;
  const auto take = [&](std::string_view line, std::int64_t line_no) {
    split_fields(line, l.delim, fields);
    if (fields.size() != l.n_fields)
      throw Error(path, at_line(line_no),
                  "has " + std::to_string(fields.size()) + " field(s), " + at_line(l.pending_line) +
                      " has " + std::to_string(l.n_fields));
    double v = 0;
    const std::string_view f = fields[static_cast<std::size_t>(l.value_col)];
    if (!parse_number(f, v))
      throw Error(path, at_line(line_no) + ", column " + std::to_string(l.value_col + 1),
                  quoted(f) + " is not a number");
    check_rows(path, line_no, ch.samples.size(), 1, opt.memory_limit);
    push_within(ch.samples, v, rows_within(opt.memory_limit, 1));
  };
  ch.samples.reserve(std::min(expected_rows(path, static_cast<double>(l.pending.size() + 1)),
                              rows_within(opt.memory_limit, 1)));
  take(l.pending, l.pending_line);
  std::string_view line;
  while (in.next(line))
    if (!is_comment(line)) take(line, in.line_number());
  fit_capacity(ch.samples);
  rec.sample_rate_hz = opt.sample_rate_hz;
  rec.facts.emplace_back("source_layout", "single column");
  rec.facts.emplace_back("source_column", std::to_string(l.value_col + 1));
  rec.channels.push_back(std::move(ch));
}

// The unit of a numeric time column: --time-unit, else the header's unit or name, else the
// magnitude of the first time stamp (an epoch in s, ms, µs or ns), else seconds.
std::pair<double, std::string> time_unit(const std::string& path, const HeaderCell& cell,
                                         double first, const InputOptions& opt) {
  if (!opt.time_unit.empty()) {
    const auto s = time_unit_seconds(opt.time_unit);
    if (!s) throw UsageError(path, "", "--time-unit '" + opt.time_unit + "': not s, ms, us or ns");
    return {*s, opt.time_unit + " (--time-unit)"};
  }
  if (const auto s = time_unit_seconds(cell.unit)) return {*s, cell.unit + " (header)"};
  const std::string name = ascii_lower(cell.name);
  if (const auto u = name.rfind('_'); u != std::string::npos)
    if (const auto s = time_unit_seconds(std::string_view(name).substr(u + 1)))
      return {*s, name.substr(u + 1) + " (header)"};
  const double a = std::fabs(first);
  if (a >= 1e17) return {1e-9, "ns (by magnitude: an epoch)"};
  if (a >= 1e14) return {1e-6, "us (by magnitude: an epoch)"};
  if (a >= 1e11) return {1e-3, "ms (by magnitude: an epoch)"};
  return {1.0, "s (by magnitude)"};
}

std::string channel_name(const HeaderCell& cell, std::size_t col,
                         const std::vector<TextChannel>& taken) {
  std::string name = cell.name;
  std::replace(name.begin(), name.end(), '/', '_');
  if (name.empty() || name == "." || name == "..") {
    name = std::string("column_");
    name += std::to_string(col + 1);
  }
  std::string unique = name;
  for (int k = 2; std::any_of(taken.begin(), taken.end(),
                              [&](const TextChannel& c) { return c.path.substr(1) == unique; });
       ++k)
    unique = name + "_" + std::to_string(k);
  return unique;
}

}  // namespace

namespace {

// The rows of a CSV/TSV file with a header, read in one pass.
class CsvReader {
public:
  CsvReader(const std::string& path, const Layout& l, const InputOptions& opt, TextRecording& rec)
      : path_(path), l_(l), opt_(opt), rec_(rec), channel_of_(l.cells.size(), -1) {}

  void read(LineReader& in) {
    std::string_view line;
    while (in.next(line)) {
      if (is_comment(line)) continue;
      const std::int64_t ln = in.line_number();
      split_fields(line, l_.delim, fields_);
      if (fields_.size() != l_.cells.size())
        throw Error(path_, at_line(ln),
                    "has " + std::to_string(fields_.size()) + " field(s), the header (" +
                        at_line(l_.header_line) + ") has " + std::to_string(l_.cells.size()) +
                        ": its values cannot be matched to the columns");
      if (rows_ == 0) choose_columns(ln, static_cast<double>(line.size() + 1));
      // The first line alone may be shorter than most: the estimate again, from 4096 lines.
      if (rows_ == 4096) reserve(static_cast<double>(in.bytes()) / static_cast<double>(ln));
      for (std::size_t c = 0; c < fields_.size(); ++c) {
        const int k = channel_of_[c];
        if (k < 0) continue;
        double v = 0;
        if (!parse_number(fields_[c], v))
          throw Error(path_, where(ln, c), quoted(fields_[c]) + " is not a number");
        push_within(rec_.channels[static_cast<std::size_t>(k)].samples, v, max_rows_);
      }
      if (l_.time_col >= 0) add_time(ln);
      check_rows(path_, ln, static_cast<std::size_t>(rows_), columns(), opt_.memory_limit);
      ++rows_;
    }
    if (rows_ == 0)
      throw Error(path_, "", "no data: the header (" + at_line(l_.header_line) + ") has no rows");
    if (rec_.channels.empty()) throw Error(path_, "", "no numeric column besides the time");
    finish();
  }

private:
  std::string where(std::int64_t ln, std::size_t c) const {
    return at_line(ln) + ", column " + std::to_string(c + 1) + " (" + printable(l_.cells[c].name) +
           ")";
  }

  // The values a row holds: its channels and its time stamp.
  std::size_t columns() const { return rec_.channels.size() + (l_.time_col >= 0 ? 1 : 0); }

  // Room for the rows a file of lines this long holds (expected_rows), within the memory limit.
  void reserve(double line_bytes) {
    max_rows_ = rows_within(opt_.memory_limit, columns());
    const std::size_t rows = std::min(expected_rows(path_, line_bytes), max_rows_);
    if (l_.time_col >= 0) times_.reserve(rows);
    for (TextChannel& ch : rec_.channels)
      ch.samples.reserve(rows);
  }

  // The first row decides: a column whose first value is text (labels, status words) is never
  // a channel, nor is one named like time stamps besides the time column (as in an HDF5
  // recording); every other column is one. A first value written as a number that is none
  // (1e999, 0x1p3) is an error, as it is further down.
  void choose_columns(std::int64_t ln, double line_bytes) {
    for (std::size_t c = 0; c < fields_.size(); ++c) {
      double v = 0;
      if (static_cast<int>(c) == l_.time_col) continue;
      if (c < l_.not_channel.size() && l_.not_channel[c]) continue;
      const std::string column =
          "column " + std::to_string(c + 1) + " (" + printable(l_.cells[c].name) + ")";
      if (is_time_name(l_.cells[c].name)) {
        rec_.notes.push_back(column + " is named like time stamps: not a channel (the time is " +
                             time_column_text() + ")");
        continue;
      }
      if (!parse_number(fields_[c], v)) {
        if (looks_numeric(fields_[c]))
          throw Error(path_, where(ln, c), quoted(fields_[c]) + " is not a number");
        rec_.notes.push_back(column + " is not numeric: not a channel");
        continue;
      }
      TextChannel ch;
      ch.path = "/" + channel_name(l_.cells[c], c, rec_.channels);
      ch.units = column_units(ch.path, l_.cells[c].unit, opt_, rec_.notes);
      channel_of_[c] = static_cast<int>(rec_.channels.size());
      rec_.channels.push_back(std::move(ch));
    }
    reserve(line_bytes);
  }

  void add_time(std::int64_t ln) {
    const auto c = static_cast<std::size_t>(l_.time_col);
    const std::string_view f = fields_[c];
    double t = 0;
    NumericStamp stamp;
    const StampParse parsed = parse_numeric_stamp(f, stamp);
    if (parsed == StampParse::beyond_int64)
      throw Error(path_, where(ln, c),
                  quoted(f) + " is beyond the range of a time stamp (a 64-bit integer)");
    if (rows_ == 0) iso_ = parsed != StampParse::ok;
    if (iso_) {
      const auto iso = parse_iso8601(f);
      if (!iso)
        throw Error(path_, where(ln, c),
                    quoted(f) + (rows_ == 0 ? " is neither a number nor an ISO-8601 time"
                                            : " is not an ISO-8601 time, as the first row's is"));
      if (rows_ == 0) iso0_ = iso->seconds;
      t = static_cast<double>(iso->seconds - iso0_) + iso->fraction;
    } else if (parsed != StampParse::ok) {
      throw Error(path_, where(ln, c), quoted(f) + " is not a time stamp");
    } else {
      t = since_first(stamp, ln, c);
    }
    // A stamp not after the ones before it is kept as the next sample and counted by the time
    // axis for the data-quality screen (docs/quality.md), not refused.
    push_within(times_, t, max_rows_);
  }

  // The stamp after the first, as a double: the integer parts subtracted exactly first, so
  // that what is left (an hour in ns is 3.6e12) is exact in double's 53 bits.
  double since_first(const NumericStamp& stamp, std::int64_t ln, std::size_t c) {
    if (rows_ == 0) first_ = stamp;
    std::int64_t whole = 0;
    if (__builtin_sub_overflow(stamp.whole, first_.whole, &whole))
      throw Error(path_, where(ln, c),
                  quoted(fields_[c]) + " is too far from the first time stamp (" +
                      std::to_string(first_.whole) + ") for a 64-bit difference");
    return static_cast<double>(whole) + (stamp.fraction - first_.fraction);
  }

  void finish() {
    for (TextChannel& ch : rec_.channels)
      fit_capacity(ch.samples);
    if (l_.time_col < 0) {
      rec_.sample_rate_hz = opt_.sample_rate_hz;
      rec_.facts.emplace_back("time_column", "(none: --sample-rate)");
      return;
    }
    const HeaderCell& cell = l_.cells[static_cast<std::size_t>(l_.time_col)];
    if (times_.size() < 2 && !(opt_.sample_rate_hz > 0))
      throw UsageError(path_, "", "one row: needs --sample-rate HZ, its time step is unknown");
    const auto [unit_s, unit_text] = iso_ ? std::pair<double, std::string>{1.0, "ISO-8601"}
                                          : time_unit(path_, cell, first_seconds(), opt_);
    TimeAxis axis;
    try {
      axis = make_time_axis(times_, 100 * rows_);
    } catch (const std::invalid_argument& e) {
      throw Error(path_, "time column " + cell.name, e.what());
    }
    times_ = {};
    const double step_s = axis.step * unit_s;
    rec_.sample_rate_hz = opt_.sample_rate_hz > 0 ? opt_.sample_rate_hz : 1.0 / step_s;
    for (TextChannel& ch : rec_.channels)
      ch.samples = with_gaps(std::move(ch.samples), axis);
    rec_.facts.emplace_back("time_column", cell.name);
    rec_.facts.emplace_back("time_unit", unit_text);
    add_time_axis_facts(rec_.facts, axis, unit_s);
    rec_.time_stamps = {axis.n_duplicate, axis.first_duplicate, axis.n_decreasing,
                        axis.first_decreasing};
    if (axis.n_duplicate + axis.n_decreasing > 0)
      rec_.notes.push_back(std::to_string(axis.n_duplicate) + " repeated and " +
                           std::to_string(axis.n_decreasing) +
                           " decreasing time stamp(s) in the time column '" + cell.name +
                           "', each taken as the next sample (the quality screen counts them)");
    if (axis.missing > 0)
      rec_.notes.push_back(std::to_string(axis.missing) + " missing sample(s) in " +
                           std::to_string(axis.gaps.size()) + " place(s) of the time column '" +
                           cell.name + "', analysed as gaps");
    if (axis.jitter_rms > 0.01 * axis.step)
      rec_.notes.push_back("timing jitter of the time column '" + cell.name + "': rms " +
                           exact_text(axis.jitter_rms * unit_s) + " s, " +
                           exact_text(100 * axis.jitter_rms / axis.step) + " % of the step " +
                           exact_text(step_s) + " s");
  }

  std::string time_column_text() const {
    if (l_.time_col < 0) return "--sample-rate's";
    const auto c = static_cast<std::size_t>(l_.time_col);
    return "column " + std::to_string(c + 1) + " (" + printable(l_.cells[c].name) + ")";
  }

  double first_seconds() const { return static_cast<double>(first_.whole) + first_.fraction; }

  const std::string& path_;
  const Layout& l_;
  const InputOptions& opt_;
  TextRecording& rec_;
  std::vector<int> channel_of_;  // per column: the channel it fills, -1 for none
  std::vector<std::string_view> fields_;
  std::vector<double> times_;
  bool iso_ = false;
  long long iso0_ = 0;
  NumericStamp first_;  // the first numeric stamp: times_ are taken from it
  std::int64_t rows_ = 0;
  std::size_t max_rows_ = 0;  // the rows the memory limit holds (rows_within)
};

std::string strip_gz(std::string name) {
  if (ascii_lower(name).ends_with(".gz")) name.resize(name.size() - 3);
  return name;
}

}  // namespace

bool is_text_name(const std::string& path) {
  const std::string name = ascii_lower(strip_gz(std::filesystem::path(path).filename().string()));
  for (const char* ext : {".txt", ".dat", ".csv", ".tsv"})
    if (name.ends_with(ext) && name.size() > 4) return true;
  return false;
}

std::string text_device_id(const std::string& path) {
  std::string name = strip_gz(std::filesystem::path(path).filename().string());
  const std::string ext = ascii_lower(std::filesystem::path(name).extension().string());
  if (ext == ".txt" || ext == ".dat" || ext == ".csv" || ext == ".tsv")
    name.resize(name.size() - ext.size());
  return name;
}

void check_text_options(const std::string& path, const InputOptions& opt) {
  LineReader in(path, opt.memory_limit);
  (void)sniff(in, path, opt);
}

TextRecording read_text_recording(const std::string& path, const InputOptions& opt) {
  LineReader in(path, opt.memory_limit);
  const Layout l = sniff(in, path, opt);
  TextRecording rec;
  rec.device_id = text_device_id(path);
  rec.data_type = opt.data_type;
  rec.facts.emplace_back("source_file_name", std::filesystem::path(path).filename().string());
  if (l.header) {
    rec.facts.emplace_back("source_layout", l.delim == '\t' ? "tsv" : "csv");
    CsvReader(path, l, opt, rec).read(in);
  } else {
    read_single_column(in, path, l, opt, rec);
  }
  std::sort(rec.channels.begin(), rec.channels.end(),
            [](const TextChannel& a, const TextChannel& b) { return a.path < b.path; });
  return rec;
}

}  // namespace allanlot::io
