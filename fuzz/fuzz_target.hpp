#pragma once
// One fuzz target per parser of outside bytes (docs/reliability.md). A
// target is a function of the raw bytes, registered by name:
//
//   STRIDEMAP_FUZZ_TARGET(scene_yaml) {
//     const std::string text = stridemap::fuzz::as_text(data);
//     try { stridemap::parse_scene_yaml(text, "fuzz.yaml"); } catch (const stridemap::InputError&) {}
//   }
//
// The same file is compiled twice: into a libFuzzer program of its own
// (fuzz/CMakeLists.txt, with fuzz_main.cpp) and into the regression test
// (tests/fuzz/fuzz_regression_test.cpp), which feeds it every file of
// fuzz/corpus/<name>/ and fuzz/regressions/<name>/ in plain `make test`.
//
// What counts as a bug: a crash or sanitizer report, any exception other than
// stridemap::InputError leaving the target, or a broken promise the target
// checks with fuzz::check (e.g. "a config the reader accepted is accepted by
// the mapper too").
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace stridemap::fuzz {

using Bytes = std::span<const std::uint8_t>;
using Entry = void (*)(Bytes);

struct Target {
  const char* name;
  Entry entry;
};

inline std::vector<Target>& registry() {
  static std::vector<Target> targets;
  return targets;
}

struct Registrar {
  Registrar(const char* name, Entry entry) { registry().push_back({name, entry}); }
};

/// A broken promise. The fuzzer program prints it and aborts (libFuzzer keeps
/// the input); the regression test turns it into a test failure.
[[noreturn]] void failure(const std::string& what);

inline void check(bool ok, const std::string& what) {
  if (!ok) failure(what);
}

inline std::string_view as_text(Bytes data) {
  return {reinterpret_cast<const char*>(data.data()), data.size()};
}

}  // namespace stridemap::fuzz

#define STRIDEMAP_FUZZ_TARGET(name)                                                                    \
  static void stridemap_fuzz_##name(::stridemap::fuzz::Bytes data);                                    \
  static const ::stridemap::fuzz::Registrar stridemap_fuzz_registrar_##name(#name, stridemap_fuzz_##name); \
  static void stridemap_fuzz_##name([[maybe_unused]] ::stridemap::fuzz::Bytes data)
