// The lot page's diagnoses (docs/reports.md "Diagnoses"): each diagnosed channel's verdict, and
// whether the lot's count of channels beyond noise exceeds what chance gives when every
// corrected model is complete (kernels/diagnose/lot_noise.hpp): a complete model is beyond the
// p95 a channel is judged by 5 % of the time (from 19 replicas up), so in a lot of hundreds of
// channels some always are.
#include "src/report/parts.hpp"

#include "kernels/diagnose/diagnose.hpp"
#include "kernels/diagnose/lot_noise.hpp"
#include "src/report/svg.hpp"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace allanlot::report {

using svg::escape;
using svg::number;

std::string diagnoses_section(const std::vector<Unit>& units) {
  std::size_t diagnosed = 0, within = 0, unjudged = 0;
  int replicas = 0;  // of the first channel judged (all of them where the chances are equal)
  std::vector<double> chance;  // of each judged channel beyond its p95, were its model complete
  std::ostringstream rows;
  for (const Unit& u : units)
    for (const auto& [channel, d] : u.diagnoses) {
      ++diagnosed;
      const double p = kernels::beyond_p95_probability(d.replicas);
      if (d.within_noise < 0 || !(p >= 0.0)) {
        ++unjudged;
        continue;
      }
      chance.push_back(p);
      if (replicas == 0) replicas = d.replicas;
      if (d.within_noise == 1) {
        ++within;
        continue;
      }
      rows << "<tr><td class=\"l\"><a href=\"" << escape(channel_href(u, channel)) << "\">"
           << escape(u.rec.device_id) << "</a></td><td class=\"l\">" << escape(channel)
           << "</td><td>" << number(d.gap_after, 3) << "</td><td>" << number(d.gap_noise_p95, 3)
           << "</td><td>" << d.replicas << "</td></tr>\n";
    }
  if (diagnosed == 0) return "";
  std::ostringstream h;
  h << "<h2>Diagnoses</h2>\n<p>" << diagnosed << " channels diagnosed";
  if (!chance.empty()) {
    const auto beyond = static_cast<int>(chance.size() - within);
    double expected = 0.0;
    for (const double p : chance)
      expected += p;
    const auto [lo, hi] = std::minmax_element(chance.begin(), chance.end());
    const double tail = kernels::at_least_probability(chance, beyond);
    h << ": " << within << " within statistical noise (the gap below the "
      << number(kernels::kGapNoiseQuantile * 100.0, 3) << " % quantile of the "
      << "corrected model's replicas' gaps), " << beyond << " beyond. Were every model complete, "
      << "a channel would be beyond with probability " << number(*lo, 2)
      << (*hi > *lo ? " to " + number(*hi, 2) + " (by its number of replicas)"
                    : " (its quantile from " + std::to_string(replicas) + " replicas)")
      << ": " << number(expected, 2) << " expected";
    if (beyond > 0)
      h << ", " << beyond << " or more with probability " << number(tail, 2) << ". "
        << (tail < 0.05 ? "<span class=\"bad\">More than chance gives a lot of complete models: "
                          "the channels below miss what their diagnoses did not name.</span>"
                        : "No more than chance gives a lot of complete models.");
    else
      h << ".";
  }
  h << "</p>\n";
  if (unjudged > 0)
    h << "<p class=\"small\">" << unjudged << " diagnoses have no verdict to count (written "
      << "without replicas, or by an earlier allanlot that did not record the verdict).</p>\n";
  if (within < chance.size())
    h << "<table><tr><th class=\"l\">unit</th><th class=\"l\">channel</th><th>gap after</th>"
         "<th>replicas' p95</th><th>replicas</th></tr>\n"
      << rows.str() << "</table>\n";
  return h.str();
}

}  // namespace allanlot::report
