// The data-quality screen in the report (docs/reports.md "Data quality"): one line per channel on
// its unit's page, and the lot page's list of the channels with a flag raised.
#include "src/report/parts.hpp"

#include "src/report/svg.hpp"

#include <sstream>

namespace allanlot::report {

using svg::escape;
using svg::number;

namespace {

// "at 1234 (1.234 s)": where a finding starts, as a sample index and a time into the record.
std::string position(std::int64_t at, double rate_hz) {
  if (at < 0) return "";
  return " at sample " + std::to_string(at) + " (" +
         number(static_cast<double>(at) / std::max(rate_hz, 1e-300), 4) + " s)";
}

// One finding: its count, bold red when it raises a flag.
void finding(std::ostringstream& h, bool raised, const std::string& text) {
  h << "; " << (raised ? "<span class=\"bad\">" + text + "</span>" : text);
}

}  // namespace

std::string quality_line(const kernels::QualityReport& q, double rate_hz) {
  std::ostringstream h;
  h << "<p class=\"small quality\">Data quality: "
    << (q.flags.empty() ? std::string("<b>ok</b>")
                        : "<span class=\"bad\">" + escape(q.flags) + "</span>");
  finding(h, q.n_gap_runs > 0,
          std::to_string(q.n_missing) + " missing samples in " + std::to_string(q.n_gap_runs) +
              " gaps" + position(q.first_gap, rate_hz));
  if (q.n_duplicate_times + q.n_decreasing_times > 0)
    finding(h, true,
            std::to_string(q.n_duplicate_times) + " duplicate and " +
                std::to_string(q.n_decreasing_times) + " decreasing time stamps");
  finding(h, q.n_saturated_runs > 0,
          std::to_string(q.n_saturated_samples) + " saturated samples in " +
              std::to_string(q.n_saturated_runs) + " runs" + position(q.first_saturated, rate_hz));
  finding(h, q.n_stuck_runs > 0,
          "longest run of identical samples " + std::to_string(q.longest_run) + " (stuck from " +
              std::to_string(q.stuck_run) + "; " + std::to_string(q.n_stuck_runs) + " stuck" +
              position(q.first_stuck, rate_hz) + ")");
  finding(h, q.n_spikes > 0,
          std::to_string(q.n_spikes) + " spikes" + position(q.first_spike, rate_hz) +
              " (largest departure " + number(q.max_spike_sigmas, 3) + " robust sigmas)");
  h << "</p>\n";
  return h.str();
}

std::string quality_section(const std::vector<Unit>& units) {
  std::ostringstream rows;
  std::size_t screened = 0, flagged = 0;
  for (const Unit& u : units)
    for (const io::ChannelResult& ch : u.rec.channels) {
      if (!ch.quality) continue;
      ++screened;
      const kernels::QualityReport& q = *ch.quality;
      if (q.flags.empty()) continue;
      ++flagged;
      rows << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(u, ch.path)) << "\">"
           << escape(u.rec.device_id) << "</a></td><td class=\"l\">" << escape(ch.path)
           << "</td><td class=\"l bad\">" << escape(q.flags) << "</td><td>" << q.n_missing
           << "</td><td>" << q.n_gap_runs << "</td><td>"
           << q.n_duplicate_times + q.n_decreasing_times << "</td><td>" << q.n_saturated_samples
           << "</td><td>" << q.longest_run << " / " << q.stuck_run << "</td><td>" << q.n_spikes
           << "</td><td>" << number(q.max_spike_sigmas, 3) << "</td></tr>\n";
    }
  std::ostringstream h;
  h << "<h2 id=\"quality\">Data quality</h2>\n";
  if (screened == 0)
    return h.str() + "<p>No channel was screened (results of an older version).</p>\n";
  if (flagged == 0)
    return h.str() + "<p>No flag raised on the " + std::to_string(screened) +
           " channels screened.</p>\n";
  h << "<p>" << flagged << " of " << screened
    << " channels screened raise a flag (docs/quality.md):</p>\n<table><tr><th "
       "class=\"l\">unit</th><th class=\"l\">channel</th><th class=\"l\">flags</th><th>missing "
       "samples</th><th>gaps</th><th>time-stamp errors</th><th>saturated samples</th><th>longest "
       "run / stuck from</th><th>spikes</th><th>largest spike<br><span "
       "class=\"small\">robust &sigma;</span></th></tr>\n"
    << rows.str() << "</table>\n";
  return h.str();
}

}  // namespace allanlot::report
