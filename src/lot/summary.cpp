#include "src/lot/summary.hpp"

#include "src/lot/spec.hpp"
#include "src/lot/statistics.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <stdexcept>
#include <system_error>

namespace allanlot::lot {

namespace fs = std::filesystem;

namespace {

// Keys under which a path is "the same file": the absolute path lexically normalized, and the
// path with symlinks resolved. Two keys because the results record fs::absolute of what
// analyze was given, while a manifest may reach the same file by another route.
std::vector<std::string> path_keys(const fs::path& p) {
  std::error_code ec;
  const fs::path abs = fs::absolute(p, ec);
  std::vector<std::string> keys{(ec ? p : abs).lexically_normal().string()};
  const fs::path canon = fs::weakly_canonical(ec ? p : abs, ec);
  if (!ec) keys.push_back(canon.string());
  return keys;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// One line per verdict of the units (spec::judge_units), the first kShown named with their
// channels; the column unit_spec_detail of lot_summary.csv has them all.
void print_unit_verdicts(const LotOverview& ov, std::size_t shown, std::ostream& out) {
  out << "  units: " << ov.units_pass << " pass, " << ov.units_fail.size() << " fail, "
      << ov.units_undecided.size() << " undecided";
  if (!ov.units_other.empty()) out << ", " << ov.units_other.size() << " no spec or no data";
  out << "\n";
  const std::pair<const char*, const std::vector<std::string>*> lists[] = {
      {"fail", &ov.units_fail}, {"undecided", &ov.units_undecided}};
  for (const auto& [name, list] : lists) {
    if (list->empty()) continue;
    out << "  units " << name << ":";
    for (std::size_t i = 0; i < std::min(shown, list->size()); ++i)
      out << (i ? "; " : " ") << (*list)[i];
    if (list->size() > shown) out << "; ... (column unit_spec_detail of lot_summary.csv)";
    out << "\n";
  }
}

// The per-unit verdicts into the overview: one per device_id, from its first row.
void count_units(const std::vector<io::SummaryRow>& rows, LotOverview& ov) {
  std::set<std::string> seen;
  for (const io::SummaryRow& r : rows) {
    if (r.unit_spec_status.empty() || !seen.insert(r.device_id).second) continue;
    const std::string named = r.device_id + " (" + r.unit_spec_detail + ")";
    if (r.unit_spec_status == "pass")
      ++ov.units_pass;
    else if (r.unit_spec_status == "fail")
      ov.units_fail.push_back(named);
    else if (r.unit_spec_status == "undecided")
      ov.units_undecided.push_back(named);
    else
      ov.units_other.push_back(r.device_id + " (" + r.unit_spec_status + ")");
  }
}

void print_overview(const LotOverview& ov, const spec::Spec* sp, std::ostream& out) {
  out << "lot: " << ov.n_units << " unit(s), " << ov.n_rows - ov.n_failed_inputs << " channel(s)";
  if (ov.n_failed_channels) out << ", " << ov.n_failed_channels << " failed";
  if (ov.n_failed_inputs) out << "; " << ov.n_failed_inputs << " input(s) without results";
  if (ov.n_missing) out << " (" << ov.n_missing << " from the manifest)";
  out << "\n";
  if (sp) {
    out << "spec " << sp->source << (sp->name.empty() ? "" : " (" + sp->name + ")")
        << " at confidence " << sp->confidence << ":\n";
    for (const KindCounts& k : ov.kinds) {
      out << "  " << k.channel << ":";
      const std::pair<const char*, std::size_t> counts[] = {{"pass", k.pass},
                                                            {"fail", k.fail},
                                                            {"undecided", k.undecided},
                                                            {"no spec", k.no_spec},
                                                            {"no data", k.no_data}};
      const char* sep = " ";
      for (const auto& [name, n] : counts)
        if (n) {
          out << sep << n << ' ' << name;
          sep = ", ";
        }
      out << "\n";
    }
  }
  // A lot of thousands can have dozens of outliers; the CSV has them all.
  constexpr std::size_t kShown = 8;
  if (sp) print_unit_verdicts(ov, kShown, out);
  if (!ov.quality.empty()) {
    out << "quality flags (" << ov.quality.size() << "):";
    for (std::size_t i = 0; i < std::min(kShown, ov.quality.size()); ++i)
      out << (i ? "; " : " ") << ov.quality[i];
    if (ov.quality.size() > kShown)
      out << "; ... (column quality of lot_summary.csv lists them all)";
    out << "\n";
  }
  if (ov.outliers.empty()) return;
  out << "outliers (" << ov.outliers.size() << "):";
  for (std::size_t i = 0; i < std::min(kShown, ov.outliers.size()); ++i)
    out << (i ? "; " : " ") << ov.outliers[i];
  if (ov.outliers.size() > kShown)
    out << "; ... (column outlier of lot_summary.csv lists them all)";
  out << "\n";
}

// The results file of each (device_id, source_file) in OUTDIR, where the spec's masks read the
// MTIE and TDEV curves (spec::judge_masks); read only when a rule holds a mask, since it opens
// every results file a second time.
std::map<std::pair<std::string, std::string>, std::string>
mask_results_files(const spec::Spec& sp, const fs::path& outdir) {
  std::map<std::pair<std::string, std::string>, std::string> out;
  if (std::none_of(sp.rules.begin(), sp.rules.end(),
                   [](const spec::Rule& r) { return !r.masks.empty(); }))
    return out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(outdir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".") || !name.ends_with(".allan.h5")) continue;
    try {
      for (const io::SummaryRow& r : io::summary_rows(io::read_summary_results(e.path())))
        out.emplace(std::make_pair(r.device_id, r.source_file), e.path().string());
    } catch (const std::exception&) {
      // An unreadable file is already a failed row of rows_from_outdir.
    }
  }
  return out;
}

// The spec's verdict of every row and of every unit. A rule unit that does not fit a matched
// channel (known only once the channels are seen) is an error; all of them are collected, one
// per rule, term and channel units (not one per unit of the lot), and thrown together, as
// parse_spec reports a file's errors.
void apply_spec(const spec::Spec& sp, std::vector<io::SummaryRow>& rows, const fs::path& outdir,
                bool quiet, std::ostream& err) {
  std::vector<bool> used(sp.rules.size(), false);
  std::vector<std::string> problems;
  std::set<std::string> seen;
  const std::map<std::pair<std::string, std::string>, std::string> files =
      mask_results_files(sp, outdir);
  for (io::SummaryRow& r : rows) {
    try {
      const auto file = files.find({r.device_id, r.source_file});
      const spec::Verdict v = spec::judge(sp, r, file == files.end() ? "" : file->second);
      r.spec_status = v.status;
      r.spec_detail = v.detail;
      r.spec_term_status = v.term_status;
    } catch (const spec::Error& e) {
      // "<file>: <key>.unit: '<unit>' is not a unit of N for a '<units>' channel (<unit:chan>...":
      // the text before " (" names the rule, the term and the channel units.
      for (const std::string& m : e.messages())
        if (seen.insert(m.substr(0, m.find(" ("))).second) problems.push_back(m);
    }
    if (const spec::Rule* rule = r.channel.empty() ? nullptr : spec::find_rule(sp, r.channel))
      used[static_cast<std::size_t>(rule - sp.rules.data())] = true;
  }
  if (!problems.empty()) throw spec::combined_error(sp.source, std::move(problems));
  for (std::size_t i = 0; i < used.size(); ++i)
    if (!used[i] && !quiet)
      err << "allanlot: warning: " << sp.source << ": channels." << sp.rules[i].glob
          << ": matches no channel of the lot\n";
  spec::judge_units(rows);
}

}  // namespace

std::vector<io::SummaryRow> rows_from_outdir(const fs::path& outdir, std::ostream& err,
                                             std::size_t* unreadable) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(outdir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".") || !name.ends_with(".allan.h5")) continue;
    files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<io::SummaryRow> rows;
  for (const fs::path& f : files) {
    try {
      for (auto& r : io::summary_rows(io::read_summary_results(f)))
        rows.push_back(std::move(r));
    } catch (const std::exception& e) {
      // A damaged file is named and listed as a failed row (the morning's reader sees the
      // unit), never trusted and never a crash (io/seal.hpp); analyze redoes it.
      err << "allanlot: error: unreadable results file: " << e.what() << "\n";
      std::string device = f.filename().string();
      device.erase(device.size() - std::string(".allan.h5").size());
      rows.push_back(
          {device, "", "", 0,
           io::ChannelStatus::failed("unreadable results file: " + std::string(e.what())),
           f.string()});
      if (unreadable) ++*unreadable;
    }
  }
  return rows;
}

std::vector<io::SummaryRow> manifest_failures(const fs::path& manifest,
                                              const std::vector<io::SummaryRow>& rows) {
  std::ifstream in(manifest);
  if (!in) throw std::runtime_error(manifest.string() + ": cannot open the manifest");
  // Every row counts as "present", failed ones too: an input this run already reported as
  // failed must not be listed a second time.
  std::set<std::string> present;
  for (const io::SummaryRow& r : rows)
    if (!r.source_file.empty())
      for (auto& k : path_keys(r.source_file))
        present.insert(std::move(k));
  const fs::path base = manifest.parent_path();
  std::vector<io::SummaryRow> out;
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const fs::path p(line);
    const fs::path entry = p.is_absolute() || base.empty() ? p : base / p;
    const auto keys = path_keys(entry);
    if (std::any_of(keys.begin(), keys.end(), [&](const auto& k) { return present.contains(k); }))
      continue;
    for (const auto& k : keys)
      present.insert(k);  // a line given twice is listed once
    out.push_back({entry.stem().string(), "", "", 0, io::ChannelStatus::failed("no results file"),
                   keys.front()});
  }
  if (in.bad()) throw std::runtime_error(manifest.string() + ": cannot read the manifest");
  return out;
}

LotOverview write_lot(const fs::path& outdir, std::vector<io::SummaryRow> rows,
                      const LotOptions& opt, std::ostream& out, std::ostream& err) {
  std::optional<spec::Spec> loaded;
  if (!opt.spec && !opt.spec_path.empty()) loaded = spec::load_spec(opt.spec_path);
  const spec::Spec* sp = opt.spec ? opt.spec : loaded ? &*loaded : nullptr;
  LotOverview ov;
  if (!opt.manifest.empty()) {
    auto missing = manifest_failures(opt.manifest, rows);
    ov.n_missing = missing.size();
    rows.insert(rows.end(), std::make_move_iterator(missing.begin()),
                std::make_move_iterator(missing.end()));
  }
  if (sp) apply_spec(*sp, rows, outdir, opt.quiet, err);
  const std::vector<io::StatisticsRow> stats = lot_statistics(rows);
  std::vector<std::pair<std::string, std::string>> attrs;
  if (sp) {
    std::error_code ec;
    const fs::path abs = fs::absolute(opt.spec_path, ec);
    attrs = {{"spec_file", (ec ? opt.spec_path : abs).string()},
             {"spec_name", sp->name},
             {"spec_confidence", std::to_string(sp->confidence)}};
  }
  io::write_lot_summary(outdir, rows, stats, attrs);

  ov.spec = sp != nullptr;
  ov.n_rows = rows.size();
  std::set<std::string> units;
  std::map<std::string, KindCounts> kinds;
  for (const io::SummaryRow& r : rows) {
    units.insert(r.device_id);
    if (r.channel.empty()) {
      ++ov.n_failed_inputs;
      continue;
    }
    if (!r.status.is_ok()) ++ov.n_failed_channels;
    KindCounts& k = kinds[r.channel];
    k.channel = r.channel;
    const std::string& s = r.spec_status;
    if (sp)
      ++(s == "pass"        ? k.pass
         : s == "fail"      ? k.fail
         : s == "undecided" ? k.undecided
         : s == "no spec"   ? k.no_spec
                            : k.no_data);
    if (!r.quality.empty() && r.quality != "ok")
      ov.quality.push_back(r.device_id + ":" + r.channel + " (" + r.quality + ")");
    if (r.outlier) {
      ++k.outliers;
      ov.outliers.push_back(r.device_id + ":" + r.channel + " (" + r.outlier_terms + ")");
    }
  }
  ov.n_units = units.size();
  for (auto& [path, k] : kinds)
    ov.kinds.push_back(std::move(k));
  count_units(rows, ov);
  if (!opt.quiet) print_overview(ov, sp, out);
  return ov;
}

}  // namespace allanlot::lot
