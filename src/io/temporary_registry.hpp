#pragma once
// Internal to the io layer: the temporary files and staging folders this
// process has open, so that a signal handler can remove them before the
// process dies (system calls only), and the clean-up of leftovers that a
// killed process (SIGKILL: no handler runs) left behind.
#include <string>

namespace stridemap::io::detail {

/// Registers a temporary path; returns a slot for release(), or -1 when the
/// table is full (the path is then only cleaned by the next run).
int register_temporary(const std::string& path, bool is_folder) noexcept;
void release_temporary(int slot) noexcept;
/// Removes every registered path (folders with the files in them).
void remove_registered_temporaries() noexcept;

/// Temporary names are "<prefix><pid>-<n>"; removes the entries of
/// `folder` so named whose process no longer runs. Errors are ignored: a
/// leftover that stays is harmless, it is never read.
void remove_stale_temporaries(const std::string& folder, const std::string& prefix) noexcept;

/// fsync of a path opened read-only (a folder, or a file written already);
/// returns errno or 0.
int sync_path(const std::string& path) noexcept;

}  // namespace stridemap::io::detail
