#pragma once
// The one exception type the library throws for bad input (files, configs,
// scans, device bytes, poses). Its message names the input, the place and
// what is wrong, so that a caller can show it to a user unchanged.
#include <stdexcept>
#include <string>

namespace stridemap {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace stridemap
