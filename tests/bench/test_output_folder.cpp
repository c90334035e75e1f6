// A user's files are never deleted or replaced: every kind of path chainmail did not make is
// refused before anything is written, and what chainmail made is replaced only by the same command.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/harness/output/output_folder.hpp"
#include "core/scene.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;

class OutputFolderTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = chainmail::test_temp_root() /
           ("chainmail_test_folder_" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // claim, write one file, commit
  void write_run(const fs::path& path, const std::string& command = "run", bool force = false) {
    OutputFolder folder = OutputFolder::claim(path.string(), command, force);
    std::ofstream(fs::path(folder.staging()) / "summary.json") << "{}";
    folder.commit();
  }
  // claim must refuse `path` with exit-2 input error naming it
  void expect_refused(const std::string& path, bool force = false) {
    try {
      OutputFolder::claim(path, "run", force);
      ADD_FAILURE() << "accepted " << path;
    } catch (const SceneError& e) {
      const bool blank = path.find_first_not_of(' ') == std::string::npos;
      EXPECT_NE(std::string(e.what()).find(blank ? "--out" : path), std::string::npos) << e.what();
    }
  }
  // nothing chainmail-made (no staging or old folder) left in the test folder
  void expect_no_leftovers() {
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      EXPECT_EQ(name.find(".partial-"), std::string::npos) << name;
      EXPECT_EQ(name.find(".old-"), std::string::npos) << name;
    }
  }

  fs::path dir_;
};

TEST_F(OutputFolderTest, RefusesARegularFileAndLeavesItAlone) {
  const fs::path file = dir_ / "notes.txt";
  std::ofstream(file) << "my notes";
  expect_refused(file.string());
  expect_refused(file.string(), /*force=*/true);
  std::ifstream in(file);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "my notes");
  expect_no_leftovers();
}

TEST_F(OutputFolderTest, RefusesADevice) {
  expect_refused("/dev/null");
  expect_refused("/dev/null", true);
  struct stat info {};
  ASSERT_EQ(::stat("/dev/null", &info), 0);
  EXPECT_TRUE(S_ISCHR(info.st_mode));
}

TEST_F(OutputFolderTest, RefusesAForeignFolderEvenWithForce) {
  const fs::path folder = dir_ / "photos";
  fs::create_directories(folder);
  std::ofstream(folder / "holiday.jpg") << "jpeg";
  expect_refused(folder.string());
  expect_refused(folder.string(), true);
  EXPECT_TRUE(fs::exists(folder / "holiday.jpg"));
}

TEST_F(OutputFolderTest, ForceReplacesOnlyAnEmptyForeignFolder) {
  const fs::path folder = dir_ / "empty";
  fs::create_directories(folder);
  expect_refused(folder.string());
  EXPECT_TRUE(fs::is_directory(folder));
  write_run(folder, "run", /*force=*/true);
  EXPECT_TRUE(fs::exists(folder / "summary.json"));
  EXPECT_TRUE(fs::exists(folder / kManifestName));
  expect_no_leftovers();
}

TEST_F(OutputFolderTest, RefusesSymlinksDanglingOrNot) {
  const fs::path target = dir_ / "target";
  fs::create_directories(target);
  fs::create_directory_symlink(target, dir_ / "link");
  fs::create_symlink(dir_ / "nowhere", dir_ / "dangling");
  expect_refused((dir_ / "link").string());
  expect_refused((dir_ / "link").string(), true);
  expect_refused((dir_ / "dangling").string());
  EXPECT_TRUE(fs::is_symlink(dir_ / "link"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling"));
  EXPECT_TRUE(fs::is_empty(target));
}

TEST_F(OutputFolderTest, RefusesPathsThatCannotBeWrittenBeforeWritingAnything) {
  std::ofstream(dir_ / "file.txt") << "x";
  expect_refused((dir_ / "file.txt" / "out").string());  // a component is a regular file
  expect_refused("/proc/chainmail-test/out");
  expect_refused((dir_ / std::string(300, 'n')).string());
  expect_refused(".");
  expect_refused((dir_ / "..").string());
  expect_refused((dir_ / "out/").string());  // trailing slash
  expect_refused("");
  expect_refused("   ");
  // a missing parent that cannot be made leaves none of the parents it made behind
  expect_refused((dir_ / "a" / "b" / std::string(300, 'c')).string());
  EXPECT_FALSE(fs::exists(dir_ / "a"));
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(OutputFolderTest, ReplacesItsOwnFolderButNotWhatAUserAddedToIt) {
  const fs::path out = dir_ / "results" / "run";
  write_run(out);
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  write_run(out);  // its own: replaced
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  std::ofstream(out / "my_analysis.py") << "print(1)";
  try {
    write_run(out);
    ADD_FAILURE() << "replaced a folder holding a user's file";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("my_analysis.py"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(out / "my_analysis.py"));
  expect_no_leftovers();
}

TEST_F(OutputFolderTest, OneCommandNeverReplacesAnothersOutput) {
  const fs::path out = dir_ / "sweep";
  write_run(out, "sweep");
  try {
    write_run(out, "run");
    ADD_FAILURE() << "run replaced a sweep folder";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("sweep"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST_F(OutputFolderTest, UncommittedFolderLeavesNothing) {
  {
    OutputFolder folder =
        OutputFolder::claim((dir_ / "deep" / "er" / "out").string(), "run", false);
    std::ofstream(fs::path(folder.staging()) / "half.csv") << "1,2";
  }  // an exception or an error: never committed
  EXPECT_FALSE(fs::exists(dir_ / "deep"));
  expect_no_leftovers();
}

TEST_F(OutputFolderTest, PointsStartedTogetherShareTheParentsTheyCreate) {
  // the points of a sweep on Slurm start at the same moment, each claiming sweep/points/K under
  // parents that none of them found: whoever makes a parent first, every point gets its folder
  for (int round = 0; round < 20; ++round) {
    fs::remove_all(dir_ / "sweep");
    constexpr int kPoints = 8;
    std::vector<std::thread> points;
    std::atomic<int> refused{0};
    for (int k = 0; k < kPoints; ++k) {
      points.emplace_back([&, k] {
        try {
          write_run(dir_ / "sweep" / "points" / std::to_string(k));
        } catch (const SceneError&) {
          ++refused;
        }
      });
    }
    for (auto& point : points) point.join();
    ASSERT_EQ(refused, 0) << "round " << round;
    for (int k = 0; k < kPoints; ++k)
      EXPECT_TRUE(fs::exists(dir_ / "sweep" / "points" / std::to_string(k) / "summary.json"));
  }
}

TEST_F(OutputFolderTest, AFileAddedWhileRunningIsNotReplaced) {
  const fs::path out = dir_ / "run";
  write_run(out);
  OutputFolder folder = OutputFolder::claim(out.string(), "run", false);
  std::ofstream(out / "added_meanwhile.txt") << "mine";
  EXPECT_THROW(folder.commit(), SceneError);
  EXPECT_TRUE(fs::exists(out / "added_meanwhile.txt"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

}  // namespace
}  // namespace chainmail
