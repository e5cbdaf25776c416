// One allan/<stat>/ group read by its path, whatever its statistic's name: for the groups that
// read_results does not walk, such as /codev/allan/gcodev of `allanlot codev`'s results file
// (docs/formats.md "Results files of hat and codev"). The group is io/schema.hpp's stat_fields().
#pragma once

#include "kernels/allan/stat_result.hpp"

#include <filesystem>
#include <string>

namespace allanlot::io {

/// Reads the statistic group at `group` (e.g. "/codev/allan/gcodev") of a sealed results file.
/// Throws io::Error naming the file and the group when the file is damaged, the group is
/// missing or a dataset has the wrong type.
kernels::StatResult read_stat_group(const std::filesystem::path& path, const std::string& group);

}  // namespace allanlot::io
