#pragma once
// Internal to the layers that write files (detail/ is not installed): an
// output file that appears under its final name only once it has been
// written completely. Writers fill a temporary file in the destination
// folder (same file system, so the final rename is atomic) and a failure at
// any point (missing or read-only folder, disk full, an exception in the
// writer) removes the temporary file, leaving whatever was at the final path
// before untouched. A final path that is a device or a pipe (/dev/null,
// /dev/full, a FIFO) is written directly; one that is a folder is an error.
// The file is synced to the disk before the rename; a temporary file left by
// a writer killed with SIGKILL is removed by the next writer of the same name
// in that folder.
#include <cstdio>
#include <string>

namespace stridemap::io::detail {

class AtomicOutputFile {
 public:
  // Creates the temporary file; `kind` names the content for error messages
  // ("PNG", "grid CSV"). Throws InputError naming the path on failure.
  AtomicOutputFile(std::string final_path, std::string kind);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::FILE* stream() { return stream_; }

  // Writes the bytes or throws InputError (with errno's reason).
  void write(const void* data, std::size_t size);

  // Flushes, closes and renames onto the final path; throws InputError if any
  // step fails (the temporary file is removed then).
  void commit();

  // "cannot write <kind> '<path>': <reason>", for writers that detect a
  // failure themselves (e.g. reported by libpng).
  [[noreturn]] void fail(const std::string& reason);

  const std::string& final_path() const { return final_path_; }
  const std::string& temp_path() const { return temp_path_; }

 private:
  void discard() noexcept;

  std::string final_path_;
  std::string kind_;
  std::string temp_path_;
  std::FILE* stream_ = nullptr;
  int registry_slot_ = -1;  // so that a stop signal's handler can remove temp_path_
};

}  // namespace stridemap::io::detail
