// Runs every fuzz target on every file of its seed corpus
// (fuzz/corpus/<target>/) and of its regressions (fuzz/regressions/<target>/:
// each input a fuzzer ever found a bug with), through the same entry point
// as the fuzzer program, so that a fixed bug stays fixed in plain `make test`.
// One test per target and folder.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz_target.hpp"
#include "test_paths.hpp"

namespace stridemap::fuzz {

struct BrokenPromise : std::logic_error {
  using std::logic_error::logic_error;
};

void failure(const std::string& what) { throw BrokenPromise(what); }

}  // namespace stridemap::fuzz

namespace {

namespace fs = std::filesystem;
using stridemap::fuzz::Target;

const fs::path kFuzzDir = fs::path(STRIDEMAP_SOURCE_DIR) / "fuzz";

std::vector<fs::path> files_in(const fs::path& folder) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzInputs : public testing::Test {
 public:
  FuzzInputs(Target target, fs::path folder, bool must_exist)
      : target_(target), folder_(std::move(folder)), must_exist_(must_exist) {}

  void TestBody() override {
    const std::vector<fs::path> files = files_in(folder_);
    if (must_exist_) {
      ASSERT_FALSE(files.empty()) << "fuzz target " << target_.name << " has no seed corpus in " << folder_;
    }
    for (const fs::path& file : files) {
      const std::vector<std::uint8_t> bytes = read_bytes(file);
      try {
        target_.entry(bytes);
      } catch (const std::exception& e) {
        ADD_FAILURE() << file << ": " << e.what();
      }
    }
  }

 private:
  Target target_;
  fs::path folder_;
  bool must_exist_;
};

// Every corpus or regression folder belongs to a target (a typo in a folder
// name would silently skip its inputs).
TEST(FuzzTargets, EveryInputFolderHasATarget) {
  for (const char* kind : {"corpus", "regressions"}) {
    for (const auto& entry : fs::directory_iterator(kFuzzDir / kind)) {
      if (!entry.is_directory()) continue;
      const std::string name = entry.path().filename().string();
      const auto& targets = stridemap::fuzz::registry();
      EXPECT_TRUE(std::any_of(targets.begin(), targets.end(), [&](const Target& t) { return name == t.name; }))
          << "fuzz/" << kind << "/" << name << " has no fuzz/targets/" << name << ".cpp";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  for (const Target& target : stridemap::fuzz::registry()) {
    for (const bool seeds : {true, false}) {
      const fs::path folder = kFuzzDir / (seeds ? "corpus" : "regressions") / target.name;
      testing::RegisterTest("FuzzRegression", (std::string(target.name) + (seeds ? "_corpus" : "_regressions")).c_str(),
                            nullptr, nullptr, __FILE__, __LINE__,
                            [=]() -> testing::Test* { return new FuzzInputs(target, folder, seeds); });
    }
  }
  return RUN_ALL_TESTS();
}
