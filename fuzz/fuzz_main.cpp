// libFuzzer entry point of a fuzzer program: it holds exactly one target
// (fuzz/targets/<name>.cpp), which this calls with each input.
#include <cstdio>
#include <cstdlib>

#include "fuzz_target.hpp"

namespace stridemap::fuzz {

void failure(const std::string& what) {
  std::fprintf(stderr, "stridemap fuzz target %s: %s\n", registry().empty() ? "?" : registry().front().name,
               what.c_str());
  std::abort();
}

}  // namespace stridemap::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto& targets = stridemap::fuzz::registry();
  if (targets.size() != 1) stridemap::fuzz::failure("a fuzzer program must hold exactly one target");
  targets.front().entry({data, size});
  return 0;
}
