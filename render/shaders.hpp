// Shader files and programs: GLSL sources are read from the shader folders with a small
// `#include "name"` mechanism, then compiled and linked into programs.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "render/gl.hpp"

namespace chainmail::render {

// folders searched for shader files, in order: `shader_dir` alone when set, otherwise shaders/
// beside the executable, then $CHAINMAIL_SHADER_DIR
std::vector<std::string> shader_dirs(const std::string& shader_dir);

class ShaderFiles {
 public:
  explicit ShaderFiles(std::vector<std::string> dirs) : dirs_(std::move(dirs)) {}

  // the file's text with `#include "name"` lines replaced by that file (nested at most 5 deep);
  // throws RenderError naming the file and the folders searched when one is missing
  std::string load(const std::string& name, int depth = 0) const;

 private:
  std::string read(const std::string& name) const;
  std::vector<std::string> dirs_;
};

// `defines` go right after the #version line; variants are separate programs because a uniform
// branch is not free on llvmpipe (both sides of a ?: get evaluated)
std::string with_defines(const std::string& source, const std::string& defines);

// compiles and links vertex + fragment (with `defines`); throws RenderError with the GL log
GLuint build_program(const GlApi& gl, const ShaderFiles& files, const std::string& vertex,
                     const std::string& fragment, const std::string& defines = "");

}  // namespace chainmail::render
