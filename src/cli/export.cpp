#include "src/cli/export.hpp"

#include "io/paths.hpp"
#include "src/cli/input_options.hpp"
#include "src/workflow/inputs.hpp"

#include "io/atomic_file.hpp"
#include "io/recording.hpp"
#include "io/results.hpp"
#include "io/stable32_table.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/units.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <string_view>
#include <utility>

namespace allanlot::cli {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Tidy CSV numbers: 12 significant digits (the dev values are exact to far fewer; more would
// only show the last bits of the double).
std::string csv_number(double v) {
  return io::csv_number(v, 12);
}

template <class T>
T at(const std::vector<T>& v, std::size_t i, T fallback) {
  return i < v.size() ? v[i] : fallback;
}

std::string root_attribute(const io::RecordingResult& r, std::string_view key) {
  for (const auto& [k, v] : r.attributes)
    if (k == key) return v;
  return "";
}

// The "FILE:" a table is titled by: the recording's file; for a hat's results (one file per
// pair, source_file lists them in pair order) the clock a /clocks/X table is of, with the
// pairs it comes from, and the pair's own file for a /pairs/XY table.
std::string stable32_file_title(const io::RecordingResult& r, const io::ChannelResult& ch) {
  if (root_attribute(r, "statistic") != "hat") return fs::path(r.source_file).filename().string();
  std::vector<std::string> files;  // paired_root joins the pairs' files with "; "
  std::stringstream ss(r.source_file);
  for (std::string f; std::getline(ss, f, ';');)
    files.push_back(
        fs::path(f.substr(std::min(f.find_first_not_of(' '), f.size()))).filename().string());
  const std::string name = ch.path.substr(ch.path.find_last_of('/') + 1);
  // The pairs in the command's order: the `pairs` attribute of hat --clocks, else AB BC CA.
  std::vector<std::string> pair_order;
  std::stringstream ps(root_attribute(r, "pairs"));
  for (std::string p; std::getline(ps, p, ',');)
    pair_order.push_back(p);
  const bool n_hat = !pair_order.empty();
  if (!n_hat) pair_order = {"AB", "BC", "CA"};  // src/cli/hat.cpp's three-cornered form
  if (ch.path.starts_with("/clocks/")) {
    std::string pairs;
    for (const std::string& f : files)
      pairs += (pairs.empty() ? "" : ", ") + f;
    const std::string clocks = root_attribute(r, "clocks");
    const std::string method =
        n_hat ? std::to_string(std::count(clocks.begin(), clocks.end(), ',') + 1) + "-cornered hat"
              : std::string("three-cornered hat");
    return "clock " + name + " (" + method + " of " + pairs + ")";
  }
  for (std::size_t k = 0; k < pair_order.size() && k < files.size(); ++k)
    if (name == pair_order[k]) return files[k] + " (pair " + name + ")";
  return fs::path(r.source_file).filename().string();
}

// What Stable32 prints above a table of this channel, and allanlot's own line below it.
io::Stable32Head stable32_head(const io::RecordingResult& r, const io::ChannelResult& ch) {
  io::Stable32Head h;
  h.file = stable32_file_title(r, ch);
  h.phase = ch.data_type == "phase";
  h.n_points = ch.n_samples;
  h.max = ch.data_max;
  h.min = ch.data_min;
  h.mean = ch.data_mean;
  // `--taus stable32` gives MTIE Stable32's fast list (kernels::stat_m_list); any other grid
  // is a non-fast run.
  h.mtie_fast = root_attribute(r, "taus").starts_with("stable32");
  h.trailer = "# allanlot: device " + r.device_id + ", channel " + ch.path + ", units " +
              (ch.units.empty() ? std::string("none") : ch.units) + "\n";
  return h;
}

// The unit of a statistic's dev, lo and hi: a deviation of the rate is in the rate's unit (B's
// unit in channel units: deg/s for a gyro, dimensionless for a clock, whether its samples are a
// time error in s or a fractional frequency), a time error in the rate's unit times seconds
// (Q's: deg/s*s, s for a clock); "" when the channel has no units.
std::string dev_unit(const std::string& name, const std::string& channel_units) {
  if (channel_units.empty()) return "";
  const auto stat = kernels::parse_stat(name);
  const bool time_error = stat && kernels::is_time_error(*stat);
  return kernels::units::channel_unit(time_error ? kernels::Term::Q : kernels::Term::B,
                                      channel_units);
}

void csv_rows(std::ostream& text, const io::RecordingResult& r, const io::ChannelResult& ch,
              const std::string& name, const kernels::StatResult& s) {
  const std::string prefix = io::csv_field(r.device_id) + "," + io::csv_field(ch.path) + "," +
                             io::csv_field(ch.units) + "," + name + ",";
  const std::string unit = "," + io::csv_field(dev_unit(name, ch.units));
  const bool ci = s.confidence > 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    text << prefix << s.m[i] << "," << csv_number(s.tau_s[i]) << "," << s.n[i] << ","
         << (i < s.alpha.size() ? std::to_string(s.alpha[i]) : std::string()) << ","
         << csv_number(ci ? at(s.dev_lo, i, kNaN) : kNaN) << "," << csv_number(s.dev[i]) << ","
         << csv_number(ci ? at(s.dev_hi, i, kNaN) : kNaN) << ","
         << csv_number(ci ? at(s.edf, i, kNaN) : kNaN) << ","
         << (ci ? csv_number(s.confidence) : std::string()) << unit << "\n";
}

// The read-outs in the order of the terminal table: N at 1 s, bias instability, K at 3 s.
constexpr std::pair<const char*, const char*> kReadouts[] = {
    {"N_1s", "N"}, {"bias_instability", "B"}, {"K_3s", "K"}};

constexpr const char* kReadoutHeader =
    "device_id,channel,units,readout,term,tau,value,sigma,unit,value_alt,sigma_alt,unit_alt,"
    "detected,note\n";

// Why a read-out is not what the fit says, or "" when it is (docs/cli.md "Command: export").
std::string readout_note(const io::ReadoutRecord& x, const char* term) {
  if (!(x.tau_s > 0.0) || !std::isfinite(x.value_datasheet))
    return "the curve does not reach the read-out's tau";
  if (!x.valid)
    return std::string("the fit does not detect ") + term +
           ": read on a branch the curve may not have";
  return "";
}

// One row per read-out of a channel with a fit (IEEE Std 952 annex C, as in the terminal table
// and the lot summary), also when the fit does not detect the term: then detected is 0 and the
// note says why.
void readout_rows(std::ostream& text, const io::RecordingResult& r, const io::ChannelResult& ch) {
  if (!ch.fit) return;
  const std::string prefix = io::csv_field(r.device_id) + "," + io::csv_field(ch.path) + "," +
                             io::csv_field(ch.units) + ",";
  for (const auto& kv : kReadouts) {
    // Plain variables, not a structured binding: clang 14 (the TSan build) cannot capture one.
    const std::string_view name = kv.first;
    const char* term = kv.second;
    const auto& xs = ch.fit->readouts;
    const auto x = std::find_if(xs.begin(), xs.end(),
                                [name](const io::ReadoutRecord& y) { return y.name == name; });
    if (x == xs.end()) continue;
    const bool read = x->tau_s > 0.0 && std::isfinite(x->value_datasheet);
    text << prefix << name << "," << term << "," << csv_number(read ? x->tau_s : kNaN) << ","
         << csv_number(read ? x->value_datasheet : kNaN) << ","
         << csv_number(read ? x->sigma_datasheet : kNaN) << "," << io::csv_field(x->unit_datasheet)
         << "," << csv_number(read ? x->value_datasheet_alt : kNaN) << ","
         << csv_number(read ? x->sigma_datasheet_alt : kNaN) << ","
         << io::csv_field(x->unit_datasheet_alt) << "," << (x->valid ? "1" : "0") << ","
         << io::csv_field(readout_note(*x, term)) << "\n";
  }
}

// The formats of src/cli/export_filter.cpp, nullopt for the tables of this file.
std::optional<FilterFormat> filter_format(ExportFormat f) {
  if (f == ExportFormat::Kalibr) return FilterFormat::Kalibr;
  if (f == ExportFormat::OpenVins) return FilterFormat::OpenVins;
  if (f == ExportFormat::Vins) return FilterFormat::Vins;
  return std::nullopt;
}

// The results files named (directories expanded, sorted); false after a usage error on `err`.
bool results_files(const ExportOptions& opt, std::vector<fs::path>& files, std::ostream& err) {
  for (const fs::path& in : opt.inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::directory_iterator(in, ec)) {
        const std::string n = e.path().filename().string();
        if (e.is_regular_file() && n.size() > 9 && n[0] != '.' &&
            n.compare(n.size() - 9, 9, ".allan.h5") == 0)
          found.push_back(e.path());
      }
      if (found.empty()) {
        err << "allanlot: usage error: " << in.string() << ": no results files (*.allan.h5)\n";
        return false;
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(in, ec)) {
      files.push_back(in);
    } else {
      err << "allanlot: usage error: " << in.string() << ": no such file or directory\n";
      return false;
    }
  }
  return true;
}

}  // namespace

std::string stable32_file_name(const std::string& device_id, const std::string& channel,
                               const std::string& stat) {
  std::string c = channel;
  while (!c.empty() && c.front() == '/')
    c.erase(c.begin());
  std::string name = device_id;
  name += '.';
  name += c;
  name += '.';
  name += stat;
  return io::sanitize_device_id(name) + ".txt";
}

int run_export(const ExportOptions& opt, std::ostream& out, std::ostream& err) {
  for (const std::string& s : opt.stats)
    if (!kernels::parse_stat(s)) {
      err << "allanlot: usage error: --stats: unknown statistic '" << s << "'\n";
      return kExitUsage;
    }
  if (opt.format == ExportFormat::Readouts && !opt.stats.empty()) {
    err << "allanlot: usage error: --stats selects deviation tables; --format readouts has "
           "none\n";
    return kExitUsage;
  }
  std::vector<fs::path> files;
  if (!results_files(opt, files, err)) return kExitUsage;
  if (const auto f = filter_format(opt.format)) {
    if (!opt.stats.empty()) {
      err << "allanlot: usage error: --stats selects deviation tables; --format kalibr, "
             "openvins and vins have none\n";
      return kExitUsage;
    }
    return run_filter_export({*f, opt.combine, opt.output, opt.channels}, files, out, err);
  }
  std::error_code ec;
  const bool to_dir = !opt.output.empty() && fs::is_directory(opt.output, ec);
  if (to_dir && opt.format != ExportFormat::Stable32) {
    err << "allanlot: usage error: -o " << opt.output.string()
        << " is a directory: one file per table is for --format stable32; give a file\n";
    return kExitUsage;
  }

  // Every output (a file, or one file per table) and its text, checked against the inputs
  // before anything is written.
  std::map<fs::path, std::string> outputs;
  std::ostringstream text;
  if (opt.format == ExportFormat::Csv)
    text << "device_id,channel,units,stat,m,tau,n,alpha,dev_lo,dev,dev_hi,edf,confidence,"
            "dev_units\n";
  if (opt.format == ExportFormat::Readouts) text << kReadoutHeader;
  std::size_t read_ok = 0, unreadable = 0, tables = 0;
  for (const fs::path& f : files) {
    io::RecordingResult r;
    try {
      r = io::read_results(f);
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      ++unreadable;
      continue;
    }
    ++read_ok;
    for (const io::ChannelResult& ch : r.channels) {
      if (!opt.channels.selects(ch.path)) continue;
      if (opt.format == ExportFormat::Readouts) {
        readout_rows(text, r, ch);
        continue;
      }
      for (const auto& [name, s] : ch.stats) {
        if (!opt.stats.empty() &&
            std::find(opt.stats.begin(), opt.stats.end(), name) == opt.stats.end())
          continue;
        if (opt.format == ExportFormat::Csv) {
          csv_rows(text, r, ch, name, s);
          continue;
        }
        const std::string table = io::stable32_table(stable32_head(r, ch), name, s);
        if (to_dir)
          outputs[opt.output / stable32_file_name(r.device_id, ch.path, name)] = table;
        else  // tables one after the other, parted by a comment line (no blank line)
          text << (tables > 0 ? "#\n" : "") << table;
        ++tables;
      }
    }
  }
  if (read_ok == 0) {
    err << "allanlot: error: no results file could be read\n";
    return kExitUsage;
  }
  if (!to_dir && !opt.output.empty()) outputs[opt.output] = text.str();
  std::vector<fs::path> planned;
  for (const auto& [path, body] : outputs)
    planned.push_back(path);
  if (const std::string clash = io::outputs_conflict(planned, files); !clash.empty()) {
    err << "allanlot: usage error: " << clash << "\n";
    return kExitUsage;
  }
  if (opt.output.empty()) out << text.str();
  try {
    for (const auto& [path, body] : outputs)
      io::write_text_atomic(path, body);
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  if (to_dir) out << outputs.size() << " Stable32 table(s) in " << opt.output.string() << "\n";
  return unreadable ? kExitSomeFailed : kExitOk;
}

Command add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  auto inputs = std::make_shared<std::vector<std::string>>();
  auto format = std::make_shared<std::string>("csv");
  auto output = std::make_shared<std::string>();
  auto stats = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "export", "Write the Allan-family tables of results files as Stable32 tables or tidy CSV, "
                "or their read-outs as tidy CSV");
  sub->add_option("results", *inputs, "Results files (*.allan.h5) or directories of them")
      ->required();
  sub->add_option("--format", *format,
                  "stable32 (Stable32 1.60 run tables), csv (tidy deviations), readouts (tidy "
                  "N at 1 s, bias instability, K at 3 s), or one IMU's noise for kalibr "
                  "(imu.yaml), openvins (kalibr_imu_chain.yaml) or vins (acc_n, gyr_n, acc_w, "
                  "gyr_w)")
      ->check(CLI::IsMember({"stable32", "csv", "readouts", "kalibr", "openvins", "vins"}))
      ->capture_default_str();
  auto combine = std::make_shared<std::string>("max");
  sub->add_option("--combine", *combine,
                  "kalibr, openvins, vins: the three axes' values as their largest (max) or "
                  "their mean")
      ->check(CLI::IsMember({"max", "mean"}))
      ->capture_default_str();
  sub->add_option("-o,--output", *output,
                  "File to write (default: standard output); with --format stable32 an existing "
                  "directory gets one file per table");
  sub->add_option("--stats", *stats, "Only these statistics (comma-separated)");
  auto channels = std::make_shared<std::vector<std::string>>();
  auto exclude = std::make_shared<std::vector<std::string>>();
  add_channel_options(sub, *channels, *exclude);
  return {sub, [=](const std::string&) {
            opt->inputs.assign(inputs->begin(), inputs->end());
            const std::map<std::string, ExportFormat> formats{
                {"stable32", ExportFormat::Stable32}, {"csv", ExportFormat::Csv},
                {"readouts", ExportFormat::Readouts}, {"kalibr", ExportFormat::Kalibr},
                {"openvins", ExportFormat::OpenVins}, {"vins", ExportFormat::Vins}};
            opt->format = formats.at(*format);
            opt->combine = *combine == "mean" ? AxisCombine::Mean : AxisCombine::Max;
            opt->output = *output;
            opt->channels = channel_selection(*channels, *exclude);
            std::stringstream ss(*stats);
            std::string s;
            while (std::getline(ss, s, ','))
              if (!s.empty()) opt->stats.push_back(s);
            return run_export(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
