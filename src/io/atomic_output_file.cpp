#include "stridemap/io/detail/atomic_output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <system_error>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/io/detail/errno_text.hpp"
#include "temporary_registry.hpp"

namespace stridemap::io::detail {
namespace {

std::string parent_folder(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Says why a file could not be created in `folder`, in the user's terms.
std::string creation_failure(const std::string& folder, int error_number) {
  struct stat info {};
  if (error_number == ENOENT && ::stat(folder.c_str(), &info) != 0) {
    return "folder '" + folder + "' does not exist";
  }
  if (error_number == ENOTDIR) return "'" + folder + "' is not a folder";
  if (error_number == EACCES || error_number == EROFS || error_number == EPERM) {
    return "folder '" + folder + "' is not writable (" + errno_text(error_number) + ")";
  }
  return "cannot create a file in folder '" + folder + "' (" + errno_text(error_number) + ")";
}

}  // namespace

AtomicOutputFile::AtomicOutputFile(std::string final_path, std::string kind)
    : final_path_(std::move(final_path)), kind_(std::move(kind)) {
  if (final_path_.empty()) throw InputError("cannot write " + kind_ + ": the output path is empty");
  const std::string name = base_name(final_path_);
  if (name.empty() || name == "." || name == "..") fail("the path names a folder, not a file");

  struct stat existing {};
  if (::stat(final_path_.c_str(), &existing) == 0) {
    if (S_ISDIR(existing.st_mode)) fail("it is a folder");
    if (!S_ISREG(existing.st_mode)) {
      // A device or pipe (/dev/null, /dev/stdout, a FIFO): write to it
      // directly. Renaming a temporary file onto it would replace the
      // device node itself when running as root.
      const int fd = ::open(final_path_.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0) fail("cannot open it (" + errno_text(errno) + ")");
      stream_ = ::fdopen(fd, "wb");
      if (stream_ == nullptr) {
        const int error_number = errno;
        ::close(fd);
        fail("cannot open a stream (" + errno_text(error_number) + ")");
      }
      return;
    }
  }

  const std::string folder = parent_folder(final_path_);
  // A writer killed with SIGKILL left its temporary file; no handler ran.
  std::string prefix(1, '.');
  prefix += name;
  prefix += ".tmp-";
  remove_stale_temporaries(folder, prefix);
  // Several processes (or threads) may write into one folder; the pid and a
  // process-wide counter keep the names apart and O_EXCL catches the rest.
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string candidate = folder + "/." + name + ".tmp-" + std::to_string(::getpid()) + "-" +
                            std::to_string(counter.fetch_add(1));
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      fail(creation_failure(folder, errno));
    }
    stream_ = ::fdopen(fd, "wb");
    if (stream_ == nullptr) {
      const int error_number = errno;
      ::close(fd);
      ::unlink(candidate.c_str());
      fail("cannot open a stream (" + errno_text(error_number) + ")");
    }
    temp_path_ = std::move(candidate);
    registry_slot_ = register_temporary(temp_path_, false);
    return;
  }
  fail("cannot find a free temporary file name in folder '" + folder + "'");
}

AtomicOutputFile::~AtomicOutputFile() { discard(); }

void AtomicOutputFile::write(const void* data, std::size_t size) {
  if (size == 0) return;
  if (std::fwrite(data, 1, size, stream_) != size) {
    fail("write failed (" + errno_text(errno) + ")");
  }
}

void AtomicOutputFile::commit() {
  // Buffered data may only hit the disk now; fflush and fclose are where a
  // full disk usually shows up.
  if (std::fflush(stream_) != 0 || std::ferror(stream_) != 0) {
    fail("write failed (" + errno_text(errno) + ")");
  }
  // Data on the disk before the name: after a power cut the final name never
  // points at a file with missing blocks.
  if (!temp_path_.empty() && ::fsync(::fileno(stream_)) != 0 && errno != EINVAL) {
    fail("write failed when syncing the file to the disk (" + errno_text(errno) + ")");
  }
  std::FILE* stream = std::exchange(stream_, nullptr);
  if (std::fclose(stream) != 0) {
    const int error_number = errno;
    if (!temp_path_.empty()) ::unlink(temp_path_.c_str());
    temp_path_.clear();
    fail("write failed when closing the file (" + errno_text(error_number) + ")");
  }
  if (temp_path_.empty()) return;  // written straight to a device or pipe
  if (std::rename(temp_path_.c_str(), final_path_.c_str()) != 0) {
    fail("cannot move the finished file into place (" + errno_text(errno) + ")");
  }
  temp_path_.clear();
  release_temporary(registry_slot_);
  registry_slot_ = -1;
  (void)sync_path(parent_folder(final_path_));
}

void AtomicOutputFile::fail(const std::string& reason) {
  discard();
  throw InputError("cannot write " + kind_ + " '" + final_path_ + "': " + reason);
}

void AtomicOutputFile::discard() noexcept {
  if (stream_ != nullptr) {
    std::fclose(stream_);
    stream_ = nullptr;
  }
  if (!temp_path_.empty()) {
    ::unlink(temp_path_.c_str());
    temp_path_.clear();
  }
  release_temporary(registry_slot_);
  registry_slot_ = -1;
}

}  // namespace stridemap::io::detail
