#pragma once
// The text of an errno value, for error messages that name the file and the
// operation that failed (internal to the layers that write files; detail/
// is not installed).
#include <string>
#include <system_error>

namespace stridemap::io::detail {

inline std::string errno_text(int error_number) { return std::generic_category().message(error_number); }

}  // namespace stridemap::io::detail
