// Expands the INPUT arguments of `analyze` and `convert` (docs/cli.md "Command: analyze"):
// recordings (HDF5 or text), directories searched for *.h5 / *.hdf5, and manifests named as
// such (`@FILE` or --manifest FILE, one path per line).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace allanlot::cli {

struct InputList {
  std::vector<std::string> files;  // recordings to analyse, in order, without duplicates
  /// Inputs that could not be expanded: (what was given, reason).
  std::vector<std::pair<std::string, std::string>> failures;
};

/// Directories are searched recursively (sorted; hidden entries, `outdir` and results files
/// skipped; links to directories followed once); manifest lines are trimmed, blank lines and
/// lines starting with '#' are skipped, and relative paths are taken relative to the
/// manifest's directory. A path given twice is analysed once. Anything but a regular file (a
/// FIFO, a device) is a failure, never opened (docs/reliability.md "Inputs and outputs").
/// An input `@FILE` is a manifest; a .txt input whose lines all name existing files throws
/// CLI::ValidationError (a usage error) suggesting `@`, since it is read as data otherwise.
InputList expand_inputs(const std::vector<std::string>& inputs,
                        const std::filesystem::path& outdir = {});

/// The --channels rule, shared by analyze, export and spec files: an empty glob selects every
/// channel; otherwise the glob (fnmatch) must match the channel's path (`/imu/gyro_x`) or its
/// name (`gyro_x`).
bool channel_matches(const std::string& glob, const std::string& path);

}  // namespace allanlot::cli
