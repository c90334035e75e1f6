// Where chainmail finds its scenes, shaders and plot script: an installed binary its install's
// data folder, a build tree its source tree, $CHAINMAIL_DATA_DIR either; in both layouts.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;

class DataDirTest : public testing::Test {
 protected:
  void SetUp() override {
    // a folder of each test's own: ctest runs the tests of this fixture in parallel
    root_ = chainmail::test_temp_root() /
            ("chainmail_test_data_dir_" +
             std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root_);
    fs::create_directories(installed() / "scenes");
    fs::create_directories(source() / "bench" / "scenes");
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path installed() const { return root_ / "prefix" / "share" / "chainmail"; }
  fs::path source() const { return root_ / "src"; }
  fs::path root_;
};

TEST_F(DataDirTest, AnInstallsDataWinsOverTheSourceTreeAndTheVariableOverBoth) {
  const DataDir from_install = find_data_dir(nullptr, installed(), source());
  EXPECT_EQ(from_install.root, installed().string());
  EXPECT_FALSE(from_install.source_tree);

  // the variable names either layout
  const DataDir from_env = find_data_dir(source().c_str(), installed(), source());
  EXPECT_EQ(from_env.root, source().string());
  EXPECT_TRUE(from_env.source_tree);
  EXPECT_EQ(find_data_dir(installed().c_str(), "", source()).root, installed().string());
  EXPECT_EQ(find_data_dir("", installed(), source()).root, installed().string());  // empty: unset

  // a binary in its build tree: no install beside it, the tree it was built from
  const DataDir from_source =
      find_data_dir(nullptr, (root_ / "build" / "share").string(), source());
  EXPECT_EQ(from_source.root, source().string());
  EXPECT_TRUE(from_source.source_tree);
}

TEST_F(DataDirTest, EachLayoutHasItsOwnPaths) {
  const DataDir install = data_dir_at(installed());
  EXPECT_EQ(install.scenes(), installed().string() + "/scenes");
  EXPECT_EQ(install.shaders(), installed().string() + "/shaders");
  EXPECT_EQ(install.plot_script("plot_sweep.py"), installed().string() + "/plot_sweep.py");
  const DataDir tree = data_dir_at(source());
  EXPECT_EQ(tree.scenes(), source().string() + "/bench/scenes");
  EXPECT_EQ(tree.shaders(), source().string() + "/shaders");
  EXPECT_EQ(tree.plot_script("plot_sweep.py"), source().string() + "/bench/plot_sweep.py");
}

TEST_F(DataDirTest, NoDataFolderIsBadInputNamingTheVariable) {
  fs::remove_all(installed() / "scenes");
  fs::remove_all(source());
  const DataDir none = find_data_dir(nullptr, installed(), source());
  EXPECT_TRUE(none.root.empty());
  try {
    none.scenes();
    FAIL() << "no error";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("set CHAINMAIL_DATA_DIR"), std::string::npos);
  }
}

TEST(DataDir, ThisTestBinaryReadsTheSourceTreeItWasBuiltFrom) {
  if (const char* env = std::getenv("CHAINMAIL_DATA_DIR"); env && *env)
    GTEST_SKIP() << "CHAINMAIL_DATA_DIR is set";
  EXPECT_EQ(fs::path(data_dir().scenes()), fs::path(CHAINMAIL_SOURCE_DIR) / "bench" / "scenes");
  EXPECT_TRUE(fs::exists(data_dir().plot_script("plot_sweep.py")));
}

}  // namespace
}  // namespace chainmail
