#include "src/report/report.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/paths.hpp"
#include "io/report_data.hpp"
#include "io/results.hpp"
#include "src/lot/spec.hpp"
#include "src/report/parts.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <ostream>
#include <set>

namespace allanlot::report {
namespace {

namespace fs = std::filesystem;
using svg::escape;

bool is_results_file(const fs::path& p) {
  const std::string n = p.filename().string();
  return n.size() > 9 && n.compare(n.size() - 9, 9, ".allan.h5") == 0 && n[0] != '.';
}

// The unit a diagnose output belongs to: by the file's root device_id; else by the input
// recording diagnose names in its `source_file` attribute (the results record theirs too);
// else by the file name, "<device>.h5" or "<device>.<anything>.h5".
Unit* match_unit(std::vector<Unit>& units, const io::ReportExtras& x, const io::DiagnosisView& d,
                 const fs::path& file) {
  if (!x.device_id.empty()) {
    for (Unit& u : units)
      if (u.rec.device_id == x.device_id) return &u;
    return nullptr;
  }
  for (const auto& [k, v] : d.attributes) {
    if (k != "source_file" || v.empty()) continue;
    std::error_code ec;
    const fs::path src = fs::weakly_canonical(fs::path(v), ec);
    for (Unit& u : units) {
      std::error_code ec2;
      if (!ec && src == fs::weakly_canonical(fs::path(u.rec.source_file), ec2) && !ec2) return &u;
    }
    for (Unit& u : units)
      if (fs::path(v).filename() == fs::path(u.rec.source_file).filename()) return &u;
  }
  const std::string name = file.filename().string();
  for (Unit& u : units)
    if (name.rfind(u.rec.device_id + ".", 0) == 0) return &u;
  return nullptr;
}

void attach_diagnoses(std::vector<Unit>& units, const io::ReportExtras& x, const fs::path& file,
                      std::ostream& err, bool quiet, std::vector<std::string>& problems) {
  for (const auto& d : x.diagnoses) {
    Unit* u = match_unit(units, x, d, file);
    if (!u) {
      const std::string msg = file.string() + ":" + d.channel +
                              "/diagnosis: no unit of the lot matches (by device_id, "
                              "source_file or file name); not shown";
      problems.push_back(msg);
      if (!quiet) err << "allanlot: warning: " << msg << "\n";
      continue;
    }
    u->diagnoses[d.channel] = d;
    for (const auto& n : x.notes)
      u->notes.push_back(file.filename().string() + ": " + n);
  }
}

// The results files (sorted) and the other HDF5 files of OUTDIR, which may hold diagnoses.
// Prints a usage error and returns false when OUTDIR cannot be listed or has no results file.
bool list_outdir(const fs::path& outdir, std::vector<fs::path>& files,
                 std::vector<fs::path>& others, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(outdir, ec)) {
    err << "allanlot: usage error: " << outdir.string() << ": not a directory\n";
    return false;
  }
  for (const auto& e : fs::directory_iterator(outdir, ec)) {
    if (!e.is_regular_file()) continue;
    if (is_results_file(e.path()))
      files.push_back(e.path());
    else if (e.path().extension() == ".h5" && e.path().filename() != "lot_summary.h5" &&
             e.path().filename().string()[0] != '.')
      others.push_back(e.path());
  }
  if (ec) {
    err << "allanlot: usage error: " << outdir.string() << ": " << ec.message() << "\n";
    return false;
  }
  std::sort(files.begin(), files.end());
  std::sort(others.begin(), others.end());
  if (files.empty()) {
    err << "allanlot: usage error: " << outdir.string()
        << ": no results files (*.allan.h5); run 'allanlot analyze -o " << outdir.string()
        << " ...' first\n";
    return false;
  }
  return true;
}

// The units of the readable results files, with their PSD fits, diagnoses and notes, and
// anchors that are unique, deterministic (sorted file order) and made of safe characters. An
// unreadable results file is a problem named on `err`.
std::vector<Unit> read_units(const std::vector<fs::path>& files, std::vector<std::string>& problems,
                             std::ostream& err) {
  std::vector<Unit> units;
  for (const fs::path& f : files) {
    Unit u;
    u.file = f;
    try {
      u.rec = io::read_results(f);
    } catch (const std::exception& e) {
      problems.push_back(std::string(e.what()));
      err << "allanlot: error: " << e.what() << "\n";
      continue;
    }
    try {
      io::ReportExtras x = io::report_extras(u.rec);
      for (auto& [chan, fit] : x.psd_fits)
        u.psd_fits[chan] = std::move(fit);
      for (auto& d : x.diagnoses)
        u.diagnoses[d.channel] = std::move(d);
      u.notes = std::move(x.notes);
    } catch (const std::exception& e) {
      u.notes.push_back(e.what());
    }
    units.push_back(std::move(u));
  }
  std::set<std::string> used;
  for (Unit& u : units) {
    std::string a = "u-" + sanitize(u.rec.device_id);
    for (int k = 2; used.count(a); ++k)
      a = "u-" + sanitize(u.rec.device_id) + "-" + std::to_string(k);
    used.insert(a);
    u.anchor = a;
  }
  return units;
}

// Attaches the diagnoses of `others` (stray files of OUTDIR, which need not be readable: they
// may be recordings kept beside the results) and of --diagnosis (which must be). Returns false
// after a usage error on `err`.
bool read_diagnoses(std::vector<Unit>& units, const std::vector<fs::path>& others,
                    const ReportOptions& opt, std::vector<std::string>& problems,
                    std::ostream& err) {
  std::vector<fs::path> diag_files = others;
  diag_files.insert(diag_files.end(), opt.diagnosis_files.begin(), opt.diagnosis_files.end());
  for (const fs::path& f : diag_files) {
    try {
      attach_diagnoses(units, io::read_report_extras(f), f, err, opt.quiet, problems);
    } catch (const std::exception& e) {
      const bool explicit_file = std::find(opt.diagnosis_files.begin(), opt.diagnosis_files.end(),
                                           f) != opt.diagnosis_files.end();
      if (explicit_file) {
        err << "allanlot: usage error: --diagnosis " << e.what() << "\n";
        return false;
      }
    }
  }
  return true;
}

// Per-unit pages in <stem>_units/ (names unique and safe) when the options or the lot's size
// ask for them; returns that directory's name, or "" for one page.
std::string assign_unit_pages(std::vector<Unit>& units, const ReportOptions& opt,
                              const fs::path& output) {
  const bool split = opt.unit_pages == UnitPages::Always ||
                     (opt.unit_pages == UnitPages::Auto &&
                      units.size() > static_cast<std::size_t>(kSinglePageMaxUnits));
  if (!split) return "";
  const std::string pages_dir = sanitize(output.stem().string()) + "_units";
  std::set<std::string> names;
  for (Unit& u : units) {
    std::string n = sanitize(u.rec.device_id);
    for (int k = 2; names.count(n); ++k)
      n = sanitize(u.rec.device_id) + "-" + std::to_string(k);
    names.insert(n);
    u.page = pages_dir + "/" + n + ".html";
  }
  return pages_dir;
}

// Writes the unit pages (when `pages_dir` is not empty) and the lot page; throws on a write
// failure.
void write_pages(const std::vector<Unit>& units, const ExtrasMap& extras,
                 const std::vector<FailedInput>& failed_inputs,
                 const std::vector<std::string>& problems, const std::string& title,
                 const fs::path& output, const std::string& pages_dir) {
  if (!pages_dir.empty()) {
    const fs::path dir = output.parent_path() / pages_dir;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw io::Error(dir.string(), "", "cannot create directory: " + ec.message());
    const std::string back = "../" + output.filename().string();
    for (const Unit& u : units) {
      std::string page = html_head("allanlot: " + u.rec.device_id);
      page += "<p class=\"small\"><a href=\"" + escape(back) + "#lot\">&larr; " + escape(title) +
              "</a></p>\n";
      page += unit_section(u, extras, back + "#lot");
      page += "</body>\n</html>\n";
      io::write_text_atomic(output.parent_path() / u.page, page);
    }
  }
  std::string html = html_head(title);
  html += lot_section(title, units, extras, failed_inputs, problems);
  if (pages_dir.empty())
    for (const Unit& u : units)
      html += unit_section(u, extras, "#lot");
  html += "</body>\n</html>\n";
  io::write_text_atomic(output, html);
}

}  // namespace

Outcome run_report(const ReportOptions& opt, std::ostream& out, std::ostream& err) {
  std::vector<fs::path> files, others;
  if (!list_outdir(opt.outdir, files, others, err)) return Outcome::UsageError;
  // The report never replaces what it reads: a results file, a lot summary, a diagnosis.
  std::vector<fs::path> read = files;
  read.insert(read.end(), others.begin(), others.end());
  read.insert(read.end(), opt.diagnosis_files.begin(), opt.diagnosis_files.end());
  for (const char* name : {"lot_summary.h5", "lot_summary.csv", "lot_statistics.csv"})
    read.push_back(opt.outdir / name);
  const std::vector<fs::path> outputs = {opt.output.empty() ? opt.outdir / "report.html"
                                                            : opt.output};
  if (const std::string clash = io::outputs_conflict(outputs, read); !clash.empty()) {
    err << "allanlot: usage error: " << clash << "\n";
    return Outcome::UsageError;
  }
  std::vector<std::string> problems;
  std::vector<Unit> units = read_units(files, problems, err);
  if (units.empty()) {
    err << "allanlot: error: no results file in " << opt.outdir.string() << " could be read\n";
    return Outcome::UsageError;
  }
  const bool some_unreadable = !problems.empty();
  if (!read_diagnoses(units, others, opt, problems, err)) return Outcome::UsageError;

  if (!opt.spec_path.empty()) {
    // The spec's masks per channel, drawn on its time-error plot (clocks.cpp).
    try {
      const spec::Spec sp = spec::load_spec(opt.spec_path);
      for (Unit& u : units)
        for (const io::ChannelResult& ch : u.rec.channels)
          if (const spec::Rule* rule = spec::find_rule(sp, ch.path))
            for (const spec::MaskLimit& l : rule->masks)
              if (const masks::Mask* m = masks::find_mask(l.mask, l.stat))
                u.masks[ch.path].push_back(m);
    } catch (const spec::Error& e) {
      err << "allanlot: usage error: --spec " << e.what() << "\n";
      return Outcome::UsageError;
    }
  }

  ExtrasMap extras;
  std::vector<FailedInput> failed_inputs;
  const fs::path summary = opt.outdir / "lot_summary.h5";
  std::error_code ec;
  if (fs::exists(summary, ec)) {
    try {
      read_lot_extras(io::read_summary_columns(summary), extras, failed_inputs);
    } catch (const std::exception& e) {
      problems.push_back(std::string("lot summary not used: ") + e.what());
    }
  }

  const fs::path output = opt.output.empty() ? opt.outdir / "report.html" : opt.output;
  const std::string pages_dir = assign_unit_pages(units, opt, output);
  const std::string title =
      "allanlot report: " + fs::absolute(opt.outdir).lexically_normal().filename().string();
  try {
    write_pages(units, extras, failed_inputs, problems, title, output, pages_dir);
    if (!opt.quiet)
      out << "report: " << output.string() << " (" << units.size() << " units"
          << (pages_dir.empty() ? ""
                                : ", unit pages in " + (output.parent_path() / pages_dir).string())
          << ")\n";
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return Outcome::UsageError;
  }
  return some_unreadable ? Outcome::WrittenSomeUnreadable : Outcome::Written;
}

}  // namespace allanlot::report
