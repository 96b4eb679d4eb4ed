#include "temporary_registry.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace stridemap::io::detail {
namespace {

constexpr int kSlots = 64;
constexpr std::size_t kMaxPath = 4096;

enum SlotState : int { kFree = 0, kFilling = 1, kReady = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  bool is_folder = false;
  char path[kMaxPath] = {};
};

std::array<Slot, kSlots> g_slots;

// The files in a staging folder, removed with raw system calls: opendir and
// readdir may allocate, getdents64 does not.
void remove_folder_contents(const char* folder) noexcept {
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[4096];
  while (true) {
    const long got = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
    if (got <= 0) break;
    // struct linux_dirent64: inode (8 bytes), offset (8), record length (2), type (1), name.
    for (long at = 0; at + 19 < got;) {
      unsigned short length = 0;
      std::memcpy(&length, buffer + at + 16, sizeof length);
      if (length == 0) break;
      const char* name = buffer + at + 19;
      if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
      at += length;
    }
  }
  ::close(fd);
}

bool process_is_gone(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

int register_temporary(const std::string& path, bool is_folder) noexcept {
  if (path.size() >= kMaxPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].is_folder = is_folder;
    g_slots[i].state.store(kReady);
    return i;
  }
  return -1;
}

void release_temporary(int slot) noexcept {
  if (slot >= 0 && slot < kSlots) g_slots[slot].state.store(kFree);
}

void remove_registered_temporaries() noexcept {
  for (Slot& slot : g_slots) {
    if (slot.state.load() != kReady) continue;
    if (slot.is_folder) {
      // Removing entries while listing may skip some: list again until empty.
      for (int pass = 0; pass < 4; ++pass) {
        remove_folder_contents(slot.path);
        if (::rmdir(slot.path) == 0 || errno == ENOENT) break;
      }
    } else {
      ::unlink(slot.path);
    }
  }
}

void remove_stale_temporaries(const std::string& folder, const std::string& prefix) noexcept {
  try {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.compare(0, prefix.size(), prefix) != 0) continue;
      char* end = nullptr;
      const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
      if (end == name.c_str() + prefix.size() || *end != '-' || !process_is_gone(pid)) continue;
      std::error_code ignored;
      std::filesystem::remove_all(entry.path(), ignored);
    }
  } catch (...) {
    // Listing failed half-way (folder removed meanwhile, out of memory): the
    // leftovers stay until a later run, harmless.
  }
}

int sync_path(const std::string& path) noexcept {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  int result = 0;
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) result = errno;  // EINVAL: not syncable (a pipe)
  ::close(fd);
  return result;
}

}  // namespace stridemap::io::detail
