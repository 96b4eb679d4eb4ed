#pragma once
// Where a test or benchmark finds the source tree (shipped scenes, configs,
// fuzz corpora), the shared recordings and the programs it runs. The paths
// are compiled into one small library per build (stridemap_test_paths,
// cmake/StridemapHelpers.cmake) rather than passed to every compile as -D
// strings: an absolute path on a compile line is part of the compiler
// cache's key, and would make a fresh clone of the same commit recompile
// every test program (cmake/StridemapCompilerCache.cmake).
namespace stridemap::test_paths {
const char* source_dir();
/// Real recordings; tests that read them skip when the folder is absent.
const char* shared_data_dir();
/// The built `stridemap` tool; empty in a build without it.
const char* cli_path();
/// The built ROS 1 node; empty in a build without ROS.
const char* node_path();
}  // namespace stridemap::test_paths

// The names the tests were written with; each is a const char*, not a literal.
#define STRIDEMAP_SOURCE_DIR (::stridemap::test_paths::source_dir())
#define STRIDEMAP_SHARED_DATA_DIR (::stridemap::test_paths::shared_data_dir())
#define STRIDEMAP_CLI_PATH (::stridemap::test_paths::cli_path())
#define STRIDEMAP_NODE_PATH (::stridemap::test_paths::node_path())
