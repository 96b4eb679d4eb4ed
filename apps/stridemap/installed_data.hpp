#pragma once
// The scenes and configurations shipped with stridemap (scenes/, configs/)
// are found where the tool runs from the source folder, and otherwise where
// `cmake --install` put them: <prefix>/share/stridemap, located relative to
// the executable (<prefix>/bin/../share/stridemap) so that a relocated
// prefix still works.
#include <string>
#include <vector>

namespace stridemap::cli {

/// Where a shipped file named by its relative path ("scenes/x.yaml") is
/// looked for, in order: the current folder, then the install prefix's
/// share/stridemap beside the executable.
std::vector<std::string> data_search_paths(const std::string& relative_path);

/// `path` as given when it is not `default_path` (the user chose a file: it
/// is used as is) or when it exists; otherwise the first existing
/// data_search_paths() entry. Throws InputError naming `option` and every
/// place looked in when the default is nowhere.
std::string resolve_default_data_file(const std::string& option, const std::string& path,
                                      const std::string& default_path);

}  // namespace stridemap::cli
