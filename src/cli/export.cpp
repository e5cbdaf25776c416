#include "src/cli/export.hpp"

#include "io/paths.hpp"
#include "src/cli/inputs.hpp"

#include "io/atomic_file.hpp"
#include "io/results.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <ostream>
#include <sstream>

namespace allanlot::cli {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Stable32's names of the statistics, as its "Sigma Type:" header line prints them.
std::string sigma_type(const std::string& stat) {
  static const std::map<std::string, std::string> names = {
      {"adev", "Allan"},          {"oadev", "Overlapping Allan"},
      {"mdev", "Modified Allan"}, {"tdev", "Time"},
      {"hdev", "Hadamard"},       {"ohdev", "Overlapping Hadamard"},
      {"totdev", "Total"},        {"mtotdev", "Modified Total"},
      {"ttotdev", "Time Total"},  {"htotdev", "Hadamard Total"},
      {"theo1", "Thêo1"},         {"theoh", "ThêoH"},
      {"mtie", "MTIE"},           {"tierms", "TIE rms"},
      {"pdev", "Parabolic"}};
  const auto it = names.find(stat);
  return it == names.end() ? stat : it->second;
}

// Stable32 prints 5 significant digits ("%.4e"); a value that is not a number is printed as
// 0, which is what Stable32 shows for a quantity it did not compute.
std::string e4(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4e", std::isfinite(v) ? v : 0.0);
  return buf;
}

// Tidy CSV numbers: 12 significant digits (the dev values are exact to far fewer; more would
// only show the last bits of the double).
std::string csv_number(double v) {
  return io::csv_number(v, 12);
}

template <class T>
T at(const std::vector<T>& v, std::size_t i, T fallback) {
  return i < v.size() ? v[i] : fallback;
}

}  // namespace

std::string stable32_block(const std::string& device_id, const std::string& channel,
                           const std::string& units, const std::string& stat,
                           const kernels::StatResult& s) {
  std::ostringstream o;
  o << "# allanlot " << stat << " (Stable32 1.60 table format)\n"
    << "# Device: " << device_id << "\n# Channel: " << channel << "\n# Units: " << units << "\n"
    << "# Sigma Type: " << sigma_type(stat) << "\n";
  char buf[160];
  std::snprintf(buf, sizeof buf, "# Confidence Factor = %.3f\n", s.confidence);
  o << buf << "#\n"
    << "#  AF        Tau        #    Alpha  Min Sigma      Sigma         Max Sigma\n";
  const bool ci = s.confidence > 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double lo = ci ? at(s.dev_lo, i, 0.0) : 0.0;
    const double hi = ci ? at(s.dev_hi, i, 0.0) : 0.0;
    std::snprintf(buf, sizeof buf, "%5lld   %s%9lld%6d   %s    %s     %s\n",
                  static_cast<long long>(s.m[i]), e4(s.tau_s[i]).c_str(),
                  static_cast<long long>(s.n[i]), at(s.alpha, i, 0), e4(lo).c_str(),
                  e4(s.dev[i]).c_str(), e4(hi).c_str());
    o << buf;
  }
  return o.str();
}

int run_export(const ExportOptions& opt, std::ostream& out, std::ostream& err) {
  for (const std::string& s : opt.stats)
    if (!kernels::parse_stat(s)) {
      err << "allanlot: usage error: --stats: unknown statistic '" << s << "'\n";
      return kExitUsage;
    }
  std::vector<fs::path> files;
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
        return kExitUsage;
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(in, ec)) {
      files.push_back(in);
    } else {
      err << "allanlot: usage error: " << in.string() << ": no such file or directory\n";
      return kExitUsage;
    }
  }
  const std::vector<fs::path> outputs = {opt.output};
  if (const std::string clash = io::outputs_conflict(outputs, files); !clash.empty()) {
    err << "allanlot: usage error: " << clash << "\n";
    return kExitUsage;
  }

  std::ostringstream text;
  if (opt.format == ExportFormat::Csv)
    text << "device_id,channel,units,stat,m,tau,n,alpha,dev_lo,dev,dev_hi,edf,confidence\n";
  std::size_t read_ok = 0, unreadable = 0, blocks = 0;
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
      if (!channel_matches(opt.channels_glob, ch.path)) continue;
      for (const auto& [name, s] : ch.stats) {
        if (!opt.stats.empty() &&
            std::find(opt.stats.begin(), opt.stats.end(), name) == opt.stats.end())
          continue;
        ++blocks;
        if (opt.format == ExportFormat::Stable32) {
          text << (blocks > 1 ? "\n" : "")
               << stable32_block(r.device_id, ch.path, ch.units, name, s);
          continue;
        }
        const std::string prefix = io::csv_field(r.device_id) + "," + io::csv_field(ch.path) + "," +
                                   io::csv_field(ch.units) + "," + name + ",";
        for (std::size_t i = 0; i < s.size(); ++i) {
          const bool ci = s.confidence > 0.0;
          text << prefix << s.m[i] << "," << csv_number(s.tau_s[i]) << "," << s.n[i] << ","
               << (i < s.alpha.size() ? std::to_string(s.alpha[i]) : std::string()) << ","
               << csv_number(ci ? at(s.dev_lo, i, kNaN) : kNaN) << "," << csv_number(s.dev[i])
               << "," << csv_number(ci ? at(s.dev_hi, i, kNaN) : kNaN) << ","
               << csv_number(ci ? at(s.edf, i, kNaN) : kNaN) << ","
               << (ci ? csv_number(s.confidence) : std::string()) << "\n";
        }
      }
    }
  }
  if (read_ok == 0) {
    err << "allanlot: error: no results file could be read\n";
    return kExitUsage;
  }
  if (opt.output.empty()) {
    out << text.str();
  } else {
    try {
      io::write_text_atomic(opt.output, text.str());
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return kExitUsage;
    }
  }
  return unreadable ? kExitSomeFailed : kExitOk;
}

Command add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  auto inputs = std::make_shared<std::vector<std::string>>();
  auto format = std::make_shared<std::string>("csv");
  auto output = std::make_shared<std::string>();
  auto stats = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "export", "Write the Allan-family tables of results files as Stable32 tables or tidy CSV");
  sub->add_option("results", *inputs, "Results files (*.allan.h5) or directories of them")
      ->required();
  sub->add_option("--format", *format, "stable32 (Stable32 1.60 run tables) or csv (tidy)")
      ->check(CLI::IsMember({"stable32", "csv"}))
      ->capture_default_str();
  sub->add_option("-o,--output", *output, "File to write (default: standard output)");
  sub->add_option("--stats", *stats, "Only these statistics (comma-separated)");
  sub->add_option("--channels", opt->channels_glob,
                  "Only channels whose path or name matches this glob");
  return {sub, [=](const std::string&) {
            opt->inputs.assign(inputs->begin(), inputs->end());
            opt->format = *format == "stable32" ? ExportFormat::Stable32 : ExportFormat::Csv;
            opt->output = *output;
            std::stringstream ss(*stats);
            std::string s;
            while (std::getline(ss, s, ','))
              if (!s.empty()) opt->stats.push_back(s);
            return run_export(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
