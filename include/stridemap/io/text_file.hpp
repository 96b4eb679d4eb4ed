#pragma once
// Writing a whole text file (summaries, reports) so that it appears under its
// final name only when complete, as the PNG and CSV writers do.
#include <string>

namespace stridemap::io {

/// Throws InputError naming the path and the reason (missing or read-only
/// folder, disk full); `kind` names the content ("summary").
void write_text_file(const std::string& path, const std::string& text, const std::string& kind);

}  // namespace stridemap::io
