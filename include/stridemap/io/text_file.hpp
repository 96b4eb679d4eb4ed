#pragma once
// Reading and writing whole files by name. Writing a whole text file (summaries, reports) so that it appears under its
// final name only when complete, as the PNG and CSV writers do.
#include <string>

namespace stridemap::io {

/// Throws InputError naming the path and the reason (missing or read-only
/// folder, disk full); `kind` names the content ("summary").
void write_text_file(const std::string& path, const std::string& text, const std::string& kind);

/// Throws InputError "<path>: cannot open <what>: it is a folder, not a file"
/// when `path` names a folder. An std::ifstream opens a folder without
/// complaint and then throws a bare "basic_filebuf::underflow" at the first
/// read, so every reader of a named file calls this before opening it.
void refuse_folder(const std::string& path, const std::string& what);

}  // namespace stridemap::io
