#include "installed_data.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "stridemap/core/error.hpp"

#ifndef STRIDEMAP_DATA_FROM_BINDIR
#define STRIDEMAP_DATA_FROM_BINDIR "../share/stridemap"
#endif

namespace stridemap::cli {
namespace {

// The running executable's folder; empty when /proc is not mounted.
std::filesystem::path executable_folder() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path() : self.parent_path();
}

}  // namespace

std::vector<std::string> data_search_paths(const std::string& relative_path) {
  std::vector<std::string> places{relative_path};
  const std::filesystem::path bin = executable_folder();
  if (!bin.empty()) {
    places.push_back((bin / STRIDEMAP_DATA_FROM_BINDIR / relative_path).lexically_normal().string());
  }
  return places;
}

std::string resolve_default_data_file(const std::string& option, const std::string& path,
                                      const std::string& default_path) {
  if (path != default_path) return path;
  const std::vector<std::string> places = data_search_paths(default_path);
  std::error_code error;
  for (const std::string& place : places) {
    if (std::filesystem::is_regular_file(place, error)) return place;
  }
  std::string looked;
  for (const std::string& place : places) {
    looked += (looked.empty() ? "" : ", ") + std::filesystem::absolute(place, error).string();
  }
  throw InputError(option + ": the default file " + default_path + " was not found (looked in " + looked +
                   "); run from the source folder, install stridemap, or pass " + option);
}

}  // namespace stridemap::cli
