#include "stridemap/io/text_file.hpp"

#include "atomic_output_file.hpp"

namespace stridemap::io {

void write_text_file(const std::string& path, const std::string& text, const std::string& kind) {
  detail::AtomicOutputFile file(path, kind);
  file.write(text.data(), text.size());
  file.commit();
}

}  // namespace stridemap::io
