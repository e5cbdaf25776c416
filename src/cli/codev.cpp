#include "src/cli/codev.hpp"

#include "io/results.hpp"
#include "kernels/uncertainty/hat.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

namespace allanlot::cli {

int run_codev(const PairedOptions& opt, std::ostream& out, std::ostream& err) {
  return run_paired(opt, err, [&] {
    const std::vector<PairedRecord> rec = read_paired_records(opt);
    const auto ms = paired_m_list(opt, rec[0].phase.n_points());
    const kernels::CodevResult c = kernels::gcodev_with_confidence(rec[0].phase, rec[1].phase, ms,
                                                                   opt.confidence, opt.threads);
    io::RecordingResult r = paired_root(opt, rec, "gcodev");
    r.channels.push_back(paired_channel(rec[0], "/records/x", "oadev", c.oadev[0]));
    r.channels.push_back(paired_channel(rec[1], "/records/y", "oadev", c.oadev[1]));
    io::ChannelResult ch = paired_channel(rec[0], "/codev", "gcodev", c.codev);
    ch.n_gaps = std::max(rec[0].phase.n_gaps, rec[1].phase.n_gaps);
    ch.notes = "Groslambert codeviation of /records/x and /records/y: signed, "
               "sign(cov) sqrt(|cov|)";
    r.channels.push_back(std::move(ch));
    io::write_results(opt.output, r);
    out << "x = " << rec[0].file << ":" << rec[0].channel.path << "\ny = " << rec[1].file << ":"
        << rec[1].channel.path << "\n          tau        gcodev        dev_lo        dev_hi\n";
    for (std::size_t i = 0; i < c.codev.size(); ++i) {
      char line[80];
      std::snprintf(line, sizeof line, " %13.5g %13.5g %13.5g %13.5g\n", c.codev.tau_s[i],
                    c.codev.dev[i], c.codev.dev_lo[i], c.codev.dev_hi[i]);
      out << line;
    }
    out << "wrote " << opt.output.string() << "\n";
  });
}

Command add_codev_command(CLI::App& app) {
  auto a = std::make_shared<PairedArgs>();
  auto* sub = app.add_subcommand(
      "codev", "Groslambert codeviation of two recordings measured against the same reference");
  add_paired_options(sub, *a);
  return {sub, [a](const std::string& command_line) {
            return run_codev(checked_paired_options(*a, command_line, 2, "codev"), std::cout,
                             std::cerr);
          }};
}

}  // namespace allanlot::cli
