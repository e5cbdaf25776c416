#include "src/cli/hat.hpp"

#include "io/results.hpp"
#include "kernels/uncertainty/hat.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

namespace allanlot::cli {
namespace {

constexpr const char* kPairs[3] = {"AB", "BC", "CA"};
constexpr const char* kClocks[3] = {"A", "B", "C"};

std::string cell(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, " %13.5g", v);
  return buf;
}

void print_table(std::ostream& out, const std::vector<PairedRecord>& rec,
                 const kernels::HatResult& h) {
  for (int k = 0; k < 3; ++k)
    out << kPairs[k] << " = " << rec[static_cast<std::size_t>(k)].file << ":"
        << rec[static_cast<std::size_t>(k)].channel.path << "\n";
  out << "          tau         dev A         dev B         dev C\n";
  for (std::size_t i = 0; i < h.clock[0].size(); ++i) {
    out << cell(h.clock[0].tau_s[i]);
    for (int k = 0; k < 3; ++k)
      out << cell(h.clock[k].dev[i]);
    out << "\n";
  }
}

}  // namespace

int run_hat(const PairedOptions& opt, std::ostream& out, std::ostream& err) {
  return run_paired(opt, err, [&] {
    const std::vector<PairedRecord> rec = read_paired_records(opt);
    const auto ms = paired_m_list(opt, rec[0].phase.n_points());
    const kernels::HatResult h = kernels::three_cornered_hat(
        rec[0].phase, rec[1].phase, rec[2].phase, ms, opt.confidence, opt.threads);
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
    print_table(out, rec, h);
    for (const std::string& note : h.notes)
      if (!note.empty()) err << "allanlot: note: " << note << "\n";
    out << "wrote " << opt.output.string() << "\n";
  });
}

Command add_hat_command(CLI::App& app) {
  auto a = std::make_shared<PairedArgs>();
  auto* sub = app.add_subcommand("hat", "Three-cornered hat: each clock's Allan deviation from the "
                                        "recordings of three pairwise differences AB BC CA");
  add_paired_options(sub, *a);
  return {sub, [a](const std::string& command_line) {
            return run_hat(checked_paired_options(*a, command_line, 3, "hat"), std::cout,
                           std::cerr);
          }};
}

}  // namespace allanlot::cli
