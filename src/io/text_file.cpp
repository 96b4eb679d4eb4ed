#include "stridemap/io/text_file.hpp"

#include <sys/stat.h>

#include "stridemap/core/error.hpp"
#include "stridemap/io/detail/atomic_output_file.hpp"

namespace stridemap::io {

void write_text_file(const std::string& path, const std::string& text, const std::string& kind) {
  detail::AtomicOutputFile file(path, kind);
  file.write(text.data(), text.size());
  file.commit();
}

void refuse_folder(const std::string& path, const std::string& what) {
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode)) {
    throw InputError(path + ": cannot open " + what + ": it is a folder, not a file");
  }
}

}  // namespace stridemap::io
