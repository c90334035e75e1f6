// Shader files without a GL context: the include mechanism, the search folders, the defines, and
// the project's own shaders all loading.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "render/renderer.hpp"
#include "render/shaders.hpp"
#include "test_temp.hpp"

namespace chainmail::render {
namespace {

namespace fs = std::filesystem;

// a fresh directory under the system temp dir, removed by the destructor
struct TempDir {
  fs::path path;
  TempDir() {
    path = chainmail::test_temp_root() /
           ("chainmail_shaders_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  void write(const std::string& sub, const std::string& name, const std::string& text) const {
    fs::create_directories(path / sub);
    std::ofstream(path / sub / name) << text;
  }
  std::string dir(const std::string& sub) const { return (path / sub).string(); }
};

// the message of the RenderError that loading `name` throws, or "" when it loads
std::string load_error(const ShaderFiles& files, const std::string& name) {
  try {
    files.load(name);
  } catch (const RenderError& error) {
    return error.what();
  }
  return "";
}

TEST(RenderShaderFiles, IncludesAreReplacedByTheFileNested) {
  TempDir tmp;
  tmp.write("a", "main.frag", "#version 330 core\n#include \"lib.glsl\"\nvoid main() {}\n");
  tmp.write("a", "lib.glsl", "// lib\n#include \"inner.glsl\"\nfloat f() { return g(); }\n");
  tmp.write("a", "inner.glsl", "float g() { return 1.0; }");  // no final newline
  const ShaderFiles files({tmp.dir("a")});
  EXPECT_EQ(files.load("main.frag"),
            "#version 330 core\n// lib\nfloat g() { return 1.0; }\nfloat f() { return g(); }\n"
            "void main() {}\n");
  // only a line that starts with #include is one
  tmp.write("a", "quoted.frag", "// see #include \"lib.glsl\"\n  #include \"lib.glsl\"\n");
  EXPECT_EQ(files.load("quoted.frag"), "// see #include \"lib.glsl\"\n  #include \"lib.glsl\"\n");
}

TEST(RenderShaderFiles, FoldersAreSearchedInOrder) {
  TempDir tmp;
  tmp.write("first", "x.glsl", "first\n");
  tmp.write("second", "x.glsl", "second\n");
  tmp.write("second", "y.glsl", "#include \"x.glsl\"\n");
  const ShaderFiles files({tmp.dir("first"), tmp.dir("second")});
  EXPECT_EQ(files.load("x.glsl"), "first\n");
  EXPECT_EQ(files.load("y.glsl"), "first\n");  // an include is searched from the first folder too
}

TEST(RenderShaderFiles, MissingFilesAndEndlessIncludesAreClearErrors) {
  TempDir tmp;
  tmp.write("a", "main.frag", "#include \"absent.glsl\"\n");
  tmp.write("a", "loop.glsl", "#include \"loop.glsl\"\n");
  const ShaderFiles files({tmp.dir("a"), tmp.dir("b")});
  const std::string missing = load_error(files, "main.frag");
  EXPECT_NE(missing.find("missing shader file 'absent.glsl'"), std::string::npos) << missing;
  EXPECT_NE(missing.find(tmp.dir("a") + ", " + tmp.dir("b")), std::string::npos) << missing;
  EXPECT_NE(load_error(files, "loop.glsl").find("nested too deep in loop.glsl"), std::string::npos);
  const std::string nowhere = load_error(ShaderFiles(std::vector<std::string>{}), "x.glsl");
  EXPECT_NE(nowhere.find("none: set RenderSettings::shader_dir"), std::string::npos) << nowhere;
}

TEST(RenderShaderFiles, DefinesGoAfterTheVersionLine) {
  EXPECT_EQ(with_defines("#version 330 core\nvoid main() {}\n", "#define A 1\n"),
            "#version 330 core\n#define A 1\nvoid main() {}\n");
  EXPECT_EQ(with_defines("#version 330 core\nx\n", ""), "#version 330 core\nx\n");
  EXPECT_EQ(with_defines("no newline", "#define A 1\n"), "no newline");
}

TEST(RenderShaderFiles, ShaderDirIsUsedAloneElseBesideTheBinaryThenTheEnvironment) {
  EXPECT_EQ(shader_dirs("/some/dir"), std::vector<std::string>{"/some/dir"});
  const char* old = std::getenv("CHAINMAIL_SHADER_DIR");
  const std::string saved = old ? old : "";
  ::setenv("CHAINMAIL_SHADER_DIR", "/from/env", 1);
  const std::vector<std::string> dirs = shader_dirs("");
  ASSERT_EQ(dirs.size(), 2u);
  EXPECT_EQ(fs::path(dirs[0]).filename(), "shaders");
  EXPECT_EQ(dirs[1], "/from/env");
  EXPECT_EQ(shader_dirs("/some/dir"), std::vector<std::string>{"/some/dir"});
  if (old) {
    ::setenv("CHAINMAIL_SHADER_DIR", saved.c_str(), 1);
  } else {
    ::unsetenv("CHAINMAIL_SHADER_DIR");
  }
}

TEST(RenderShaderFiles, EveryProjectShaderLoadsWithItsIncludesResolved) {
  const ShaderFiles files({std::string(CHAINMAIL_SOURCE_DIR) + "/shaders"});
  int programs = 0;
  for (const auto& entry : fs::directory_iterator(std::string(CHAINMAIL_SOURCE_DIR) + "/shaders")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".vert" && entry.path().extension() != ".frag") continue;
    const std::string source = files.load(name);
    EXPECT_EQ(source.rfind("#version", 0), 0u) << name;
    EXPECT_EQ(source.find("#include"), std::string::npos) << name;
    ++programs;
  }
  EXPECT_GE(programs, 10);
}

}  // namespace
}  // namespace chainmail::render
