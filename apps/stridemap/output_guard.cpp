#include "output_guard.hpp"

#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "stridemap/core/error.hpp"

namespace stridemap::cli {
namespace {

extern "C" void on_cleanup_signal(int signal_number) {
  stridemap::io::remove_temporaries_in_signal_handler();
  // Die of the signal, as the caller expects (exit status 128 + n).
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

bool inside_folder(const std::string& folder, const std::string& path) {
  std::error_code ec;
  const auto f = std::filesystem::weakly_canonical(folder, ec);
  if (ec) return false;
  const auto p = std::filesystem::weakly_canonical(path, ec);
  if (ec) return false;
  auto fi = f.begin();
  auto pi = p.begin();
  for (; fi != f.end(); ++fi, ++pi) {
    if (pi == p.end() || *fi != *pi) return false;
  }
  return true;
}

}  // namespace

void refuse_output_that_is_an_input(const std::string& option, const std::string& path,
                                    const std::vector<NamedPath>& inputs) {
  if (path.empty()) return;
  for (const NamedPath& input : inputs) {
    if (input.path.empty()) continue;
    if (io::same_file(path, input.path)) {
      throw InputError(option + ": '" + path + "' is the same file as " + input.option + " '" + input.path +
                       "'; writing it would destroy the input");
    }
    // An input in an output folder would be replaced if it has the name of
    // an output, and would sit among the outputs as if it were one: refused
    // even with --overwrite, whether the folder exists yet or not.
    if (input.path != path && inside_folder(path, input.path)) {
      throw InputError(option + ": folder '" + path + "' holds " + input.option + " '" + input.path +
                       "'; an output folder must not hold the run's inputs, so give another one");
    }
  }
}

void add_existing_log_flags(CLI::App& command, bool& overwrite, bool& append, const std::string& overwrite_help) {
  command.add_flag("--overwrite", overwrite, overwrite_help);
  command.add_flag("--append", append, "Add to an existing log (a new sensor block, then the scans)");
}

void add_output_folder_overwrite_flag(CLI::App& command, bool& overwrite, const std::string& folder_option) {
  command.add_flag("--overwrite", overwrite,
                   "Replace stridemap's earlier outputs in " + folder_option +
                       " even when the folder holds other files, which are kept (by default such a folder is refused)");
}

ExistingLog existing_log_choice(bool overwrite, bool append) {
  if (overwrite && append) throw InputError("--overwrite and --append exclude each other");
  return overwrite ? ExistingLog::overwrite : append ? ExistingLog::append : ExistingLog::refuse;
}

void check_log_output(const std::string& option, const std::string& path, ExistingLog choice,
                      const std::string& magic) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return;  // a new file
  if (S_ISDIR(info.st_mode)) throw InputError(option + ": '" + path + "' is a folder, not a log file");
  if (!S_ISREG(info.st_mode) || info.st_size == 0) return;  // a pipe, /dev/null, an empty file: nothing to lose
  if (choice == ExistingLog::refuse) {
    throw InputError(option + ": '" + path + "' exists (" + std::to_string(info.st_size) +
                     " bytes); pass --overwrite to replace it or --append to add to it");
  }
  if (choice == ExistingLog::append) {
    std::ifstream in(path, std::ios::binary);
    std::string first;
    std::getline(in, first);
    if (first.compare(0, magic.size(), magic) != 0) {
      throw InputError(option + ": '" + path + "' is not a " + magic + " file; --append would mix two formats");
    }
  }
}

void add_file_overwrite_flag(CLI::App& command, bool& overwrite, const std::string& what) {
  command.add_flag("--overwrite", overwrite, "Replace " + what + " if it exists (by default an existing file is refused)");
}

void refuse_existing_files(const std::vector<NamedPath>& outputs, bool overwrite) {
  std::vector<const NamedPath*> found;
  for (const NamedPath& output : outputs) {
    struct stat info {};
    if (output.path.empty() || ::stat(output.path.c_str(), &info) != 0) continue;
    if (S_ISDIR(info.st_mode)) throw InputError(output.option + ": '" + output.path + "' is a folder, not a file");
    if (S_ISREG(info.st_mode)) found.push_back(&output);
  }
  if (found.empty() || overwrite) return;
  const NamedPath& first = *found.front();
  std::string more = found.size() > 1 ? " (and " + std::to_string(found.size() - 1) + " more outputs)" : "";
  throw InputError(first.option + ": '" + first.path + "' already exists" + more +
                   "; choose another name or pass --overwrite");
}

void install_cleanup_signals() {
  struct sigaction action {};
  action.sa_handler = on_cleanup_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal_number, &action, nullptr);
  // Past the file size limit (ulimit -f) a write then fails with EFBIG, and
  // the writer names the file; by default the signal killed the process
  // with no word and left its temporaries.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGXFSZ, &ignore, nullptr);
}

}  // namespace stridemap::cli
