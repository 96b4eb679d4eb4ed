#include "stridemap/io/output_folder.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <system_error>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/io/detail/errno_text.hpp"
#include "temporary_registry.hpp"

namespace stridemap::io {
namespace {

namespace fs = std::filesystem;


// A target given with a trailing slash ("map/") names the same folder.
std::string without_trailing_slashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

std::string parent_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string name_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string staging_prefix(const std::string& target) {
  std::string prefix(1, '.');
  prefix += name_of(target);
  prefix += ".tmp-";
  return prefix;
}

// What a target folder holds: the entries its manifest names (stridemap's,
// replaceable) and everything else (the user's, never touched). A folder
// without a manifest holds nothing of stridemap's: an extension says nothing
// about who wrote a file (a results.csv or settings.json of the user's).
struct FolderListing {
  bool has_manifest = false;
  std::vector<std::string> owned;    // sorted
  std::vector<std::string> foreign;  // sorted
};

std::set<std::string> manifest_names(const std::string& path, const std::string& option) {
  std::ifstream in(path);
  if (!in) throw InputError(option + ": cannot read the manifest '" + path + "': " + detail::errno_text(errno));
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') names.insert(line);
  }
  if (in.bad()) throw InputError(option + ": cannot read the manifest '" + path + "'");
  return names;
}

FolderListing list_folder(const std::string& target, const std::string& raw_target, const std::string& option) {
  FolderListing listing;
  const std::string manifest = target + "/" + kOutputManifest;
  struct stat info {};
  listing.has_manifest = ::lstat(manifest.c_str(), &info) == 0 && S_ISREG(info.st_mode);
  const std::set<std::string> listed =
      listing.has_manifest ? manifest_names(manifest, option) : std::set<std::string>{};
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(target, ec)) {
    std::string name = entry.path().filename().string();
    if (listing.has_manifest && name == kOutputManifest) continue;
    // Only names present in the folder count: a manifest edited by hand
    // cannot make this tool remove anything outside it.
    (listed.count(name) != 0 ? listing.owned : listing.foreign).push_back(std::move(name));
  }
  if (ec) throw InputError(option + ": cannot list folder '" + raw_target + "': " + ec.message());
  std::sort(listing.owned.begin(), listing.owned.end());
  std::sort(listing.foreign.begin(), listing.foreign.end());
  return listing;
}

std::string foreign_entry_refusal(const std::string& raw_target, const std::string& option, const std::string& name,
                                  bool has_manifest) {
  std::string text = option + ": folder '" + raw_target + "' holds '" + name +
                     "', which stridemap did not write there (" +
                     (has_manifest ? std::string("it is not in the folder's ") + kOutputManifest
                                   : std::string("the folder has no ") + kOutputManifest) +
                     "); ";
  // Command-line options take --overwrite; other callers (the Python
  // binding) only have the choice of another folder.
  if (option.rfind("--", 0) == 0) {
    text += "pass --overwrite to replace only stridemap's own files there and keep the others, or give a new or "
            "empty folder";
  } else {
    text += "give a new or empty folder";
  }
  return text;
}

struct TargetState {
  bool exists = false;
  FolderListing listing;
};

TargetState inspect_target(const std::string& raw_target, const std::string& option) {
  const std::string target = without_trailing_slashes(raw_target);
  if (target.empty()) throw InputError(option + ": the output folder is empty");
  const std::string name = name_of(target);
  if (name == "." || name == ".." || target == "/") {
    throw InputError(option + ": '" + raw_target + "' cannot be replaced as a whole; name a folder of its own");
  }
  struct stat info {};
  if (::lstat(target.c_str(), &info) != 0) {
    if (errno == ENOENT) return {};  // created by commit(); a parent that cannot be made is found when staging
    throw InputError(raw_target + ": cannot create the output folder: " + detail::errno_text(errno));
  }
  if (!S_ISDIR(info.st_mode)) {
    throw InputError(raw_target + ": cannot create the output folder: it exists and is not a folder");
  }
  return {true, list_folder(target, raw_target, option)};
}

void write_small_file(const std::string& path, const std::string& text) {
  std::FILE* out = std::fopen(path.c_str(), "wb");
  if (out == nullptr) throw InputError("cannot write " + path + ": " + detail::errno_text(errno));
  const bool written = std::fwrite(text.data(), 1, text.size(), out) == text.size();
  const bool flushed = std::fflush(out) == 0 && ::fsync(::fileno(out)) == 0;
  const int error = errno;
  const bool closed = std::fclose(out) == 0;
  if (!written || !flushed || !closed) throw InputError("cannot write " + path + ": " + detail::errno_text(error));
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  struct stat first {}, second {};
  if (a.empty() || b.empty() || ::stat(a.c_str(), &first) != 0 || ::stat(b.c_str(), &second) != 0) return false;
  return first.st_dev == second.st_dev && first.st_ino == second.st_ino;
}

bool path_within(const std::string& inner, const std::string& outer) {
  if (inner.empty() || outer.empty()) return false;
  std::error_code ec;
  const std::filesystem::path a = std::filesystem::weakly_canonical(std::filesystem::absolute(inner, ec), ec);
  if (ec) return false;
  const std::filesystem::path b = std::filesystem::weakly_canonical(std::filesystem::absolute(outer, ec), ec);
  if (ec) return false;
  auto i = a.begin(), j = b.begin();
  for (; j != b.end(); ++i, ++j) {
    if (j->empty()) continue;  // the empty last part of a path ending in '/'
    if (i == a.end() || *i != *j) return false;
  }
  return true;
}

void check_output_folder(const std::string& raw_target, const std::string& option, OtherFiles other) {
  const TargetState state = inspect_target(raw_target, option);
  if (other == OtherFiles::refuse && !state.listing.foreign.empty()) {
    throw InputError(foreign_entry_refusal(raw_target, option, state.listing.foreign.front(), state.listing.has_manifest));
  }
}

OutputFolder::OutputFolder(std::string target, std::string option, OtherFiles other)
    : target_(without_trailing_slashes(std::move(target))), option_(std::move(option)), other_(other) {
  check_output_folder(target_, option_, other_);
  const std::string parent = parent_of(target_);
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw InputError(parent + ": cannot create the output folder: " + ec.message());
  detail::remove_stale_temporaries(parent, staging_prefix(target_));
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string candidate = parent + "/" + staging_prefix(target_) + std::to_string(::getpid()) + "-" +
                            std::to_string(counter.fetch_add(1));
    if (::mkdir(candidate.c_str(), 0777) == 0) {
      staging_ = std::move(candidate);
      registry_slot_ = detail::register_temporary(staging_, true);
      return;
    }
    if (errno != EEXIST) {
      throw InputError(target_ + ": cannot create the output folder (staging beside it): " + detail::errno_text(errno));
    }
  }
  throw InputError(option_ + ": no free staging folder name beside '" + target_ + "'");
}

OutputFolder::~OutputFolder() {
  if (!committed_) discard();
}

std::string OutputFolder::file(const std::string& name) const { return staging_ + "/" + name; }

void OutputFolder::commit() {
  const auto fail = [&](const std::string& what) {
    discard();
    throw InputError(target_ + ": cannot put the outputs in place: " + what);
  };
  // The manifest comes last: a folder holding it holds every file it names.
  std::string manifest = "# stridemap output set: every file below was written completely before this list\n";
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(staging_, ec)) names.push_back(entry.path().filename().string());
  if (ec) fail(ec.message());
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    if (const int error = detail::sync_path(file(name)); error != 0) fail("fsync " + name + ": " + detail::errno_text(error));
    manifest += name + "\n";
  }
  try {
    write_small_file(file(kOutputManifest), manifest);
  } catch (const InputError& e) {
    fail(std::string("cannot write the manifest: ") + e.what());
  }
  if (const int error = detail::sync_path(staging_); error != 0) fail("fsync: " + detail::errno_text(error));

  // The same checks as at the start: the folder may have changed since.
  TargetState state;
  try {
    state = inspect_target(target_, option_);
  } catch (const InputError& e) {
    fail(e.what());
  }
  if (!state.exists) {
    if (::rename(staging_.c_str(), target_.c_str()) != 0) fail(detail::errno_text(errno));
    finish(false);
    return;
  }
  if (!state.listing.foreign.empty()) {
    if (other_ == OtherFiles::refuse) {
      discard();
      throw InputError(foreign_entry_refusal(target_, option_, state.listing.foreign.front(),
                                             state.listing.has_manifest) +
                       "; nothing was written");
    }
    replace_in_place(state.listing.owned, state.listing.foreign, names);
    return;
  }
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
    fail(detail::errno_text(errno));
  }
  finish(true);
}

void OutputFolder::finish(bool exchanged) {
  committed_ = true;
  (void)detail::sync_path(parent_of(target_));
  // After an exchange the staging name holds the previous set: remove it. A
  // kill now leaves it for the next run to remove; readers never see it.
  bool remove = exchanged;
  if (exchanged) {
    // Whatever reached the old folder after the last check is not ours: it
    // goes back beside the new set, and the old set stays if it cannot.
    try {
      const FolderListing previous = list_folder(staging_, staging_, option_);
      for (const std::string& name : previous.foreign) {
        const std::string to = target_ + "/" + name;
        struct stat info {};
        if (::lstat(to.c_str(), &info) == 0 || ::rename((staging_ + "/" + name).c_str(), to.c_str()) != 0) {
          remove = false;
        }
      }
    } catch (const InputError&) {
      remove = false;
    }
  }
  if (remove) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
  detail::release_temporary(registry_slot_);
  registry_slot_ = -1;
}

void OutputFolder::replace_in_place(const std::vector<std::string>& owned, const std::vector<std::string>& foreign,
                                    const std::vector<std::string>& names) {
  const auto fail = [&](const std::string& what) {
    discard();
    throw InputError(target_ + ": cannot put the outputs in place: " + what);
  };
  for (const std::string& name : names) {
    if (std::binary_search(foreign.begin(), foreign.end(), name)) {
      discard();
      throw InputError(option_ + ": folder '" + target_ + "' holds '" + name +
                       "', which stridemap did not write there, and this run writes a file of that name; it is kept "
                       "and nothing was written: move it away or give a new or empty folder");
    }
  }
  // The user's entries stay where they are, so the set cannot be swapped in
  // whole: it moves in name by name. Meanwhile the manifest names the old
  // and the new files, so that a run killed half-way leaves a folder the
  // next run still knows (and replaces) as stridemap's.
  std::set<std::string> either(owned.begin(), owned.end());
  either.insert(names.begin(), names.end());
  std::string interim = "# stridemap output set being replaced: the files below are stridemap's; some may be missing "
                        "or from the previous set\n";
  for (const std::string& name : either) interim += name + "\n";
  const std::string interim_path = staging_ + "/" + kOutputManifest + ".interim";
  const std::string target_manifest = target_ + "/" + kOutputManifest;
  try {
    write_small_file(interim_path, interim);
  } catch (const InputError& e) {
    fail(std::string("cannot write the manifest: ") + e.what());
  }
  if (::rename(interim_path.c_str(), target_manifest.c_str()) != 0) fail("manifest: " + detail::errno_text(errno));
  if (const int error = detail::sync_path(target_); error != 0) fail("fsync: " + detail::errno_text(error));
  std::error_code ec;
  for (const std::string& name : names) {
    const std::string to = target_ + "/" + name;
    const bool ours = std::binary_search(owned.begin(), owned.end(), name);
    struct stat info {};
    // A folder neither is renamed over nor renames over a file: the
    // previous entry (ours) goes first.
    struct stat staged {};
    const bool staged_folder = ::lstat(file(name).c_str(), &staged) == 0 && S_ISDIR(staged.st_mode);
    if (ours && ::lstat(to.c_str(), &info) == 0 && (S_ISDIR(info.st_mode) || staged_folder)) fs::remove_all(to, ec);
    if (ec) fail(name + ": " + ec.message());
    // A name that was not ours when the folder was listed may be the user's
    // by now: never replaced.
    const unsigned flags = ours ? 0 : RENAME_NOREPLACE;
    if (::renameat2(AT_FDCWD, file(name).c_str(), AT_FDCWD, to.c_str(), flags) != 0) {
      fail(name + ": " + detail::errno_text(errno));
    }
  }
  for (const std::string& name : owned) {
    if (!std::binary_search(names.begin(), names.end(), name)) fs::remove_all(target_ + "/" + name, ec);
    if (ec) fail(name + ": " + ec.message());
  }
  if (const int error = detail::sync_path(target_); error != 0) fail("fsync: " + detail::errno_text(error));
  if (::rename(file(kOutputManifest).c_str(), target_manifest.c_str()) != 0) {
    fail("manifest: " + detail::errno_text(errno));
  }
  finish(false);
  std::error_code ignored;
  fs::remove_all(staging_, ignored);  // empty by now
}

void OutputFolder::discard() noexcept {
  if (!staging_.empty()) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
  detail::release_temporary(registry_slot_);
  registry_slot_ = -1;
}

void remove_temporaries_in_signal_handler() noexcept { detail::remove_registered_temporaries(); }

}  // namespace stridemap::io
