#include "src/report/svg.hpp"
#include "src/report/svg_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <utility>
#include <vector>

namespace allanlot::svg {

double text_width(std::string_view text, double font_px) {
  // Advance widths in em, rounded up from DejaVu Sans (wider than Helvetica and Arial): narrow
  // glyphs, wide ones, capitals, and the rest; a multi-byte character (Greek, a minus sign, a
  // superscript) counts as a capital.
  double em = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c & 0xC0) == 0x80) continue;  // continuation byte of a UTF-8 character
    if (c >= 0x80)
      em += 0.8;
    else if (std::string_view(" .,:;'!|()[]ijlrtf/*").find(static_cast<char>(c)) !=
             std::string_view::npos)
      em += 0.42;
    else if (c == 'm' || c == 'w' || c == 'M' || c == 'W')
      em += 1.0;
    else if (c >= 'A' && c <= 'Z')
      em += 0.78;
    else
      em += 0.66;
  }
  return em * font_px;
}

namespace layout {
namespace {

// A label's box in viewBox px.
struct Box2 {
  double l, t, r, b;
  bool overlaps(const Box2& o) const { return l < o.r && o.l < r && t < o.b && o.t < b; }
};

// Whether the segment (x0, y0)-(x1, y1) meets `r` (Liang-Barsky clipping).
bool segment_hits(double x0, double y0, double x1, double y1, const Box2& r) {
  double t0 = 0, t1 = 1;
  const double dx = x1 - x0, dy = y1 - y0;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {x0 - r.l, r.r - x0, y0 - r.t, r.b - y0};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

// What labels keep clear of: the lines, error bars and dots of the non-optional series, as
// segments (a dot is the segment across its diameter, widened by the padding).
struct Obstacles {
  std::vector<std::array<double, 4>> segments;
  std::vector<Box2> boxes;  // dots and the labels placed so far
  int hits(const Box2& b) const {
    int n = 0;
    for (const auto& s : segments)
      n += segment_hits(s[0], s[1], s[2], s[3], b) ? 1 : 0;
    for (const Box2& o : boxes)
      n += o.overlaps(b) ? 1 : 0;
    return n;
  }
};

Obstacles obstacles_of(const Plot& p, const Frame& f) {
  Obstacles ob;
  for (const Series& s : p.series) {
    if (s.optional) continue;
    bool have_prev = false;
    double px = 0, py = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.ok_x(s.x[i]) || !f.ok_y(s.y[i])) {
        have_prev = false;
        continue;
      }
      const double x = f.X(s.x[i]), y = f.Y(s.y[i]);
      if (s.line && have_prev) ob.segments.push_back({px, py, x, y});
      if (s.dots) {
        const double r = s.dot_size / 2;
        ob.boxes.push_back({x - r, y - r, x + r, y + r});
      }
      if (!s.y_lo.empty() && f.ok_y(s.y_lo[i]) && f.ok_y(s.y_hi[i]))
        ob.segments.push_back({x, f.Y(s.y_lo[i]), x, f.Y(s.y_hi[i])});
      px = x;
      py = y;
      have_prev = true;
    }
  }
  return ob;
}

// The centre of a label of size w x h placed near (ax, ay): the nearest of a ring of
// candidates (below first: the asymptotes the labels name lie under the curves) that meets no
// obstacle and stays inside the plot area; failing that, the one that meets the fewest.
std::pair<double, double> place_label(double ax, double ay, double w, double h, const Frame& f,
                                      const Obstacles& ob) {
  static constexpr double kDirs[8][2] = {{0, 1},  {-0.7, 0.7}, {0.7, 0.7},   {0, -1},
                                         {-1, 0}, {1, 0},      {-0.7, -0.7}, {0.7, -0.7}};
  double best_x = ax, best_y = ay + 12;
  int best_hits = -1;
  for (const double r : {11.0, 16.0, 23.0, 32.0, 44.0, 58.0, 75.0, 95.0, 120.0, 150.0})
    for (const auto& d : kDirs) {
      const double cx = ax + d[0] * (r + (d[0] != 0 ? w / 2 : 0)), cy = ay + d[1] * r;
      const Box2 b{cx - w / 2 - 2, cy - h / 2 - 2, cx + w / 2 + 2, cy + h / 2 + 2};
      if (b.l < f.left || b.r > f.left + f.plot_w || b.t < f.top || b.b > f.top + f.plot_h)
        continue;
      const int n = ob.hits(b);
      if (n == 0) return {cx, cy};
      if (best_hits < 0 || n < best_hits) {
        best_hits = n;
        best_x = cx;
        best_y = cy;
      }
    }
  return {best_x, best_y};
}

}  // namespace

void draw_annotations(std::string& o, const Plot& p, const Frame& f) {
  // Annotations, clamped into the plot area so that a label is never lost off the edge.
  Obstacles ob;
  bool have_obstacles = false;
  for (const Annotation& a : p.annotations) {
    if (!f.ok_x(a.x) || !f.ok_y(a.y)) continue;
    const std::string cls =
        a.css_class.empty() ? std::string() : " class=\"" + escape(a.css_class) + "\"";
    const std::string text_attrs =
        "\" fill=\"" + escape(a.color) +
        "\" font-size=\"11\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\">";
    if (!a.avoid) {
      const double x = std::clamp(f.X(a.x) + a.dx, f.left + 2, f.left + f.plot_w - 2);
      const double y = std::clamp(f.Y(a.y) + a.dy, f.top + 12, f.top + f.plot_h - 4);
      o += "<text" + cls + " x=\"" + coord(x) + "\" y=\"" + coord(y) + "\" text-anchor=\"" +
           escape(a.anchor) + text_attrs + escape(a.text) + "</text>\n";
      continue;
    }
    if (!have_obstacles) {
      ob = obstacles_of(p, f);
      have_obstacles = true;
    }
    const double ax = f.X(a.x), ay = f.Y(a.y), w = text_width(a.text, 11), h = 12;
    const auto [cx, cy] = place_label(ax, ay, w, h, f, ob);
    ob.boxes.push_back({cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2});
    // A leader from the point to the label's edge when the label had to move away from it.
    const double vx = ax - cx, vy = ay - cy;
    if (std::hypot(vx, vy) > 20) {
      const double t = std::min(vx != 0 ? (w / 2 + 1) / std::abs(vx) : 1e9,
                                vy != 0 ? (h / 2 + 1) / std::abs(vy) : 1e9);
      o += "<path class=\"leader\" d=\"M" + coord(ax) + " " + coord(ay) + "L" + coord(cx + vx * t) +
           " " + coord(cy + vy * t) + "\" stroke=\"" + escape(a.color) +
           "\" stroke-width=\"0.8\" fill=\"none\"/>\n";
    }
    o += "<text" + cls + " x=\"" + coord(cx) + "\" y=\"" + coord(cy + 4) +
         "\" text-anchor=\"middle" + text_attrs + escape(a.text) + "</text>\n";
  }
}

}  // namespace layout
}  // namespace allanlot::svg
