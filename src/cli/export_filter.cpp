#include "src/cli/export_filter.hpp"

#include "io/atomic_file.hpp"
#include "io/paths.hpp"
#include "io/results.hpp"
#include "kernels/model/terms.hpp"
#include "kernels/model/units.hpp"
#include "src/cli/cli.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace allanlot::cli {
namespace {

namespace fs = std::filesystem;
using kernels::Term;
using kernels::units::Family;

// One axis of one IMU: its channel and fit.
struct Axis {
  std::string path;
  std::string units;
  const io::FitRecord* fit = nullptr;
};

struct Imu {
  std::string device, group;  // the channels' group: a ROS topic, or e.g. /imu
  double rate_hz = 0;
  std::vector<Axis> gyro, accel;
};

std::string number(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", v);
  return s;
}

// The continuous-time SI unit of a term of a family (rad/s/sqrt(Hz) is rad/s*sqrt(s), ...).
const char* si_unit(Family f, Term t) {
  if (f == Family::Gyro) return t == Term::N ? "rad/s/sqrt(Hz)" : "rad/s/sqrt(s)";
  return t == Term::N ? "m/s^2/sqrt(Hz)" : "m/s^2/sqrt(s)";
}
const char* si_label(Family f, Term t) {
  if (f == Family::Gyro) return t == Term::N ? "rad/s/sqrt(Hz)" : "rad/s^2/sqrt(Hz)";
  return t == Term::N ? "m/s^2/sqrt(Hz)" : "m/s^3/sqrt(Hz)";
}

// The taus the fit used, "0.01 .. 300 s".
std::string taus_used(const io::FitRecord& fit) {
  const auto first = std::find_if(fit.tau.begin(), fit.tau.end(),
                                  [&](double t) { return t >= fit.first_tau_fitted * (1 - 1e-9); });
  if (first == fit.tau.end() || fit.taus_fitted <= 0) return "taus ?";
  const auto i = static_cast<std::size_t>(first - fit.tau.begin());
  const std::size_t last =
      std::min(fit.tau.size() - 1, i + static_cast<std::size_t>(fit.taus_fitted) - 1);
  return "taus " + number(*first) + " .. " + number(fit.tau[last]) + " s";
}

// One field: each axis's term in SI (its 95 % upper bound where the fit does not detect it),
// combined over the axes, and the comment that says how.
struct Field {
  double value = 0;
  std::string comment;
};

Field field(const std::vector<Axis>& axes, Family f, Term t, AxisCombine combine) {
  Field out;
  std::vector<std::string> bounded;
  double sum = 0;
  const char* name = t == Term::N ? "N" : "K";
  std::string each;
  for (const Axis& a : axes) {
    const auto term = std::find_if(a.fit->terms.begin(), a.fit->terms.end(),
                                   [&](const io::TermRecord& r) { return r.term == name; });
    if (term == a.fit->terms.end()) throw std::runtime_error(a.path + ": its fit has no " + name);
    const double to_si = 1.0 / kernels::units::from_datasheet(t, 1.0, si_unit(f, t), a.units);
    const double v = (term->detected ? term->value : term->upper) * to_si;
    if (!term->detected) bounded.push_back(a.path);
    each += (each.empty() ? "" : "; ") + a.path +
            (term->detected ? " " + number(v)
                            : " < " + number(v) + " (fit " + number(term->value * to_si) + ")") +
            " sigma " + number(term->sigma * to_si) + " (" + taus_used(*a.fit) + ")";
    out.value = std::max(out.value, v);
    sum += v;
  }
  if (combine == AxisCombine::Mean) out.value = sum / static_cast<double>(axes.size());
  out.comment = std::string(combine == AxisCombine::Max ? "largest" : "mean") + " of " + name +
                " [" + si_label(f, t) + "]: " + each;
  if (!bounded.empty()) {
    out.comment += "; not detected on";
    for (const std::string& p : bounded)
      out.comment += " " + p;
    out.comment += ": its 95 % upper bound";
  }
  return out;
}

// The IMUs the selected channels form: channels grouped by device and group, gyro and
// accelerometer axes told by their units.
std::map<std::string, Imu> imus(const std::vector<io::RecordingResult>& results,
                                const workflow::ChannelSelection& sel) {
  std::map<std::string, Imu> out;
  for (const io::RecordingResult& r : results)
    for (const io::ChannelResult& ch : r.channels) {
      if (!sel.selects(ch.path)) continue;
      const Family f = kernels::units::family_of(ch.units);
      if (f != Family::Gyro && f != Family::Accelerometer) continue;
      const std::string group = ch.path.substr(0, ch.path.find_last_of('/'));
      Imu& imu = out[r.device_id + ":" + (group.empty() ? "/" : group)];
      imu.device = r.device_id;
      imu.group = group.empty() ? "/" : group;
      imu.rate_hz = ch.sample_rate_hz;
      if (!ch.fit)
        throw std::runtime_error(r.device_id + " " + ch.path + ": no fit in its results");
      (f == Family::Gyro ? imu.gyro : imu.accel).push_back({ch.path, ch.units, &*ch.fit});
    }
  return out;
}

struct Numbers {
  Field acc_n, acc_w, gyr_n, gyr_w;
};

std::string yaml(FilterFormat format, const Imu& imu, const Numbers& n) {
  std::ostringstream y;
  const auto line = [&](const std::string& indent, const char* key, const Field& f) {
    y << indent << key << ": " << number(f.value) << "  # " << f.comment << "\n";
  };
  const std::string rate = number(imu.rate_hz);
  if (format == FilterFormat::Vins) {
    y << "%YAML:1.0\n# IMU noise of " << imu.device << " " << imu.group
      << ", continuous time (allanlot export --format vins)\n";
    y << "imu_topic: \"" << imu.group << "\"\n";
    line("", "acc_n", n.acc_n);
    line("", "gyr_n", n.gyr_n);
    line("", "acc_w", n.acc_w);
    line("", "gyr_w", n.gyr_w);
    return y.str();
  }
  std::string in;
  if (format == FilterFormat::OpenVins) {
    y << "%YAML:1.0\n";
    in = "  ";
  }
  y << "# IMU noise of " << imu.device << " " << imu.group
    << ", continuous time, SI units (allanlot export)\n";
  if (format == FilterFormat::OpenVins)
    y << "imu0:\n  T_i_b:\n    - [1.0, 0.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0, 0.0]\n"
         "    - [0.0, 0.0, 1.0, 0.0]\n    - [0.0, 0.0, 0.0, 1.0]\n";
  line(in, "accelerometer_noise_density", n.acc_n);
  line(in, "accelerometer_random_walk", n.acc_w);
  line(in, "gyroscope_noise_density", n.gyr_n);
  line(in, "gyroscope_random_walk", n.gyr_w);
  y << in << "rostopic: " << imu.group << "\n";
  if (format == FilterFormat::OpenVins) y << in << "time_offset: 0.0\n";
  y << in << "update_rate: " << rate << "\n";
  if (format == FilterFormat::OpenVins) y << in << "model: \"kalibr\"\n";
  return y.str();
}

}  // namespace

int run_filter_export(const FilterExport& opt, const std::vector<fs::path>& files,
                      std::ostream& out, std::ostream& err) {
  std::vector<io::RecordingResult> results;
  std::size_t unreadable = 0;
  for (const fs::path& f : files) {
    try {
      results.push_back(io::read_results(f));
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      ++unreadable;
    }
  }
  std::string text;
  try {
    const auto found = imus(results, opt.channels);
    std::vector<std::string> complete;
    for (const auto& [key, imu] : found)
      if (!imu.gyro.empty() && !imu.accel.empty()) complete.push_back(key);
    if (complete.size() != 1) {
      std::string names;
      for (const auto& k : complete)
        names += " " + k;
      throw std::runtime_error(
          complete.empty()
              ? "no IMU with both gyro (deg/s, rad/s) and accelerometer (m/s^2, g) "
                "channels among the selected channels"
              : std::to_string(complete.size()) + " IMUs (" + names.substr(1) +
                    "): select one with --channels, e.g. '" + found.at(complete[0]).group + "/*'");
    }
    const Imu& imu = found.at(complete[0]);
    const Numbers n{field(imu.accel, Family::Accelerometer, Term::N, opt.combine),
                    field(imu.accel, Family::Accelerometer, Term::K, opt.combine),
                    field(imu.gyro, Family::Gyro, Term::N, opt.combine),
                    field(imu.gyro, Family::Gyro, Term::K, opt.combine)};
    text = yaml(opt.format, imu, n);
  } catch (const std::exception& e) {
    err << "allanlot: usage error: " << e.what() << "\n";
    return kExitUsage;
  }
  if (opt.output.empty()) {
    out << text;
  } else {
    const std::vector<fs::path> planned{opt.output};
    if (const std::string clash = io::outputs_conflict(planned, files); !clash.empty()) {
      err << "allanlot: usage error: " << clash << "\n";
      return kExitUsage;
    }
    try {
      io::write_text_atomic(opt.output, text);
    } catch (const std::exception& e) {
      err << "allanlot: error: " << e.what() << "\n";
      return kExitUsage;
    }
  }
  return unreadable ? kExitSomeFailed : kExitOk;
}

}  // namespace allanlot::cli
