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
#include <system_error>
#include <vector>

#include "stridemap/core/error.hpp"
#include "errno_text.hpp"
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

bool looks_like_an_older_output(const fs::directory_entry& entry) {
  std::error_code ec;
  if (!entry.is_regular_file(ec)) return false;
  const std::string extension = entry.path().extension().string();
  return extension == ".png" || extension == ".csv" || extension == ".json" || extension == ".smap";
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  struct stat first {}, second {};
  if (a.empty() || b.empty() || ::stat(a.c_str(), &first) != 0 || ::stat(b.c_str(), &second) != 0) return false;
  return first.st_dev == second.st_dev && first.st_ino == second.st_ino;
}

void check_output_folder(const std::string& raw_target, const std::string& option) {
  const std::string target = without_trailing_slashes(raw_target);
  if (target.empty()) throw InputError(option + ": the output folder is empty");
  const std::string name = name_of(target);
  if (name == "." || name == ".." || target == "/") {
    throw InputError(option + ": '" + raw_target + "' cannot be replaced as a whole; name a folder of its own");
  }
  struct stat info {};
  if (::lstat(target.c_str(), &info) != 0) {
    if (errno == ENOENT) return;  // created by commit(); a parent that cannot be made is found when staging
    throw InputError(raw_target + ": cannot create the output folder: " + detail::errno_text(errno));
  }
  if (!S_ISDIR(info.st_mode)) {
    throw InputError(raw_target + ": cannot create the output folder: it exists and is not a folder");
  }
  std::error_code ec;
  if (fs::exists(fs::path(target) / kOutputManifest, ec)) return;
  for (const auto& entry : fs::directory_iterator(target, ec)) {
    if (!looks_like_an_older_output(entry)) {
      throw InputError(option + ": folder '" + raw_target + "' holds '" + entry.path().filename().string() +
                       "', which stridemap did not write there; the whole folder would be replaced, so give a "
                       "new or empty folder");
    }
  }
  if (ec) throw InputError(option + ": cannot list folder '" + raw_target + "': " + ec.message());
}

OutputFolder::OutputFolder(std::string target, std::string option)
    : target_(without_trailing_slashes(std::move(target))), option_(std::move(option)) {
  check_output_folder(target_, option_);
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
  {
    const std::string manifest_path = file(kOutputManifest);
    std::FILE* out = std::fopen(manifest_path.c_str(), "wb");
    if (out == nullptr) fail("cannot write the manifest: " + detail::errno_text(errno));
    const bool written = std::fwrite(manifest.data(), 1, manifest.size(), out) == manifest.size();
    const bool flushed = std::fflush(out) == 0 && ::fsync(::fileno(out)) == 0;
    const int error = errno;
    const bool closed = std::fclose(out) == 0;
    if (!written || !flushed || !closed) fail("cannot write the manifest: " + detail::errno_text(error));
  }
  if (const int error = detail::sync_path(staging_); error != 0) fail("fsync: " + detail::errno_text(error));

  struct stat info {};
  const bool replacing = ::lstat(target_.c_str(), &info) == 0;
  if (replacing) {
    // The same checks as at the start: the folder may have changed since.
    try {
      check_output_folder(target_, option_);
    } catch (const InputError& e) {
      fail(e.what());
    }
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
      fail(detail::errno_text(errno));
    }
  } else if (::rename(staging_.c_str(), target_.c_str()) != 0) {
    fail(detail::errno_text(errno));
  }
  committed_ = true;
  (void)detail::sync_path(parent_of(target_));
  // After an exchange the staging name holds the previous set: remove it. A
  // kill now leaves it for the next run to remove; readers never see it.
  if (replacing) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
  detail::release_temporary(registry_slot_);
  registry_slot_ = -1;
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
