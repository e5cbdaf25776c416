// The parts of the HTML report (src/report/report.hpp) its files share: the units of the lot
// and the lot summary's extra columns as read, names, anchors and colours (parts.cpp), the
// plots of a channel and of the lot (plots.cpp, distribution.cpp) and the two kinds of page
// (unit_page.cpp, lot_page.cpp). Internal to src/report/.
#pragma once

#include "io/report_data.hpp"
#include "io/results.hpp"
#include "kernels/model/fit.hpp"
#include "src/lot/masks.hpp"
#include "src/report/svg.hpp"

#include <array>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace allanlot::svg {
struct Plot;
}

namespace allanlot::report {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The eq. (3) terms with their Allan-deviation slope (the paper's Figure 1: mu of
// sigma(tau) ~ tau^mu) and a colour for their asymptote.
struct TermStyle {
  const char* name;
  const char* slope;  // as printed
  const char* color;
  const char* meaning;
};
inline constexpr std::array<TermStyle, 5> kTerms = {{
    {"R", "+1", "#e377c2", "rate ramp"},
    {"K", "+1/2", "#ff7f0e", "rate random walk"},
    {"B", "0", "#bcbd22", "bias instability (flicker)"},
    {"N",
     "\xE2\x88\x92"
     "1/2",
     "#17becf", "white rate noise (ARW/VRW)"},
    {"Q",
     "\xE2\x88\x92"
     "1",
     "#7f7f7f", "quantization"},
}};

// ---------------------------------------------------------------------------------------------
// Lot-summary columns added by other commands (spec_status, fits_agree), looked up by
// (device, channel). Absent columns leave every field empty: no colouring.

struct RowExtras {
  std::string spec;         // whole-row spec status: pass, fail, undecided, or ""
  std::string spec_detail;  // the terms that decided it, each with its limit (spec_detail)
  // The unit's verdict over all its channels (unit_spec_status, unit_spec_detail): the same on
  // every channel of the unit; the status is pass, fail, undecided or "" like `spec`.
  std::string unit_spec, unit_spec_detail;
  std::array<std::string, 5> term_spec;
  std::string agree;  // "yes", "no" or ""
};

using ExtrasMap = std::map<std::pair<std::string, std::string>, RowExtras>;

struct FailedInput {
  std::string device_id, source_file, status;
};

// The units of the lot.
struct Unit {
  std::filesystem::path file;
  io::RecordingResult rec;
  std::map<std::string, io::FitRecord> psd_fits;       // by channel path
  std::map<std::string, io::DiagnosisView> diagnoses;  // by channel path
  std::vector<std::string> notes;                      // what the extras could not read
  std::string anchor;                                  // id of its section
  std::string page;  // its own page, relative to the lot page ("" = in the lot page)
  // The ITU-T masks that `report --spec`'s rules apply to a channel, by channel path.
  std::map<std::string, std::vector<const masks::Mask*>> masks;
};

// The channels of one kind across the lot, and a unit the lot rule flags on a term.
struct Member {
  const Unit* unit;
  const io::ChannelResult* ch;
};

struct Outlier {
  const Unit* unit;
  std::string channel;
  std::size_t term;
  double value, ratio, z;
  std::string unit_ds;
};

// Names, ids and colours.

// An id or file name made of [A-Za-z0-9_-] only: device ids and channel paths come from the
// data, and must neither break the HTML nor lead a link outside the report's directory.
std::string sanitize(std::string_view s);
// The colour of statistic s (kernels/allan/stats.hpp StatInfo::color), the same on every plot.
std::string stat_color(const std::string& s);
int term_index(const std::string& name);
// "pass", "fail", "undecided" as the lot summary writes them, or "" (no colouring).
std::string spec_class(const std::string& v);
// The verdict cell of a channel: "fail: N 0.21±0.02 > 0.15 deg/sqrt(h)", the status and the
// terms behind it with their limits, escaped; "" without a spec status.
std::string spec_cell(const RowExtras& x);
// The same for a table cell: the status in bold, then each term with its limit kept on one
// line ("N 0.305±0.00065 > 0.3 deg/sqrt(h)"), lines breaking only between terms.
std::string spec_cell_terms(const RowExtras& x);
// The unit's verdict from any of its channels' extras, nullptr when the lot summary has none.
const RowExtras* unit_extras(const ExtrasMap& extras, const std::string& device_id);
// The spec and fits_agree columns of a lot summary by (device, channel), and its failed inputs.
void read_lot_extras(const io::SummaryColumns& c, ExtrasMap& map, std::vector<FailedInput>& failed);

std::string channel_anchor(const Unit& u, const std::string& channel);
// Links from the lot page.
std::string unit_href(const Unit& u);
std::string channel_href(const Unit& u, const std::string& channel);

// Numbers in tables: `digits` significant digits, without an exponent from 1 to a million.
std::string cell_number(double v, int digits);
std::string value_pm(double v, double s);
const io::TermRecord* find_term(const io::FitRecord& f, const std::string& name);
std::array<double, kernels::kNumTerms> theta_of(const io::FitRecord& f);
// Decade-snapped x range of a set of taus, shared by the asymptotes so that they span the
// whole plot.
std::pair<double, double> decade_range(const std::vector<double>& v);

// The units the plots of a channel are drawn in: those of the coefficient table, i.e. of B's
// datasheet form for a deviation of the rate (deg/h, mg; dimensionless for clocks) and of Q's
// for a time error (urad, m/s, s), converted by kernels/model/units.hpp, the one owner.
struct AxisUnits {
  double factor = 1;         // from the stored channel units
  std::string unit;          // "" when the channel has no units
  std::string text() const;  // as an axis prints it: "deg/h", "dimensionless", "no units given"
};
AxisUnits rate_axis_units(const std::string& channel_units);
AxisUnits time_error_axis_units(const std::string& channel_units);
// True when the channel is a clock's (units s or 1): its deviations are of the (dimensionless)
// fractional frequency.
bool is_clock(const std::string& channel_units);

// Plots of one channel (plots.cpp). A deviation panel: the Allan-family deviations of the
// rate (`time_error` false: OADEV, the eq. (3) fit and its terms; the other statistics behind
// boxes the reader ticks) or the time errors (TDEV; TTOTDEV, MTIE, TIE rms behind boxes), in
// the table's units; "" when the channel has no statistic of that kind.
std::string deviation_panel(const std::string& id, const io::ChannelResult& ch, bool time_error,
                            const std::vector<const masks::Mask*>& masks = {});
// The CSS that shows a statistic when its box is ticked, for every statistic.
std::string toggle_css();
std::string psd_plot(const std::string& id, const io::ChannelResult& ch,
                     const io::FitRecord* psd_fit);
// `clock`: titled "PSD cross-check" rather than by the paper's eq. (2) (docs/clocks.md).
std::string crosscheck_plot(const std::string& id, const io::CrosscheckRecord& c,
                            bool clock = false);
std::string diagnosis_plot(const std::string& id, const io::DiagnosisView& d,
                           const std::string& units);
// The spread of each detected term of one channel kind across the units, `outliers` in red
// (distribution.cpp).
// `title` names the channel's group; "" when no unit detects any term (nothing to plot).
std::string distribution_plot(const std::string& id, const std::string& title,
                              const std::string& channel, const std::vector<Member>& members,
                              const std::vector<Outlier>& outliers);

// The data-quality screen (quality.cpp): one line of a channel's findings, flagged ones in red,
// and the lot page's table of the channels that raise a flag.
std::string quality_line(const kernels::QualityReport& q, double rate_hz);
std::string quality_section(const std::vector<Unit>& units);

// The lot page's diagnoses (diagnoses.cpp): how many diagnosed channels are within noise, and
// whether the count beyond it exceeds what chance gives a lot of complete models; "" when no
// unit has a diagnosis.
std::string diagnoses_section(const std::vector<Unit>& units);

// Clocks (clock.cpp, docs/clocks.md "The clock report"): whether a channel is a clock's
// (kernels::powerlaw::is_clock_channel, the one rule), an alpha with its noise type's name
// ("0 (white FM)"), the table of the power-law levels, the power-law model and the detected
// levels' asymptotes on the Allan plot, the deviations against the model, and the lot page's
// table of each clock's levels.
bool is_clock_channel(const io::ChannelResult& ch);
std::string noise_type_label(int alpha);
std::string powerlaw_table_html(const io::ChannelResult& ch);
void add_powerlaw(svg::Plot& p, const io::ChannelResult& ch, double factor);
std::string powerlaw_residual_plot(const std::string& id, const io::ChannelResult& ch);
std::string clock_summary_table(const std::string& channel, const std::vector<Member>& members);

// A channel's data editing (editing.cpp): the drift removed with its residual plot, the edits
// and the dynamic Allan deviation's heat map; "" when the channel has none of them.
std::string editing_section(const std::string& id, const io::ChannelResult& ch);

// Clocks (clocks.cpp): a hat's results file (root `statistic` "hat") as a section of each
// clock's Allan deviation with its interval, plot and table ("" for any other file); and the
// ITU-T masks as dashed curves on a time-error plot, in the plot's units (`factor`).
std::string hat_section(const Unit& u);
void add_mask_series(svg::Plot& p, const std::vector<const masks::Mask*>& ms, double factor);
// Pages (unit_page.cpp, lot_page.cpp).
std::string html_head(const std::string& title);
std::string unit_section(const Unit& u, const ExtrasMap& extras, const std::string& lot_href);
std::string lot_section(const std::string& title, const std::vector<Unit>& units,
                        const ExtrasMap& extras, const std::vector<FailedInput>& failed_inputs,
                        const std::vector<std::string>& problems);

}  // namespace allanlot::report
