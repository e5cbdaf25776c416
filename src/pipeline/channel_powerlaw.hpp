// A clock channel's power-law model (docs/clocks.md): the levels h_alpha of white PM .. random-
// walk FM fitted to its OADEV and MDEV (kernels/powerlaw/fit.hpp) into the powerlaw/ record, the
// choice between it and eq. (3) (analyze --model), and the terminal table of the levels.
#pragma once

#include "io/results.hpp"
#include "kernels/allan/phase.hpp"

#include <string>
#include <string_view>

namespace allanlot::pipeline {

/// analyze --model: which noise model a channel gets. Auto: the power-law model for clock
/// channels (kernels::powerlaw::is_clock_channel), eq. (3) for the others.
enum class NoiseModel { Auto, Eq3, PowerLaw };

/// Parses "auto", "eq3", "powerlaw"; throws std::invalid_argument naming the text otherwise.
NoiseModel parse_noise_model(std::string_view text);

/// True when `channel` (its units and data type) gets the power-law model under `choice`.
bool uses_powerlaw(NoiseModel choice, const io::ChannelResult& channel);

/// The powerlaw/ record of a channel from its overlapping Allan deviation and the MDEV of
/// `result.stats` (computed here on the same taus when --stats left it out), both with their
/// edf. `confidence` is the level add_confidence gives the MDEV computed here.
io::PowerLawRecord powerlaw_channel(const io::ChannelResult& result,
                                    const kernels::PhaseData& phase,
                                    const kernels::StatResult& oadev, double confidence,
                                    int threads);

/// The levels of one clock channel as the terminal shows them: one row per noise type with its
/// name, h_alpha with sigma when detected, "< upper bound" when not.
std::string powerlaw_table(const std::string& device_id, const io::ChannelResult& ch);

}  // namespace allanlot::pipeline
