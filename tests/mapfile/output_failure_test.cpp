// Writing outputs where that cannot work, in ways that hold when the tests
// run as root (chmod-based read-only folders do not stop root): /dev/full is
// a disk that is always full, sysfs refuses new files to everyone, and a
// path below a regular file has no folder. Every writer must say which file
// and why, and never touch the device node it was pointed at.
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap::io {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& write) {
  try {
    write();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

bool is_character_device(const char* path) {
  struct stat info {};
  return ::stat(path, &info) == 0 && S_ISCHR(info.st_mode);
}

// One writer of each kind aimed at `path`.
std::vector<std::pair<std::string, std::string>> errors_writing_to(const std::string& path) {
  const Eigen::MatrixXf grid = Eigen::MatrixXf::Constant(200, 200, 0.25f);
  return {{"PNG", error_of([&] { write_png(path, RgbImage(400, 400, 10, 20, 30)); })},
          {"grid CSV", error_of([&] { write_grid_csv(path, grid, {}); })},
          {"summary", error_of([&] { write_text_file(path, std::string(100000, 'x'), "summary"); })}};
}

TEST(OutputFailure, FullDiskIsReportedByEveryWriter) {
  if (!is_character_device("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  for (const auto& [kind, message] : errors_writing_to("/dev/full")) {
    EXPECT_EQ(message.rfind("cannot write " + kind + " '/dev/full': ", 0), 0u) << message;
    EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  }
  EXPECT_TRUE(is_character_device("/dev/full")) << "a writer replaced the device node";
  for (const auto& entry : fs::directory_iterator("/dev")) {
    EXPECT_EQ(entry.path().filename().string().rfind(".full.tmp", 0), std::string::npos) << entry.path();
  }
}

TEST(OutputFailure, DevNullIsWrittenToNotReplaced) {
  if (!is_character_device("/dev/null")) GTEST_SKIP() << "no /dev/null on this system";
  for (const auto& [kind, message] : errors_writing_to("/dev/null")) EXPECT_EQ(message, "no error") << kind;
  EXPECT_TRUE(is_character_device("/dev/null"));
}

// The same on a device node of our own (root only, as in CI), where a
// writer that renamed a temporary file onto it would do no harm to /dev.
TEST(OutputFailure, DeviceNodeSurvivesEveryWriter) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_device_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string node = (dir / "null").string();
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    fs::remove_all(dir);
    GTEST_SKIP() << "cannot create a device node here (needs root and a file system that allows them)";
  }
  for (const auto& [kind, message] : errors_writing_to(node)) {
    EXPECT_EQ(message, "no error") << kind;
    EXPECT_TRUE(is_character_device(node.c_str())) << kind << " replaced the device node";
  }
  fs::remove_all(dir);
}

TEST(OutputFailure, FolderNobodyMayWriteIntoEvenRoot) {
  // sysfs refuses to create files for every user, root included.
  if (!fs::is_directory("/sys/kernel")) GTEST_SKIP() << "no sysfs mounted at /sys";
  for (const auto& [kind, message] : errors_writing_to("/sys/stridemap_map.out")) {
    EXPECT_EQ(message.rfind("cannot write " + kind + " '/sys/stridemap_map.out': folder '/sys' is not writable", 0),
              0u)
        << message;
  }
}

TEST(OutputFailure, PathBelowAFileAndPathThatIsAFolder) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_output_failure_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "existing_folder");
  write_text_file((dir / "plain.txt").string(), "x", "text");
  for (const auto& [kind, message] : errors_writing_to((dir / "plain.txt" / "map.out").string())) {
    EXPECT_NE(message.find("plain.txt' is not a folder"), std::string::npos) << kind << ": " << message;
  }
  for (const auto& [kind, message] : errors_writing_to((dir / "existing_folder").string())) {
    EXPECT_NE(message.find("existing_folder': it is a folder"), std::string::npos) << kind << ": " << message;
  }
  EXPECT_TRUE(fs::is_directory(dir / "existing_folder"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace stridemap::io
