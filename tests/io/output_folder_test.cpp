// io::OutputFolder on a target that holds more than stridemap's set: the
// user's entries refuse it, or with OtherFiles::keep stay untouched while
// the set's files are replaced; the manifest decides what is stridemap's,
// and only entries that are really in the folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/output_folder.hpp"

namespace stridemap {
namespace output_folder_test {
namespace {

namespace fs = std::filesystem;

void write_set(const std::string& target, io::OtherFiles other, const std::set<std::string>& names,
               const std::string& content) {
  io::OutputFolder staged(target, "--out", other);
  for (const std::string& name : names) std::ofstream(staged.file(name)) << content;
  staged.commit();
}

std::set<std::string> listed_in(const fs::path& folder) {
  std::ifstream in(folder / io::kOutputManifest);
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') names.insert(line);
  }
  return names;
}

TEST(OutputFolderOwnership, KeepReplacesTheSetAndLeavesTheUsersEntries) {
  test::TestFolder dir;
  const std::string target = dir / "out";
  write_set(target, io::OtherFiles::refuse, {"a.csv", "b.png"}, "old");
  dir.write("out/notes.txt", "mine");
  fs::create_directories(dir / "out/plots");
  dir.write("out/plots/fig.pdf", "figure");
  EXPECT_THROW(write_set(target, io::OtherFiles::refuse, {"a.csv"}, "new"), InputError);
  EXPECT_EQ(dir.read("out/a.csv"), "old");

  write_set(target, io::OtherFiles::keep, {"a.csv", "c.json"}, "new");
  EXPECT_EQ(dir.read("out/a.csv"), "new");
  EXPECT_EQ(dir.read("out/c.json"), "new");
  EXPECT_FALSE(fs::exists(dir / "out/b.png"));  // the old set's, not written again
  EXPECT_EQ(dir.read("out/notes.txt"), "mine");
  EXPECT_EQ(dir.read("out/plots/fig.pdf"), "figure");
  EXPECT_EQ(listed_in(dir / "out"), (std::set<std::string>{"a.csv", "c.json"}));
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

TEST(OutputFolderOwnership, AManifestNamingWhatIsNotInTheFolderRemovesNothing) {
  test::TestFolder dir;
  const std::string target = dir / "out";
  write_set(target, io::OtherFiles::refuse, {"a.csv"}, "old");
  dir.write("precious.txt", "outside");
  fs::create_directories(dir / "out/mine");
  dir.write("out/mine/data.txt", "inside");
  // A manifest edited by hand (or damaged) names paths that are not entries of the folder.
  std::ofstream(dir / ("out/" + std::string(io::kOutputManifest)), std::ios::app)
      << "../precious.txt\nmine/data.txt\n/\n..\n";
  write_set(target, io::OtherFiles::keep, {"a.csv"}, "new");
  EXPECT_EQ(dir.read("precious.txt"), "outside");
  EXPECT_EQ(dir.read("out/mine/data.txt"), "inside");
  EXPECT_EQ(dir.read("out/a.csv"), "new");
}

TEST(OutputFolderOwnership, AUsersFileWithAnOutputsNameIsNeverReplaced) {
  test::TestFolder dir;
  fs::create_directories(dir / "out");
  dir.write("out/a.csv", "mine");
  try {
    write_set(dir / "out", io::OtherFiles::keep, {"a.csv", "b.csv"}, "new");
    ADD_FAILURE() << "the clash was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds 'a.csv', which stridemap did not write there, and this run writes "
                                         "a file of that name; it is kept and nothing was written"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(dir.read("out/a.csv"), "mine");
  EXPECT_FALSE(fs::exists(dir / "out/b.csv"));
  EXPECT_FALSE(fs::exists(dir / ("out/" + std::string(io::kOutputManifest))));
}

}  // namespace
}  // namespace output_folder_test
}  // namespace stridemap
