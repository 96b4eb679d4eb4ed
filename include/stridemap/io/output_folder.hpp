#pragma once
// A set of output files (a map, an experiment's results) that readers see
// whole or not at all. The files are written into a staging folder beside
// the target (`<parent>/.<name>.tmp-<pid>-<n>/`, same file system) and
// commit() fsyncs them, writes the manifest `.stridemap-output` last, fsyncs
// the folder and swaps it into place with one atomic rename (an exchange
// when the target exists; the previous set is then removed). Until then the
// previous set stays untouched: an exception, a stop signal or SIGKILL at any
// moment leaves either the old set or the new one (docs/outputs.md).
//
// The target holds stridemap's files only: those its manifest names. Any
// other entry is the user's and is never removed or replaced; it refuses
// the folder unless the caller chose OtherFiles::keep (`--overwrite`), and
// then the set moves in name by name beside it (not atomically as a whole).
//
// Leftovers of a killed run (a staging folder, or a previous set swapped out
// but not yet removed) carry the dead process's id in their name; the next
// OutputFolder for the same target removes them, and nothing reads them.
#include <string>
#include <vector>

namespace stridemap::io {

/// Name of the manifest in every output folder: it marks the folder as
/// stridemap's and lists the files of the set.
inline constexpr const char* kOutputManifest = ".stridemap-output";

/// What an output folder may hold besides the entries its manifest names.
enum class OtherFiles {
  refuse,  ///< the default: any other entry refuses the folder
  keep,    ///< `--overwrite`: stridemap's entries are replaced, the others stay as they are
};

/// Throws InputError unless `target` may receive an output set: it does not
/// exist, or every entry in it is named by its manifest (an empty folder
/// too). Anything else (a file or folder of the user's, the npy/ or map.ply
/// `export` wrote beside a run, any file of a folder without a manifest) is
/// refused with `refuse`, naming `option` and the first such entry by name,
/// and the option that keeps it (`--overwrite`) when `option` is one.
void check_output_folder(const std::string& target, const std::string& option,
                         OtherFiles other = OtherFiles::refuse);

class OutputFolder {
 public:
  /// Checks the target (check_output_folder), removes stale leftovers of
  /// killed runs and creates the staging folder. Throws InputError.
  OutputFolder(std::string target, std::string option, OtherFiles other = OtherFiles::refuse);
  /// Removes the staging folder unless commit() succeeded.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// The staging folder: write the set here.
  const std::string& path() const { return staging_; }
  /// path() + "/" + name.
  std::string file(const std::string& name) const;
  const std::string& target() const { return target_; }

  /// Makes the staged set the target (see above). Throws InputError naming
  /// the target; the staging folder is removed then and the previous set
  /// stays. With OtherFiles::keep, a file of the user's that has the name of
  /// one of the set's files refuses the commit (it is kept); a failure
  /// half-way through the name-by-name move leaves a manifest naming the old
  /// and the new files, which the next run replaces.
  void commit();

 private:
  void discard() noexcept;
  void finish(bool exchanged);
  void replace_in_place(const std::vector<std::string>& owned, const std::vector<std::string>& foreign,
                        const std::vector<std::string>& names);
  std::string target_;
  std::string option_;
  OtherFiles other_ = OtherFiles::refuse;
  std::string staging_;
  int registry_slot_ = -1;
  bool committed_ = false;
};

/// True when both paths exist and are the same file (device and inode):
/// an output must never be one of the run's inputs.
bool same_file(const std::string& a, const std::string& b);

/// True when `inner` is `outer` or lies below it, the parts that exist
/// resolved (symbolic links, "..") and the rest compared by name: two
/// folders a run writes must not nest, existing yet or not.
bool path_within(const std::string& inner, const std::string& outer);

/// For a handler of SIGINT, SIGTERM or SIGHUP that ends the process: removes
/// every temporary file and staging folder this process has open right now.
/// Async-signal-safe (system calls only).
void remove_temporaries_in_signal_handler() noexcept;

}  // namespace stridemap::io
