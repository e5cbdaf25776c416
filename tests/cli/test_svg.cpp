// The SVG plotting module (src/report/svg.hpp): ticks of log and linear axes, escaping, and the
// rendered element: well-formed XML, deterministic, hostile text escaped, unusable points
// skipped, ids unique per plot.
#include "src/report/svg.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace allanlot {
namespace {

// A minimal XML well-formedness check, enough for what render() emits: every element closed
// in order, attribute values quoted, no raw '<' or stray '&' in text or attributes. Returns
// "" when well-formed, else what is wrong and where.
std::string xml_problem(const std::string& s) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  const auto entity_ok = [&](std::size_t at) {
    const auto semi = s.find(';', at);
    if (semi == std::string::npos || semi - at > 8) return false;
    const std::string e = s.substr(at + 1, semi - at - 1);
    return e == "amp" || e == "lt" || e == "gt" || e == "quot" || e == "#39" ||
           (e.size() > 1 && e[0] == '#');
  };
  while (i < s.size()) {
    if (s[i] == '&' && !entity_ok(i)) return "stray & at " + std::to_string(i);
    if (s[i] != '<') {
      if (s[i] == '>') return "stray > at " + std::to_string(i);
      ++i;
      continue;
    }
    const bool closing = i + 1 < s.size() && s[i + 1] == '/';
    std::size_t j = i + (closing ? 2 : 1);
    std::string name;
    while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '-' ||
                            s[j] == ':' || s[j] == '_'))
      name += s[j++];
    if (name.empty()) return "bad tag at " + std::to_string(i);
    bool self_closing = false;
    while (j < s.size() && s[j] != '>') {
      if (s[j] == '"') {
        const auto end = s.find('"', j + 1);
        if (end == std::string::npos) return "unterminated attribute at " + std::to_string(j);
        for (std::size_t k = j + 1; k < end; ++k) {
          if (s[k] == '<') return "< in attribute at " + std::to_string(k);
          if (s[k] == '&' && !entity_ok(k)) return "stray & in attribute at " + std::to_string(k);
        }
        j = end + 1;
        continue;
      }
      if (s[j] == '/' && j + 1 < s.size() && s[j + 1] == '>') self_closing = true;
      ++j;
    }
    if (j >= s.size()) return "unterminated tag " + name;
    if (closing) {
      if (stack.empty() || stack.back() != name) return "mismatched </" + name + ">";
      stack.pop_back();
    } else if (!self_closing) {
      stack.push_back(name);
    }
    i = j + 1;
  }
  return stack.empty() ? "" : "unclosed <" + stack.back() + ">";
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1))
    ++n;
  return n;
}

svg::Plot allan_like_plot() {
  svg::Plot p;
  p.id = "u-1-imu_gyro_x-adev";
  p.title = "Allan deviation";
  p.x_label = "tau (s)";
  p.y_label = "sigma (deg/s)";
  svg::Series s;
  s.label = "oadev";
  s.dots = true;
  for (int k = 0; k < 40; ++k) {
    const double tau = std::pow(10.0, -3 + k * 0.15);
    s.x.push_back(tau);
    s.y.push_back(0.01 / std::sqrt(tau) + 1e-4);
    s.y_lo.push_back(s.y.back() * 0.9);
    s.y_hi.push_back(s.y.back() * 1.1);
  }
  p.series.push_back(s);
  svg::Series a;
  a.label = "N: slope -1/2";
  a.dash = "6 4";
  a.x = {1e-3, 1e3};
  a.y = {0.01 / std::sqrt(1e-3), 0.01 / std::sqrt(1e3)};
  p.series.push_back(a);
  p.annotations.push_back({1e-2, 0.1, "N (-1/2)"});
  return p;
}

TEST(Svg, EscapesTheXmlSpecialCharacters) {
  EXPECT_EQ(svg::escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(svg::escape(std::string("x\x01y")), "x?y");  // control characters are not XML
  EXPECT_EQ(svg::escape("deg/h/sqrt(Hz) \xC2\xB5"), "deg/h/sqrt(Hz) \xC2\xB5");  // UTF-8 kept
}

TEST(Svg, LogTicksAreDecadesWithMinorTicksBetween) {
  const auto t = svg::log_ticks(1e-3, 1e3);
  std::vector<std::string> major;
  int minor = 0;
  for (const auto& k : t)
    k.major ? major.push_back(k.label) : void(++minor);
  EXPECT_EQ(major,
            (std::vector<std::string>{"10^-3", "10^-2", "10^-1", "10^0", "10^1", "10^2", "10^3"}));
  EXPECT_EQ(minor, 6 * 8);  // 2..9 in each of the six decades
}

TEST(Svg, NarrowLogAxesLabelTwoAndFive) {
  std::vector<std::string> major;
  for (const auto& k : svg::log_ticks(0.4, 2.5))
    if (k.major) major.push_back(k.label);
  EXPECT_EQ(major, (std::vector<std::string>{"0.5", "1", "2"}));
  // Within one decade and far from 1: mantissa times a power of ten.
  major.clear();
  for (const auto& k : svg::log_ticks(2.2e-6, 4.5e-6))
    if (k.major) major.push_back(k.label);
  EXPECT_EQ(major, (std::vector<std::string>{"3\xC3\x97"
                                             "10^-6",
                                             "4\xC3\x97"
                                             "10^-6"}));
}

TEST(Svg, VeryWideLogAxesLabelEveryOtherDecade) {
  int labelled = 0;
  for (const auto& k : svg::log_ticks(1e-12, 1e2))
    labelled += k.major ? 1 : 0;
  EXPECT_EQ(labelled, 8);  // 1e-12, 1e-10, ..., 1e2
}

TEST(Svg, LinearTicksUseOneTwoFiveSteps) {
  std::vector<double> v;
  for (const auto& k : svg::linear_ticks(0.0, 1.0))
    v.push_back(k.value);
  EXPECT_EQ(v, (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0}));
}

TEST(Svg, RendersWellFormedDeterministicSvg) {
  const svg::Plot p = allan_like_plot();
  const std::string a = svg::render(p), b = svg::render(p);
  EXPECT_EQ(a, b);
  EXPECT_EQ(xml_problem(a), "") << a;
  EXPECT_EQ(a.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"u-1-imu_gyro_x-adev\"", 0), 0u);
  EXPECT_NE(a.find("viewBox=\"0 0 720 420\""), std::string::npos);
  EXPECT_NE(a.find("clip-path=\"url(#u-1-imu_gyro_x-adev-clip)\""), std::string::npos);
  EXPECT_NE(a.find("stroke-dasharray=\"6 4\""), std::string::npos);
  // Decade labels with a superscript exponent and a true minus sign.
  EXPECT_NE(a.find("10<tspan dy=\"-0.45em\" font-size=\"75%\">\xE2\x88\x92"
                   "3</tspan>"),
            std::string::npos);
  // Legend entries for both labelled series.
  EXPECT_NE(a.find(">oadev</text>"), std::string::npos);
  EXPECT_NE(a.find(">N: slope -1/2</text>"), std::string::npos);
  // Error bars: one vertical subpath and two caps per point.
  EXPECT_GE(count(a, "h4"), 80u);
  EXPECT_EQ(a.find("nan"), std::string::npos);
  EXPECT_EQ(a.find("inf"), std::string::npos);
}

TEST(Svg, EscapesHostileText) {
  svg::Plot p = allan_like_plot();
  p.title = "<script>alert(1)</script> & \"x\"";
  p.series[0].label = "</svg><b>";
  p.annotations[0].text = "a<b";
  p.x_label = "'&'";
  const std::string s = svg::render(p);
  EXPECT_EQ(xml_problem(s), "");
  EXPECT_EQ(s.find("<script"), std::string::npos);
  EXPECT_EQ(s.find("</svg><b>"), std::string::npos);
  EXPECT_NE(s.find("&lt;script&gt;"), std::string::npos);
}

TEST(Svg, SkipsPointsALogAxisCannotShowAndBreaksTheLine) {
  svg::Plot p;
  p.id = "gaps";
  svg::Series s;
  s.x = {1, 2, 3, 4, 5, 6};
  s.y = {1, 2, 0, 4, NAN, 6};  // zero and NaN cannot be on a log axis
  p.series.push_back(s);
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  // Three runs: {1,2}, {4}, {6}: three "M" moves in the series' path.
  const auto start = out.find("<path d=\"M", out.find("<g clip-path"));
  ASSERT_NE(start, std::string::npos);
  const auto end = out.find('"', start + 9);
  EXPECT_EQ(count(out.substr(start + 9, end - start - 9), "M"), 3u);
}

TEST(Svg, LinksAndCategories) {
  svg::Plot p;
  p.id = "dist";
  p.x_scale = svg::Scale::Categorical;
  p.categories = {"R\nn.d.", "N\n0.3"};
  svg::Series s;
  s.line = false;
  s.dots = true;
  s.x = {0.9, 1.1};
  s.y = {1.0, 5.0};
  s.hrefs = {"", "units/u 1.html#u-1"};
  s.tooltips = {"", "u<1> N"};
  p.series.push_back(s);
  p.boxes.push_back({1.0, 0.8, 1.0, 1.2, 0.7, 1.3});
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  EXPECT_NE(out.find("<a href=\"units/u 1.html#u-1\">"), std::string::npos);
  EXPECT_NE(out.find("<title>u&lt;1&gt; N</title>"), std::string::npos);
  EXPECT_NE(out.find(">n.d.</tspan>"), std::string::npos);  // second line of a category label
}

// A legend entry is the only key to its curve: the legend column widens to the longest
// entry (up to 40 % of the plot) and wraps a longer one at blanks, never cutting it.
TEST(Svg, LegendEntriesAreNeverCut) {
  svg::Plot p = allan_like_plot();
  p.series[1].label = "ratio (outside the valid range of the cross-check)";
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  EXPECT_EQ(out.find("\xE2\x80\xA6"), std::string::npos);  // no ellipsis
  const auto legend = out.substr(out.find("<g class=\"legend\""));
  for (const char* word : {"ratio", "(outside", "valid", "range", "cross-check)"})
    EXPECT_NE(legend.find(word), std::string::npos) << word;
  EXPECT_NE(legend.find("<tspan"), std::string::npos);  // wrapped onto a second line
  // The estimate errs wide: DejaVu Sans, the widest of the report's fonts, sets this text at
  // 11 px in 215.6 px (measured in Chromium).
  EXPECT_GE(svg::text_width("ratio (outside the valid range) N (\xE2\x88\x92"
                            "1/2)",
                            11),
            215.6);
}

// A label with `avoid` set is moved off the curve it names: here a flat line through its
// point, so the label's middle lies at least half its height above or below the line.
TEST(Svg, AvoidingLabelsLeaveTheCurve) {
  svg::Plot p;
  p.id = "flat";
  p.legend = false;
  svg::Series s;
  s.x = {1, 10, 100};
  s.y = {1, 1, 1};
  s.dots = true;
  p.series.push_back(s);
  svg::Annotation a;
  a.x = 10;
  a.y = 1;
  a.text = "B (0)";
  a.avoid = true;
  a.css_class = "slope";
  p.annotations.push_back(a);
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  const auto path = out.find("<path d=\"M", out.find("<g class=\"series"));
  const double line_y = std::stod(out.substr(out.find(' ', path + 10) + 1));
  const auto text = out.find("<text class=\"slope\" x=\"");
  ASSERT_NE(text, std::string::npos) << out;
  const double baseline = std::stod(out.substr(out.find("y=\"", text) + 3));
  EXPECT_GE(std::abs(baseline - 4 - line_y), 6.0) << out;
}

// Optional series (statistics the reader ticks on) and their legend entries carry their class
// and "opt", which the page hides until the box is ticked.
TEST(Svg, OptionalSeriesCarryTheirClasses) {
  svg::Plot p = allan_like_plot();
  p.series[0].css_class = "s-mdev";
  p.series[0].optional = true;
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  EXPECT_NE(out.find("<g class=\"series s-mdev opt\" data-label=\"oadev\">"), std::string::npos);
  EXPECT_NE(out.find("<g class=\"s-mdev opt\">"), std::string::npos);
}

TEST(Svg, RejectsInconsistentInput) {
  svg::Plot p;
  EXPECT_THROW(svg::render(p), std::invalid_argument);  // no id
  p.id = "x";
  svg::Series s;
  s.x = {1, 2};
  s.y = {1};
  p.series.push_back(s);
  EXPECT_THROW(svg::render(p), std::invalid_argument);
}

TEST(Svg, EmptyPlotStillRenders) {
  svg::Plot p;
  p.id = "empty";
  p.title = "nothing to show";
  const std::string out = svg::render(p);
  EXPECT_EQ(xml_problem(out), "");
  EXPECT_NE(out.find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace allanlot
