// Expands the INPUT arguments of `analyze` and `convert` (docs/cli.md "Command: analyze"):
// recordings (HDF5 or text), directories searched for recordings (*.h5, *.hdf5, *.csv, *.tsv,
// *.csv.gz, *.tsv.gz), and manifests named as such (`@FILE` or --manifest FILE, one path per
// line); and the channel selection of --channels and --exclude-channels.
#pragma once

#include "io/recording.hpp"
#include "src/workflow/input_args.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace allanlot::workflow {

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
/// OptionError naming that input (a usage error) suggesting `@`, since it is read as data
/// otherwise.
InputList expand_inputs(const std::vector<std::string>& inputs,
                        const std::filesystem::path& outdir = {});

/// io::channel_glob_matches, the one rule of channel globs (analyze, export, spec files).
bool channel_matches(const std::string& glob, const std::string& path);

/// Which channels a command analyses (docs/cli.md "Channel selection"): a channel is selected
/// when an include glob matches it (or none is given) and no exclude glob does.
class ChannelSelection {
public:
  ChannelSelection() = default;
  /// Each argument a comma-separated list of globs; a glob `!GLOB` among `include` excludes.
  /// Throws std::invalid_argument for an empty glob after '!'.
  ChannelSelection(const std::vector<std::string>& include,
                   const std::vector<std::string>& exclude);
  bool selects(const std::string& path) const;
  bool selects_all() const { return include_.empty() && exclude_.empty(); }
  /// The include globs that match none of `paths` (a recording's channels).
  std::vector<std::string> unmatched(const std::vector<std::string>& paths) const;
  /// The selection as one list, excludes after a '!': `gyro_*,accel_*,!*temp*` ("" for all).
  /// A single glob reads as it was given, so a resume stamp of earlier versions stays current.
  std::string text() const;

private:
  std::vector<std::string> include_, exclude_;
};

/// Why `selection` takes no channel of `info`: the selection and the channels it has.
std::string unselected_reason(const ChannelSelection& selection, const io::RecordingInfo& info);

/// A note on `notes` for each include glob of `selection` that matches no channel of the
/// recording `file` while others do (a recording without the accelerometers of its lot).
void note_unmatched(const std::string& file, const ChannelSelection& selection,
                    const io::RecordingInfo& info, std::ostream& notes);

/// Throws io::UsageError (exit status 2) when a text recording among `files` needs an option
/// that was not given, naming the file and the option. HDF5 files pass, and so does a file with
/// another problem: that is its own failure, reported when it is read.
void check_inputs_need(const std::vector<std::string>& files, const io::InputOptions& options);

}  // namespace allanlot::workflow
