// What a path is, before allanlot reads or writes it (docs/reliability.md "Inputs and
// outputs"): whether two paths are one file, whether an output would replace an input, whether
// an input is a regular file (a FIFO would block open(2) for ever), and the clean-up of the
// temporary files that an interrupted run left behind.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

namespace allanlot::io {

/// True when both paths exist and are the same file (device and inode, symbolic links
/// followed): a hard link, a symbolic link or another spelling of one path.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

/// The first of `inputs` that writing `output` would replace, or nullopt. An output that does
/// not exist yet replaces nothing.
std::optional<std::filesystem::path> replaced_input(const std::filesystem::path& output,
                                                    std::span<const std::filesystem::path> inputs);

/// Empty when no output replaces an input or another output; otherwise the usage error's
/// message (every command's outputs go through this before any work: docs/reliability.md).
std::string outputs_conflict(std::span<const std::filesystem::path> outputs,
                             std::span<const std::filesystem::path> inputs);

/// The message of a usage error for an output that would replace an input.
std::string replaced_input_message(const std::filesystem::path& output,
                                   const std::filesystem::path& input);

/// Empty when `path` may be opened as an input file; otherwise why not ("not a regular file
/// (a FIFO)", "no such file", ...). Does not open it.
std::string input_file_problem(const std::filesystem::path& path);

/// Removes from `dir` the temporary files of io::AtomicFile's naming pattern
/// (`.<name>.tmp.<host>.<pid>.<random hex>`) that an earlier, interrupted run left: those last
/// modified before `before` whose writer is not a live process of this host. Returns how many.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir,
                                     std::filesystem::file_time_type before);

}  // namespace allanlot::io
