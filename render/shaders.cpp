#include "render/shaders.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "render/types.hpp"

namespace chainmail::render {
namespace {

std::string executable_dir() {
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string() : exe.parent_path().string();
}

GLuint compile_shader(const GlApi& gl, GLenum type, const std::string& source,
                      const std::string& name) {
  const GLuint shader = gl.CreateShader(type);
  const char* text = source.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    gl.GetShaderInfoLog(shader, sizeof(log), nullptr, log);
    gl.DeleteShader(shader);
    throw RenderError("render: shader " + name + " does not compile: " + log);
  }
  return shader;
}

GLuint link_program(const GlApi& gl, GLuint vs, GLuint fs, const std::string& name) {
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vs);
  gl.AttachShader(program, fs);
  gl.LinkProgram(program);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = 0;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    gl.GetProgramInfoLog(program, sizeof(log), nullptr, log);
    gl.DeleteProgram(program);
    throw RenderError("render: program " + name + " does not link: " + log);
  }
  return program;
}

}  // namespace

std::vector<std::string> shader_dirs(const std::string& shader_dir) {
  if (!shader_dir.empty()) return {shader_dir};
  std::vector<std::string> dirs;
  if (const std::string exe = executable_dir(); !exe.empty()) dirs.push_back(exe + "/shaders");
  if (const char* env = std::getenv("CHAINMAIL_SHADER_DIR"); env && *env) dirs.push_back(env);
  return dirs;
}

std::string ShaderFiles::load(const std::string& name, int depth) const {
  std::istringstream in(read(name));
  std::string line, out;
  while (std::getline(in, line)) {
    const auto first = line.find('"'), last = line.rfind('"');
    if (line.rfind("#include", 0) == 0 && first != std::string::npos && last > first) {
      if (depth > 4) throw RenderError("render: shader includes nested too deep in " + name);
      out += load(line.substr(first + 1, last - first - 1), depth + 1);
    } else {
      out += line;
      out += '\n';
    }
  }
  return out;
}

std::string ShaderFiles::read(const std::string& name) const {
  for (const std::string& dir : dirs_) {
    std::ifstream file(dir + "/" + name, std::ios::binary);
    if (file) return std::string(std::istreambuf_iterator<char>(file), {});
  }
  std::string searched;
  for (const std::string& dir : dirs_) searched += (searched.empty() ? "" : ", ") + dir;
  if (searched.empty()) searched = "none: set RenderSettings::shader_dir or CHAINMAIL_SHADER_DIR";
  throw RenderError("render: missing shader file '" + name + "' (searched: " + searched + ")");
}

std::string with_defines(const std::string& source, const std::string& defines) {
  if (defines.empty()) return source;
  const auto end_of_version = source.find('\n');
  if (end_of_version == std::string::npos) return source;
  return source.substr(0, end_of_version + 1) + defines + source.substr(end_of_version + 1);
}

GLuint build_program(const GlApi& gl, const ShaderFiles& files, const std::string& vertex,
                     const std::string& fragment, const std::string& defines) {
  const GLuint vs = compile_shader(gl, GL_VERTEX_SHADER, files.load(vertex), vertex);
  GLuint fs = 0;
  try {
    fs = compile_shader(gl, GL_FRAGMENT_SHADER, with_defines(files.load(fragment), defines),
                        fragment);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
  return link_program(gl, vs, fs, vertex + " + " + fragment);
}

}  // namespace chainmail::render
