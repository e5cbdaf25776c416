// Reads the Stable32 tables of tests/data/stable32 (columns AF, Tau, #, Alpha,
// Min Sigma, Sigma, Max Sigma; '#' starts a header line) and plain one-column data files.
#pragma once

#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::test {

inline std::string reference_path(const std::string& rel) {
  return std::string(ALLANLOT_REFERENCE_DIR) + "/" + rel;
}

struct Stable32Row {
  std::int64_t m = 0;
  double tau = 0, min_sigma = 0, sigma = 0, max_sigma = 0;
  std::int64_t n = 0;
  int alpha = 0;
};

inline std::vector<Stable32Row> read_stable32(const std::string& rel) {
  std::ifstream in(reference_path(rel));
  if (!in) throw std::runtime_error("cannot open " + reference_path(rel));
  std::vector<Stable32Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    Stable32Row r;
    if (ss >> r.m >> r.tau >> r.n >> r.alpha >> r.min_sigma >> r.sigma >> r.max_sigma)
      rows.push_back(r);
  }
  return rows;
}

/// Every row of a Stable32 table, including those that the AllanTools test suite commented out
/// with a leading '#' (the files are kept as published; the rows are still Stable32's), and the
/// four-column tables of MTIE and TIE rms (AF, Tau, #, value: min_sigma = max_sigma = 0). The
/// "#" column is read as a number because Stable32 prints it as %.4e for Thêo1 (4.9550e+03).
inline std::vector<Stable32Row> read_stable32_every_row(const std::string& rel) {
  std::ifstream in(reference_path(rel));
  if (!in) throw std::runtime_error("cannot open " + reference_path(rel));
  std::vector<Stable32Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') line.erase(0, 1);
    std::istringstream ss(line);
    std::vector<double> v;
    std::string word;
    bool numeric = true;
    while (ss >> word) {
      try {
        std::size_t used = 0;
        v.push_back(std::stod(word, &used));
        numeric = numeric && used == word.size();
      } catch (const std::exception&) {
        numeric = false;
      }
    }
    if (!numeric || (v.size() != 4 && v.size() != 7)) continue;
    Stable32Row r;
    r.m = static_cast<std::int64_t>(v[0]);
    r.tau = v[1];
    r.n = static_cast<std::int64_t>(v[2] + 0.5);
    if (v.size() == 4) {
      r.sigma = v[3];
    } else {
      r.alpha = static_cast<int>(v[3]);
      r.min_sigma = v[4];
      r.sigma = v[5];
      r.max_sigma = v[6];
    }
    rows.push_back(r);
  }
  return rows;
}

/// One number per line; lines starting with '#' are skipped.
inline std::vector<double> read_column(const std::string& rel) {
  std::ifstream in(reference_path(rel));
  if (!in) throw std::runtime_error("cannot open " + reference_path(rel));
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    v.push_back(std::stod(line));
  }
  return v;
}

/// NBS14 data sets of NIST SP1065 pp. 107-108.
inline std::vector<double> nbs14_10_phase() {
  return {0.00000,  103.11111, 123.22222, 157.33333, 166.44444,
          48.55555, -96.33333, -2.22222,  111.88889, 0.00000};
}
inline std::vector<double> nbs14_10_freq() {
  return {892, 809, 823, 798, 671, 644, 883, 903, 677};
}

/// The 1000-point set: Lewis/Park-Miller LCG, y[i] = n[i] / 2147483647 from n[0] = 1234567890.
inline std::vector<double> nbs14_1000_freq() {
  std::vector<double> y(1000);
  std::uint64_t n = 1234567890;
  for (auto& v : y) {
    v = static_cast<double>(n) / 2147483647.0;
    n = (16807 * n) % 2147483647;
  }
  return y;
}

}  // namespace allanlot::test
