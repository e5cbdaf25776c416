#include "src/cli/hat.hpp"

#include "io/results.hpp"
#include "kernels/uncertainty/hat.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace allanlot::cli {
namespace {

constexpr const char* kPairs[3] = {"AB", "BC", "CA"};
constexpr const char* kClocks[3] = {"A", "B", "C"};

std::string cell(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, " %13.5g", v);
  return buf;
}

// The table on stdout: per tau, each clock's deviation and its interval [lo, hi] ("nan" where
// the estimate is negative and has none).
void print_table(std::ostream& out, const std::vector<PairedRecord>& rec,
                 const std::vector<std::string>& pair_names,
                 const std::vector<std::string>& clock_names,
                 const std::vector<kernels::StatResult>& clock) {
  for (std::size_t k = 0; k < rec.size(); ++k)
    out << pair_names[k] << " = " << rec[k].file << ":" << rec[k].channel.path << "\n";
  out << "          tau";
  const auto head = [](const std::string& t) {
    return " " + std::string(t.size() < 13 ? 13 - t.size() : 0, ' ') + t;
  };
  for (const std::string& c : clock_names)
    out << head("dev " + c) << head("lo") << head("hi");
  out << "\n";
  for (std::size_t i = 0; i < clock[0].size(); ++i) {
    out << cell(clock[0].tau_s[i]);
    for (const kernels::StatResult& c : clock)
      out << cell(c.dev[i]) << cell(c.dev_lo[i]) << cell(c.dev_hi[i]);
    out << "\n";
  }
}

// The three-cornered hat of AB BC CA (the form without --clocks): its file is unchanged.
void run_three(const PairedOptions& opt, std::ostream& out, std::ostream& err) {
  const std::vector<PairedRecord> rec = read_paired_records(opt);
  const auto ms = paired_m_list(opt, rec[0].phase.n_points());
  const kernels::HatResult h = kernels::three_cornered_hat(rec[0].phase, rec[1].phase, rec[2].phase,
                                                           ms, opt.confidence, opt.threads);
  io::RecordingResult r = paired_root(opt, rec, "hat");
  for (int k = 0; k < 3; ++k)
    r.channels.push_back(paired_channel(rec[static_cast<std::size_t>(k)],
                                        std::string("/pairs/") + kPairs[k], "oadev", h.pair[k]));
  for (int k = 0; k < 3; ++k) {
    // Clock k from the pairs it is in, less the pair it is not in (kernels/uncertainty/hat.hpp).
    io::ChannelResult ch =
        paired_channel(rec[0], std::string("/clocks/") + kClocks[k], "oadev", h.clock[k]);
    for (const PairedRecord& p : rec)
      ch.n_gaps = std::max(ch.n_gaps, p.phase.n_gaps);
    ch.notes = std::string("three-cornered hat: (") + kPairs[k] + " + " + kPairs[(k + 2) % 3] +
               " - " + kPairs[(k + 1) % 3] + ") / 2 of the pairs' overlapping Allan variances";
    if (!h.notes[k].empty()) ch.notes += "; " + h.notes[k];
    r.channels.push_back(std::move(ch));
  }
  io::write_results(opt.output, r);
  print_table(out, rec, {"AB", "BC", "CA"}, {"A", "B", "C"}, {h.clock[0], h.clock[1], h.clock[2]});
  for (const std::string& note : h.notes)
    if (!note.empty()) err << "allanlot: note: " << note << "\n";
  out << "wrote " << opt.output.string() << "\n";
}

// The N-cornered hat of --clocks (docs/cli.md "Command: hat"): the pairs in pair order.
void run_n(const PairedOptions& opt, const std::vector<std::string>& names, std::ostream& out,
           std::ostream& err) {
  const std::vector<PairedRecord> rec = read_paired_records(opt);
  const auto ms = paired_m_list(opt, rec[0].phase.n_points());
  std::vector<kernels::PhaseData> phases;
  for (const PairedRecord& p : rec)
    phases.push_back(p.phase);
  const std::size_t n = names.size();
  const kernels::NHatResult h = kernels::n_cornered_hat(phases, n, ms, opt.confidence, opt.threads);
  const std::vector<std::string> pairs = hat_pair_names(names);
  io::RecordingResult r = paired_root(opt, rec, "hat");
  std::string clocks_attr, pairs_attr;
  for (const std::string& c : names)
    clocks_attr += (clocks_attr.empty() ? "" : ",") + c;
  for (const std::string& p : pairs)
    pairs_attr += (pairs_attr.empty() ? "" : ",") + p;
  r.attributes.emplace_back("clocks", clocks_attr);
  r.attributes.emplace_back("pairs", pairs_attr);
  for (std::size_t p = 0; p < rec.size(); ++p)
    r.channels.push_back(paired_channel(rec[p], "/pairs/" + pairs[p], "oadev", h.pair[p]));
  for (std::size_t k = 0; k < n; ++k) {
    io::ChannelResult ch = paired_channel(rec[0], "/clocks/" + names[k], "oadev", h.clock[k]);
    for (const PairedRecord& p : rec)
      ch.n_gaps = std::max(ch.n_gaps, p.phase.n_gaps);
    ch.notes = std::to_string(n) +
               "-cornered hat: least-squares solution of the pairs' overlapping Allan variances "
               "(Gray & Allan)";
    if (!h.notes[k].empty()) ch.notes += "; " + h.notes[k];
    r.channels.push_back(std::move(ch));
  }
  io::write_results(opt.output, r);
  print_table(out, rec, pairs, names, h.clock);
  for (std::size_t k = 0; k < n; ++k)
    if (!h.notes[k].empty())
      err << "allanlot: note: clock " << names[k] << ": " << h.notes[k] << "\n";
  out << "wrote " << opt.output.string() << "\n";
}

struct HatArgs {
  PairedArgs paired;
  std::string clocks;  // --clocks A,B,C,D; "" = the three-cornered form AB BC CA
};

}  // namespace

std::vector<std::string> hat_clock_names(const std::string& list) {
  std::vector<std::string> names;
  std::stringstream ss(list);
  for (std::string name; std::getline(ss, name, ',');) {
    if (name.empty() ||
        name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                               "0123456789_.") != std::string::npos)
      throw CLI::ValidationError("--clocks", "'" + name +
                                                 "' is not a clock name (letters, digits, '_' "
                                                 "and '.', separated by commas)");
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw CLI::ValidationError("--clocks", "clock '" + name + "' named twice");
    names.push_back(name);
  }
  if (!list.empty() && list.back() == ',')
    throw CLI::ValidationError("--clocks", "an empty clock name at the end of '" + list + "'");
  if (names.size() < 3)
    throw CLI::ValidationError("--clocks", "the hat needs at least 3 clocks, got " +
                                               std::to_string(names.size()) + " ('" + list + "')");
  return names;
}

std::vector<std::string> hat_pair_names(const std::vector<std::string>& clocks) {
  const bool letters =
      std::all_of(clocks.begin(), clocks.end(), [](const std::string& c) { return c.size() == 1; });
  std::vector<std::string> pairs;
  for (std::size_t i = 0; i < clocks.size(); ++i)
    for (std::size_t j = i + 1; j < clocks.size(); ++j)
      pairs.push_back(clocks[i] + (letters ? "" : "-") + clocks[j]);
  return pairs;
}

int run_hat(const PairedOptions& opt, std::ostream& out, std::ostream& err) {
  return run_paired(opt, err, [&] { run_three(opt, out, err); });
}

int run_hat(const PairedOptions& opt, const std::vector<std::string>& clocks, std::ostream& out,
            std::ostream& err) {
  return run_paired(opt, err, [&] { run_n(opt, clocks, out, err); });
}

Command add_hat_command(CLI::App& app) {
  auto a = std::make_shared<HatArgs>();
  auto* sub = app.add_subcommand(
      "hat", "N-cornered hat: each clock's Allan deviation with its interval from the recordings "
             "of the clocks' pairwise differences (AB BC CA, or with --clocks every pair in "
             "pair order)");
  add_paired_options(sub, a->paired);
  sub->add_option("--clocks", a->clocks,
                  "Clock names A,B,C,D,...: N >= 3 clocks, whose N(N-1)/2 pair recordings follow "
                  "in pair order AB AC AD BC BD CD");
  return {sub, [a](const std::string& command_line) {
            if (a->clocks.empty())
              return run_hat(checked_paired_options(a->paired, command_line, 3, "hat"), std::cout,
                             std::cerr);
            const std::vector<std::string> names = hat_clock_names(a->clocks);
            const std::size_t pairs = names.size() * (names.size() - 1) / 2;
            return run_hat(
                checked_paired_options(a->paired, command_line, pairs, "hat --clocks " + a->clocks),
                names, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
