#pragma once
// The rules every command follows before it writes (docs/outputs.md,
// "Overwriting"): an output is never one of the run's inputs (same device
// and inode), an existing log is never truncated unless asked, and a set of
// files appears whole or not at all. Commands check their outputs after
// reading their inputs and before any work that could be lost.
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "stridemap/io/output_folder.hpp"

namespace stridemap::cli {

/// An input of the run, for the same-file checks: the option and the path.
struct NamedPath {
  std::string option;
  std::string path;
};

/// Throws InputError when `path` (the value of `option`) is the same file
/// as one of `inputs`, or (for an output folder) holds one of them.
void refuse_output_that_is_an_input(const std::string& option, const std::string& path,
                                    const std::vector<NamedPath>& inputs);

/// What to do with a log file that exists already.
enum class ExistingLog { refuse, overwrite, append };

/// `--overwrite` and `--append` for a command that writes a log.
void add_existing_log_flags(CLI::App& command, bool& overwrite, bool& append,
                            const std::string& overwrite_help = "Replace an existing log (by default an existing log "
                                                                "is refused)");

/// `--overwrite` for a command that writes an output folder: the entries of
/// the folder's manifest are replaced and every other entry is kept
/// (io::OtherFiles); without it a folder holding anything else is refused.
void add_output_folder_overwrite_flag(CLI::App& command, bool& overwrite, const std::string& folder_option = "--out");
inline io::OtherFiles other_files(bool overwrite) {
  return overwrite ? io::OtherFiles::keep : io::OtherFiles::refuse;
}
/// Throws InputError for both flags at once.
ExistingLog existing_log_choice(bool overwrite, bool append);

/// Throws InputError (exit 2) when the log at `path` exists, is not empty
/// and `choice` is refuse; with append it must be a log of `magic` (the
/// start of its first line).
void check_log_output(const std::string& option, const std::string& path, ExistingLog choice,
                      const std::string& magic);

/// `--overwrite` for a command that writes single files of the user's naming.
void add_file_overwrite_flag(CLI::App& command, bool& overwrite, const std::string& what);

/// Throws InputError (exit 2) naming the first output that exists already
/// as a file or folder, unless `overwrite`. Devices and pipes (/dev/null, a
/// FIFO) are written straight through and never refused. Checked before
/// any work, so a refused run costs nothing.
void refuse_existing_files(const std::vector<NamedPath>& outputs, bool overwrite);

/// The set written by `write(folder)` replaces the previous set in the
/// folder `target` (io::OutputFolder).
template <typename Write>
void write_output_set(const std::string& target, const std::string& option, Write&& write,
                      io::OtherFiles other = io::OtherFiles::refuse) {
  io::OutputFolder staged(target, option, other);
  std::forward<Write>(write)(staged.path());
  staged.commit();
}

/// SIGINT, SIGTERM and SIGHUP end the process, after removing the
/// temporary files and staging folders it has open, so the previous
/// outputs stay as they were. For every command but record and live,
/// which stop their loop instead (install_stop_signals). SIGXFSZ is ignored,
/// so that a write past `ulimit -f` fails and is reported naming its file.
void install_cleanup_signals();

}  // namespace stridemap::cli
