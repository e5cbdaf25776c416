#include "src/cli/unit_tables.hpp"

#include "kernels/allan/stats.hpp"
#include "kernels/model/units.hpp"
#include "kernels/powerlaw/names.hpp"
#include "src/pipeline/channel_fit.hpp"
#include "src/pipeline/channel_powerlaw.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <vector>

namespace allanlot::cli {

namespace {

namespace units = kernels::units;

// More taus than this are thinned to one per octave: the table is read, not parsed (the
// results file has every tau).
constexpr std::size_t kMaxRows = 40;

std::string cell(const kernels::StatResult& s, std::size_t i) {
  char buf[80];
  const bool bounds = i < s.dev_lo.size() && i < s.dev_hi.size() && std::isfinite(s.dev_lo[i]) &&
                      std::isfinite(s.dev_hi[i]);
  if (bounds)
    std::snprintf(buf, sizeof buf, "%.3g [%.2g, %.2g]", s.dev[i], s.dev_lo[i], s.dev_hi[i]);
  else
    std::snprintf(buf, sizeof buf, "%.3g", s.dev[i]);
  return buf;
}

// The taus of the table: every tau of any statistic, thinned to one per octave when there are
// more than kMaxRows (the first tau kept, then each at least twice the last kept).
std::vector<double> table_taus(const io::ChannelResult& ch) {
  std::vector<double> taus;
  for (const auto& st : ch.stats)
    taus.insert(taus.end(), st.second.tau_s.begin(), st.second.tau_s.end());
  std::sort(taus.begin(), taus.end());
  taus.erase(std::unique(taus.begin(), taus.end()), taus.end());
  if (taus.size() <= kMaxRows) return taus;
  std::vector<double> kept;
  for (const double t : taus)
    if (kept.empty() || t >= 2.0 * kept.back()) kept.push_back(t);
  return kept;
}

// What the numbers are in: a clock's deviations are of fractional frequency (dimensionless)
// and its time errors in seconds (docs/formats.md "Input recordings"); other phase data keep
// the channel's rate units, and their time errors are those units times seconds.
std::string units_note(const io::ChannelResult& ch) {
  if (units::family_of(ch.units) == units::Family::Clock)
    return "deviations of fractional frequency (dimensionless); time errors in s";
  const std::string u = ch.units.empty() ? "the channel's units" : ch.units;
  return "deviations in " + u + "; time errors in " + u + "*s";
}

}  // namespace

bool is_clock_channel(const io::ChannelResult& ch) {
  return kernels::powerlaw::is_clock_channel(ch.units, ch.data_type);
}

std::string deviation_table(const std::string& device_id, const io::ChannelResult& ch) {
  if (ch.stats.empty()) return "";
  const std::vector<double> taus = table_taus(ch);
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"tau [s]"};
  double confidence = 0;
  for (const auto& [name, st] : ch.stats) {
    header.push_back(name);
    confidence = std::max(confidence, st.confidence);
  }
  rows.push_back(header);
  for (const double tau : taus) {
    char t[32];
    std::snprintf(t, sizeof t, "%.4g", tau);
    std::vector<std::string> row = {t};
    for (const auto& st : ch.stats) {
      const auto& tv = st.second.tau_s;
      const auto it = std::find(tv.begin(), tv.end(), tau);
      row.push_back(it == tv.end() ? "-"
                                   : cell(st.second, static_cast<std::size_t>(it - tv.begin())));
    }
    rows.push_back(row);
  }
  std::ostringstream out;
  out << device_id << ": " << ch.path << " (clock data, " << ch.data_type << ", units '" << ch.units
      << "'): deviations";
  if (confidence > 0) out << " [lo, hi] at " << 100 * confidence << " % confidence";
  out << "; " << units_note(ch) << "\n" << pipeline::aligned_rows(rows);
  return out.str();
}

std::string unit_tables(const io::RecordingResult& rec, bool si) {
  io::RecordingResult imu;
  imu.device_id = rec.device_id;
  imu.source_file = rec.source_file;
  std::vector<const io::ChannelResult*> clocks;
  std::vector<const io::ChannelResult*> levels;  // power-law levels of IMU channels (--model)
  for (const io::ChannelResult& ch : rec.channels) {
    const bool clock = is_clock_channel(ch);
    // eq. (3)'s table for IMU channels and for clocks analysed with --model eq3.
    if (!clock || ch.fit) imu.channels.push_back(ch);
    if (clock && ch.status.is_ok()) clocks.push_back(&ch);
    if (!clock && ch.powerlaw) levels.push_back(&ch);
  }
  std::string out = imu.channels.empty() ? "" : pipeline::fit_table(imu, si);
  for (const io::ChannelResult* ch : clocks)
    out += deviation_table(rec.device_id, *ch) + pipeline::powerlaw_table(rec.device_id, *ch);
  for (const io::ChannelResult* ch : levels)
    out += pipeline::powerlaw_table(rec.device_id, *ch);
  return out;
}

}  // namespace allanlot::cli
