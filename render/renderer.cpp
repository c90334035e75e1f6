#include "render/renderer.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "render/gl.hpp"
#include "render/image.hpp"
#include "render/mesh.hpp"

namespace chainmail::render {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

struct Material {
  const char* name;
  float r, g, b;
};
constexpr Material kMaterials[] = {
    {"steel", 0.62f, 0.64f, 0.67f},   {"silver", 0.86f, 0.87f, 0.89f},
    {"gold", 1.0f, 0.77f, 0.34f},     {"copper", 0.95f, 0.55f, 0.38f},
    {"brass", 0.88f, 0.74f, 0.42f},   {"bronze", 0.76f, 0.52f, 0.31f},
    {"titanium", 0.56f, 0.54f, 0.51f}};
// index = the cloth shader's u_mode
constexpr const char* kClothShaders[] = {"blinn_phong", "texture", "bump", "displacement",
                                         "mirror"};
constexpr int kDisplacementSubdivisions = 4;

// the environment: sun direction (also the key light), face sizes, blur tap spacing
const Vector3d kSunDirection = Vector3d(0.45, 0.75, 0.5).normalized();
constexpr int kSkyFaceSize = 256;
constexpr int kBlurredFaceSize = 128;
constexpr float kBlurSpread = 0.018f;

// ---- shader files ------------------------------------------------------------------------------

std::string executable_dir() {
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string() : exe.parent_path().string();
}

// directories searched for shader files, in order
std::vector<std::string> shader_dirs(const RenderSettings& settings) {
  if (!settings.shader_dir.empty()) return {settings.shader_dir};
  std::vector<std::string> dirs;
  if (const std::string exe = executable_dir(); !exe.empty()) dirs.push_back(exe + "/shaders");
  if (const char* env = std::getenv("CHAINMAIL_SHADER_DIR"); env && *env) dirs.push_back(env);
  return dirs;
}

class ShaderFiles {
 public:
  explicit ShaderFiles(std::vector<std::string> dirs) : dirs_(std::move(dirs)) {}

  // the file's text with `#include "name"` lines replaced by that file (one level is all we use)
  std::string load(const std::string& name, int depth = 0) const {
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

 private:
  std::string read(const std::string& name) const {
    for (const std::string& dir : dirs_) {
      std::ifstream file(dir + "/" + name, std::ios::binary);
      if (file) return std::string(std::istreambuf_iterator<char>(file), {});
    }
    std::string searched;
    for (const std::string& dir : dirs_) searched += (searched.empty() ? "" : ", ") + dir;
    if (searched.empty()) searched = "none: set RenderSettings::shader_dir or CHAINMAIL_SHADER_DIR";
    throw RenderError("render: missing shader file '" + name + "' (searched: " + searched + ")");
  }
  std::vector<std::string> dirs_;
};

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

// `defines` go right after the #version line; variants are separate programs because a uniform
// branch is not free on llvmpipe (both sides of a ?: get evaluated)
std::string with_defines(const std::string& source, const std::string& defines) {
  if (defines.empty()) return source;
  const auto end_of_version = source.find('\n');
  if (end_of_version == std::string::npos) return source;
  return source.substr(0, end_of_version + 1) + defines + source.substr(end_of_version + 1);
}

GLuint build_program(const GlApi& gl, const ShaderFiles& files, const std::string& vertex,
                     const std::string& fragment, const std::string& defines = "") {
  const GLuint vs = compile_shader(gl, GL_VERTEX_SHADER, files.load(vertex), vertex);
  GLuint fs = 0;
  try {
    fs = compile_shader(gl, GL_FRAGMENT_SHADER, with_defines(files.load(fragment), defines),
                        fragment);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
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
    throw RenderError("render: program " + vertex + " + " + fragment + " does not link: " + log);
  }
  return program;
}

// ---- the procedural environment ---------------------------------------------------------------

// sky gradient, sun, hazy horizon with a line of hills, darker ground; linear HDR values
Vector3f sky_color(const Vector3d& direction) {
  const Vector3d d = direction.normalized();
  const double e = d.y();
  const double azimuth = std::atan2(d.z(), d.x());
  const Vector3d horizon(0.80, 0.84, 0.88), zenith(0.20, 0.40, 0.78);
  const Vector3d ground_near(0.42, 0.39, 0.35), ground_far(0.18, 0.16, 0.14);
  Vector3d c;
  if (e >= 0.0) {
    c = horizon + (zenith - horizon) * std::pow(e, 0.45);
  } else {
    c = ground_near + (ground_far - ground_near) * std::pow(-e, 0.4);
  }
  const double hills =
      0.035 + 0.025 * std::sin(3.0 * azimuth) + 0.012 * std::sin(7.0 * azimuth + 1.0);
  if (e >= 0.0 && e < hills) c = Vector3d(0.30, 0.34, 0.30);
  c += Vector3d(1.0, 0.95, 0.85) * 0.22 * std::exp(-std::abs(e) * 30.0);
  const double s = std::max(d.dot(kSunDirection), 0.0);
  c += Vector3d(1.0, 0.92, 0.75) * (0.35 * std::pow(s, 40.0) + 6.0 * std::pow(s, 900.0));
  if (s > std::cos(0.035)) c += Vector3d(20.0, 19.0, 17.0);
  return c.cast<float>();
}

// direction of texel (s, t) in [-1, 1] on cubemap face 0..5 (+X, -X, +Y, -Y, +Z, -Z)
Vector3d cube_direction(int face, double a, double b) {
  switch (face) {
    case 0:
      return {1.0, -b, -a};
    case 1:
      return {-1.0, -b, a};
    case 2:
      return {a, 1.0, b};
    case 3:
      return {a, -1.0, -b};
    case 4:
      return {a, -b, 1.0};
    default:
      return {-a, -b, -1.0};
  }
}

// ---- the renderer ----------------------------------------------------------------------------

constexpr int kInstanceFloats = 7;  // centre (3), quaternion x, y, z, w (4)

class GlRenderer final : public Renderer {
 public:
  GlRenderer(const RenderSettings& settings, std::unique_ptr<GlContext> context)
      : settings_(settings), context_(std::move(context)), gl_(context_->gl()) {}

  ~GlRenderer() override {
    for (GLuint program : {sky_program_, prefilter_program_, ring_program_, impostor_program_,
                           flat_program_, cloth_program_}) {
      if (program) gl_.DeleteProgram(program);
    }
    const GLuint textures[] = {sky_texture_, blurred_texture_};
    gl_.DeleteTextures(2, textures);
    const GLuint framebuffers[] = {msaa_fbo_, resolve_fbo_};
    gl_.DeleteFramebuffers(2, framebuffers);
    const GLuint renderbuffers[] = {msaa_color_, msaa_depth_, resolve_color_, resolve_depth_};
    gl_.DeleteRenderbuffers(4, renderbuffers);
    gl_.DeleteVertexArrays(kLodLevels, lod_vao_);
    const GLuint vaos[] = {empty_vao_, flat_vao_, cloth_vao_};
    gl_.DeleteVertexArrays(3, vaos);
    gl_.DeleteBuffers(kLodLevels, lod_vbo_);
    gl_.DeleteBuffers(kLodLevels, lod_ibo_);
    const GLuint buffers[] = {instance_vbo_, flat_vbo_, flat_ibo_, cloth_vbo_, cloth_ibo_};
    gl_.DeleteBuffers(5, buffers);
  }

  void setup() {
    // settings that must name something we have
    const auto material =
        std::find_if(std::begin(kMaterials), std::end(kMaterials),
                     [&](const Material& m) { return settings_.material == m.name; });
    if (material == std::end(kMaterials)) {
      throw RenderError("render: unknown material '" + settings_.material + "' (" +
                        join(material_names()) + ")");
    }
    material_ = Vector3f(material->r, material->g, material->b);
    const auto cloth =
        std::find(std::begin(kClothShaders), std::end(kClothShaders), settings_.cloth_shader);
    if (cloth == std::end(kClothShaders)) {
      throw RenderError("render: unknown cloth shader '" + settings_.cloth_shader + "' (" +
                        join(cloth_shader_names()) + ")");
    }
    cloth_mode_ = static_cast<int>(cloth - std::begin(kClothShaders));
    if (!(settings_.lod_scale >= 0.0) || !std::isfinite(settings_.lod_scale)) {
      throw RenderError("render: lod_scale must be a finite number >= 0");
    }
    if (settings_.width < 1 || settings_.height < 1 || settings_.width > 16384 ||
        settings_.height > 16384) {
      throw RenderError("render: image size " + std::to_string(settings_.width) + "x" +
                        std::to_string(settings_.height) + " out of range");
    }

    // every program up front, so a missing or broken shader fails here and not mid-run
    const ShaderFiles files(shader_dirs(settings_));
    sky_program_ = build_program(gl_, files, "fullscreen.vert", "sky.frag");
    prefilter_program_ = build_program(gl_, files, "fullscreen.vert", "prefilter.frag");
    const std::string blur = settings_.live_blur ? "#define LIVE_BLUR 1\n" : "";
    ring_program_ = build_program(gl_, files, "ring.vert", "ring.frag", blur);
    impostor_program_ = build_program(gl_, files, "ring_impostor.vert", "ring_impostor.frag", blur);
    flat_program_ = build_program(gl_, files, "flat.vert", "flat.frag");
    cloth_program_ = build_program(gl_, files, "cloth.vert", "cloth.frag");

    renderer_name_ = text(GL_RENDERER) + " / " + text(GL_VERSION);
    gl_.GenVertexArrays(1, &empty_vao_);
    make_framebuffers();
    make_environment();
    make_buffers();
    gl_.Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    check_gl("setting up");
  }

  Image render(const Scene& scene, const Weave& weave, const std::vector<Panel>& panels) override {
    const auto start = std::chrono::steady_clock::now();
    stats_ = FrameStats{};
    if (panels.empty()) throw RenderError("render: no panels to draw");

    // one camera for all panels: the scene's, or framing every panel's fabric
    std::vector<const RingFrame*> frames;
    for (const Panel& panel : panels) frames.push_back(panel.frame);
    const Bounds bounds = frame_bounds(frames);
    const CameraView camera =
        make_camera(scene, bounds, static_cast<double>(settings_.width) / settings_.height);
    // float positions relative to the camera target keep precision far from the world origin
    origin_ = camera.target;
    view_projection_ = camera.view_projection(origin_);
    const double fabric_radius =
        std::max(bounds.radius(), 0.0) + scene.ring.centre_radius + scene.ring.wire_radius;
    upload_scene_mesh(scene, bounds.empty() ? camera.target : bounds.center(), fabric_radius);
    ensure_torus_meshes(scene.ring);

    std::vector<Image> images;
    images.reserve(panels.size());
    for (const Panel& panel : panels) {
      images.push_back(render_panel(scene, weave, camera, panel));
    }
    Image result = images.size() == 1 ? std::move(images.front()) : compose_horizontal(images);
    stats_.ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
  }

  const FrameStats& last_stats() const override { return stats_; }
  std::string context_name() const override { return context_->name(); }
  std::string gl_renderer() const override { return renderer_name_; }

 private:
  static std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
    return out;
  }
  std::string text(GLenum name) const {
    const auto* value = reinterpret_cast<const char*>(gl_.GetString(name));
    return value ? value : "?";
  }
  void check_gl(const char* what) const {
    if (const GLenum error = gl_.GetError(); error != GL_NO_ERROR) {
      char code[16];
      std::snprintf(code, sizeof(code), "0x%04x", error);
      throw RenderError(std::string("render: GL error ") + code + " while " + what);
    }
  }
  GLint uniform(GLuint program, const char* name) const {
    return gl_.GetUniformLocation(program, name);
  }

  // multisampled target (resolved by a blit) and the single-sampled target that is read back
  void make_framebuffers() {
    const int w = settings_.width, h = settings_.height;
    GLint max_samples = 1;
    gl_.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
    samples_ = std::clamp(settings_.samples, 1, std::max(max_samples, 1));

    gl_.GenFramebuffers(1, &resolve_fbo_);
    gl_.GenRenderbuffers(1, &resolve_color_);
    gl_.GenRenderbuffers(1, &resolve_depth_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, resolve_color_);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, resolve_depth_);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                resolve_color_);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                resolve_depth_);
    check_framebuffer("the resolve target");

    if (samples_ > 1) {
      gl_.GenFramebuffers(1, &msaa_fbo_);
      gl_.GenRenderbuffers(1, &msaa_color_);
      gl_.GenRenderbuffers(1, &msaa_depth_);
      gl_.BindRenderbuffer(GL_RENDERBUFFER, msaa_color_);
      gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, w, h);
      gl_.BindRenderbuffer(GL_RENDERBUFFER, msaa_depth_);
      gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, w, h);
      gl_.BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
      gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  msaa_color_);
      gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                  msaa_depth_);
      check_framebuffer("the multisampled target");
    }
    check_gl("creating framebuffers");
  }

  void check_framebuffer(const char* what) const {
    if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw RenderError(std::string("render: incomplete framebuffer for ") + what);
    }
  }

  // the sharp skybox from sky_color(), then its blurred copy rendered once by prefilter.frag
  void make_environment() {
    gl_.GenTextures(1, &sky_texture_);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, sky_texture_);
    std::vector<float> face(static_cast<size_t>(kSkyFaceSize) * kSkyFaceSize * 4);
    for (int f = 0; f < 6; ++f) {
      for (int t = 0; t < kSkyFaceSize; ++t) {
        for (int s = 0; s < kSkyFaceSize; ++s) {
          const double a = (s + 0.5) / kSkyFaceSize * 2.0 - 1.0;
          const double b = (t + 0.5) / kSkyFaceSize * 2.0 - 1.0;
          const Vector3f c = sky_color(cube_direction(f, a, b));
          float* p = &face[(static_cast<size_t>(t) * kSkyFaceSize + s) * 4];
          p[0] = c.x(), p[1] = c.y(), p[2] = c.z(), p[3] = 1.0f;
        }
      }
      gl_.TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, kSkyFaceSize, kSkyFaceSize,
                     0, GL_RGBA, GL_FLOAT, face.data());
    }
    set_cube_sampling();

    gl_.GenTextures(1, &blurred_texture_);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, blurred_texture_);
    for (int f = 0; f < 6; ++f) {
      gl_.TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, kBlurredFaceSize,
                     kBlurredFaceSize, 0, GL_RGBA, GL_FLOAT, nullptr);
    }
    set_cube_sampling();

    GLuint fbo = 0;
    gl_.GenFramebuffers(1, &fbo);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl_.Viewport(0, 0, kBlurredFaceSize, kBlurredFaceSize);
    gl_.Disable(GL_DEPTH_TEST);
    gl_.UseProgram(prefilter_program_);
    gl_.ActiveTexture(GL_TEXTURE0);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, sky_texture_);
    gl_.Uniform1i(uniform(prefilter_program_, "u_env"), 0);
    gl_.Uniform1f(uniform(prefilter_program_, "u_size"), static_cast<float>(kBlurredFaceSize));
    gl_.Uniform1f(uniform(prefilter_program_, "u_spread"), kBlurSpread);
    gl_.BindVertexArray(empty_vao_);
    for (int f = 0; f < 6; ++f) {
      gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                               GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, blurred_texture_, 0);
      check_framebuffer("the environment prefilter");
      gl_.Uniform1i(uniform(prefilter_program_, "u_face"), f);
      gl_.DrawArrays(GL_TRIANGLES, 0, 3);
    }
    gl_.Finish();
    gl_.DeleteFramebuffers(1, &fbo);
    check_gl("building the environment map");
  }

  void set_cube_sampling() {
    gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }

  // vertex arrays: one per torus level (mesh + per-instance attributes), flat, cloth
  void make_buffers() {
    gl_.GenBuffers(1, &instance_vbo_);
    gl_.GenVertexArrays(kLodLevels, lod_vao_);
    gl_.GenBuffers(kLodLevels, lod_vbo_);
    gl_.GenBuffers(kLodLevels, lod_ibo_);
    for (int level = 0; level < kLodLevels; ++level) {
      gl_.BindVertexArray(lod_vao_[level]);
      gl_.BindBuffer(GL_ARRAY_BUFFER, lod_vbo_[level]);
      gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, lod_ibo_[level]);
      attribute(0, 3, 6, 0);
      attribute(1, 3, 6, 3);
      gl_.BindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
      attribute(2, 3, kInstanceFloats, 0);
      attribute(3, 4, kInstanceFloats, 3);
      gl_.VertexAttribDivisor(2, 1);
      gl_.VertexAttribDivisor(3, 1);
    }
    gl_.GenVertexArrays(1, &flat_vao_);
    gl_.GenBuffers(1, &flat_vbo_);
    gl_.GenBuffers(1, &flat_ibo_);
    gl_.BindVertexArray(flat_vao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, flat_vbo_);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, flat_ibo_);
    attribute(0, 3, 10, 0);
    attribute(1, 3, 10, 3);
    attribute(2, 4, 10, 6);
    gl_.GenVertexArrays(1, &cloth_vao_);
    gl_.GenBuffers(1, &cloth_vbo_);
    gl_.GenBuffers(1, &cloth_ibo_);
    gl_.BindVertexArray(cloth_vao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, cloth_vbo_);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, cloth_ibo_);
    attribute(0, 3, 8, 0);
    attribute(1, 3, 8, 3);
    attribute(2, 2, 8, 6);
    gl_.BindVertexArray(0);
    check_gl("creating vertex arrays");
  }

  // float attribute `index` of `size` floats at float `offset` in a `stride`-float vertex
  void attribute(GLuint index, int size, int stride, size_t offset) {
    gl_.EnableVertexAttribArray(index);
    gl_.VertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, stride * sizeof(float),
                            reinterpret_cast<const void*>(offset * sizeof(float)));
  }

  // the torus levels depend on the ring's a and c only: rebuilt when those change (the last
  // level's box is the unit box, sized in its vertex shader)
  void ensure_torus_meshes(const RingGeometry& ring) {
    if (ring.wire_radius == torus_a_ && ring.centre_radius == torus_c_) return;
    torus_a_ = ring.wire_radius, torus_c_ = ring.centre_radius;
    for (int level = 0; level < kLodLevels; ++level) {
      const Mesh mesh = level < kMeshLevels ? torus_mesh(torus_a_, torus_c_, kLodSegments[level][0],
                                                         kLodSegments[level][1])
                                            : box_mesh();
      gl_.BindVertexArray(lod_vao_[level]);
      gl_.BindBuffer(GL_ARRAY_BUFFER, lod_vbo_[level]);
      gl_.BufferData(GL_ARRAY_BUFFER, mesh.vertices.size() * sizeof(float), mesh.vertices.data(),
                     GL_STATIC_DRAW);
      gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(std::uint32_t),
                     mesh.indices.data(), GL_STATIC_DRAW);
      lod_index_count_[level] = static_cast<int>(mesh.indices.size());
    }
    gl_.BindVertexArray(0);
  }

  void upload_scene_mesh(const Scene& scene, const Vector3d& focus, double fabric_radius) {
    const Mesh mesh = scene_mesh(scene, origin_, focus, 4.0 * fabric_radius);
    flat_index_count_ = static_cast<int>(mesh.indices.size());
    // checker tiles: the largest of 1, 2, 5 x 10^k up to half the fabric's radius
    const double decade = std::pow(10.0, std::floor(std::log10(0.5 * fabric_radius)));
    checker_ = static_cast<float>(decade * (0.5 * fabric_radius >= 5 * decade   ? 5.0
                                            : 0.5 * fabric_radius >= 2 * decade ? 2.0
                                                                                : 1.0));
    if (flat_index_count_ == 0) return;
    gl_.BindVertexArray(flat_vao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, flat_vbo_);
    gl_.BufferData(GL_ARRAY_BUFFER, mesh.vertices.size() * sizeof(float), mesh.vertices.data(),
                   GL_STREAM_DRAW);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(std::uint32_t),
                   mesh.indices.data(), GL_STREAM_DRAW);
    gl_.BindVertexArray(0);
  }

  void set_common_uniforms(GLuint program, const CameraView& camera) {
    gl_.UseProgram(program);
    gl_.UniformMatrix4fv(uniform(program, "u_view_projection"), 1, GL_FALSE,
                         view_projection_.data());
    const Vector3d eye = camera.eye - origin_;
    gl_.Uniform3f(uniform(program, "u_eye"), static_cast<float>(eye.x()),
                  static_cast<float>(eye.y()), static_cast<float>(eye.z()));
    gl_.Uniform3f(uniform(program, "u_light_dir"), static_cast<float>(kSunDirection.x()),
                  static_cast<float>(kSunDirection.y()), static_cast<float>(kSunDirection.z()));
    gl_.Uniform3f(uniform(program, "u_material"), material_.x(), material_.y(), material_.z());
    gl_.Uniform1i(uniform(program, "u_env"), 0);
    gl_.Uniform1i(uniform(program, "u_env_blurred"), 1);
  }

  Image render_panel(const Scene& scene, const Weave& weave, const CameraView& camera,
                     const Panel& panel) {
    const int w = settings_.width, h = settings_.height;
    gl_.BindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? msaa_fbo_ : resolve_fbo_);
    gl_.Viewport(0, 0, w, h);
    gl_.DepthMask(GL_TRUE);
    gl_.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl_.ActiveTexture(GL_TEXTURE0);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, sky_texture_);
    gl_.ActiveTexture(GL_TEXTURE1);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, blurred_texture_);

    // ground, support and colliders
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    if (flat_index_count_ > 0) {
      set_common_uniforms(flat_program_, camera);
      gl_.Uniform3f(uniform(flat_program_, "u_origin"), static_cast<float>(origin_.x()),
                    static_cast<float>(origin_.y()), static_cast<float>(origin_.z()));
      gl_.Uniform1f(uniform(flat_program_, "u_checker"), checker_);
      gl_.BindVertexArray(flat_vao_);
      gl_.DrawElements(GL_TRIANGLES, flat_index_count_, GL_UNSIGNED_INT, nullptr);
    }

    // the fabric: cloth, or the rings' meshes (the ray-cast rings come after the resolve)
    int raycast_rings = 0;
    if (panel.frame) {
      if (!panel.as_cloth || !draw_cloth(*panel.frame, weave, camera)) {
        raycast_rings = draw_ring_meshes(scene, *panel.frame, camera);
      }
    }

    // sky after the opaque things, only where nothing was drawn (at the far plane), so it costs
    // no hidden pixels; before the ray-cast rings, whose antialiased edges blend over it
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LEQUAL);
    gl_.DepthMask(GL_FALSE);
    gl_.Disable(GL_CULL_FACE);
    gl_.UseProgram(sky_program_);
    const double tan_y = std::tan(0.5 * camera.fov_y_rad), tan_x = tan_y * camera.aspect;
    Eigen::Matrix3f ray_basis;
    ray_basis.col(0) = (camera.right() * tan_x).cast<float>();
    ray_basis.col(1) = (camera.true_up() * tan_y).cast<float>();
    ray_basis.col(2) = camera.forward().cast<float>();
    gl_.UniformMatrix3fv(uniform(sky_program_, "u_ray_basis"), 1, GL_FALSE, ray_basis.data());
    gl_.Uniform1i(uniform(sky_program_, "u_env"), 0);
    gl_.BindVertexArray(empty_vao_);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);

    gl_.DepthMask(GL_TRUE);
    gl_.BindVertexArray(0);

    // resolve the samples (depth too when ray-cast rings are still to be depth-tested against
    // them), then the ray-cast rings into the single-sampled target
    if (samples_ > 1) {
      gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
      gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
      gl_.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      if (raycast_rings > 0) {
        gl_.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
      }
    }
    if (raycast_rings > 0) draw_raycast_rings(camera);
    gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
    gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
    Image image;
    image.width = w, image.height = h;
    image.rgba.resize(static_cast<size_t>(w) * h * 4);
    readback_.resize(image.rgba.size());
    gl_.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, readback_.data());
    check_gl("drawing a panel");
    const size_t row = static_cast<size_t>(w) * 4;
    for (int y = 0; y < h; ++y) {
      std::copy_n(&readback_[(h - 1 - y) * row], row, &image.rgba[y * row]);
    }

    if (settings_.labels) {
      std::string label = panel.label;
      char buffer[96];
      if (panel.frame) {
        std::snprintf(buffer, sizeof(buffer), "  t = %.3f s", panel.frame->t);
        label += buffer;
      }
      if (panel.ms_per_step >= 0.0) {
        std::snprintf(buffer, sizeof(buffer), "  %.3f ms/step", panel.ms_per_step);
        label += buffer;
      }
      draw_label(image, label);
    }
    return image;
  }

  // instanced tori: rings sorted into levels of detail by on-screen size and culled against the
  // view frustum. The mesh levels are drawn front to back (cheaper fragments through the early
  // depth test); returns how many rings are left for the ray-cast level.
  int draw_ring_meshes(const Scene& scene, const RingFrame& frame, const CameraView& camera) {
    const Vector3d forward = camera.forward(), right = camera.right(), up = camera.true_up();
    const double radius = scene.ring.centre_radius + scene.ring.wire_radius;
    const double focal = camera.focal_pixels(settings_.height);
    const double tan_y = std::tan(0.5 * camera.fov_y_rad), tan_x = tan_y * camera.aspect;
    const double slack_x = radius * std::sqrt(1.0 + tan_x * tan_x);
    const double slack_y = radius * std::sqrt(1.0 + tan_y * tan_y);

    for (auto& bucket : buckets_) bucket.clear();
    for (int ring = 0; ring < frame.size(); ++ring) {
      const Vector3d p = frame.position.col(ring);
      const Eigen::Vector4d q = frame.orientation.col(ring);
      if (!p.allFinite() || !q.allFinite() || q.norm() < 1e-12) continue;
      const Vector3d relative = p - camera.eye;
      const double depth = relative.dot(forward);
      if (depth + radius < camera.near_plane || depth - radius > camera.far_plane) continue;
      if (std::abs(relative.dot(right)) - depth * tan_x > slack_x) continue;
      if (std::abs(relative.dot(up)) - depth * tan_y > slack_y) continue;
      const double pixels = 2.0 * radius * focal / std::max(depth, 1e-9);
      const int level = settings_.lod ? lod_for_pixels(settings_.lod_scale * pixels) : 0;
      buckets_[level].push_back({depth, ring});
    }

    // sort: front to back for the meshes, back to front for the blended ray-cast level
    instance_data_.clear();
    for (int level = 0; level < kLodLevels; ++level) {
      auto& bucket = buckets_[level];
      if (level < kMeshLevels) {
        std::sort(bucket.begin(), bucket.end());
      } else {
        std::sort(bucket.begin(), bucket.end(), std::greater<>());
      }
      level_offsets_[level + 1] = level_offsets_[level] + static_cast<int>(bucket.size());
      for (const auto& [depth, ring] : bucket) {
        const Vector3d p = frame.position.col(ring) - origin_;
        const Eigen::Vector4d q = frame.orientation.col(ring).normalized();  // w, x, y, z
        instance_data_.insert(
            instance_data_.end(),
            {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
             static_cast<float>(q[1]), static_cast<float>(q[2]), static_cast<float>(q[3]),
             static_cast<float>(q[0])});
      }
      stats_.per_lod[level] += static_cast<int>(bucket.size());
    }
    stats_.instances += level_offsets_[kLodLevels];
    if (level_offsets_[kLodLevels] == 0) return 0;

    // one upload per frame (orphaning the old store), then one draw per level
    gl_.BindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
    const auto bytes = static_cast<GLsizeiptr>(instance_data_.size() * sizeof(float));
    gl_.BufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_STREAM_DRAW);
    gl_.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, instance_data_.data());

    set_common_uniforms(ring_program_, camera);
    gl_.Uniform1f(uniform(ring_program_, "u_spread"), kBlurSpread);
    gl_.Enable(GL_CULL_FACE);
    gl_.CullFace(GL_BACK);
    for (int level = 0; level < kMeshLevels; ++level) draw_level(level);
    gl_.Disable(GL_CULL_FACE);
    return level_offsets_[kLodLevels] - level_offsets_[kMeshLevels];
  }

  // the last level: bounding boxes, the torus ray-cast in each. Drawn single-sampled after the
  // resolve, back to front and blended by the coverage the shader computes, so these rings are
  // antialiased without multisampling (whose cost on a software rasterizer grows with the number
  // of tiny primitives, not with pixels)
  void draw_raycast_rings(const CameraView& camera) {
    gl_.BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    gl_.DepthMask(GL_TRUE);
    gl_.Enable(GL_BLEND);
    gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // alpha stays 1
    set_common_uniforms(impostor_program_, camera);
    gl_.Uniform1f(uniform(impostor_program_, "u_spread"), kBlurSpread);
    gl_.Uniform2f(uniform(impostor_program_, "u_torus"), static_cast<float>(torus_a_),
                  static_cast<float>(torus_c_));
    gl_.Uniform1f(uniform(impostor_program_, "u_pixel_angle"),
                  static_cast<float>(1.0 / camera.focal_pixels(settings_.height)));
    gl_.Enable(GL_CULL_FACE);
    gl_.CullFace(GL_BACK);
    draw_level(kMeshLevels);
    gl_.Disable(GL_CULL_FACE);
    gl_.Disable(GL_BLEND);
    gl_.BindVertexArray(0);
  }

  // one instanced draw of level `level`'s mesh for that level's instances
  void draw_level(int level) {
    const int count = level_offsets_[level + 1] - level_offsets_[level];
    if (count == 0) return;
    gl_.BindVertexArray(lod_vao_[level]);
    gl_.BindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
    const size_t first = static_cast<size_t>(level_offsets_[level]) * kInstanceFloats;
    attribute(2, 3, kInstanceFloats, first);
    attribute(3, 4, kInstanceFloats, first + 3);
    gl_.DrawElementsInstanced(GL_TRIANGLES, lod_index_count_[level], GL_UNSIGNED_INT, nullptr,
                              count);
  }

  // the cloth baseline's look; false when the weave has no quads (a chain): draw rings instead
  bool draw_cloth(const RingFrame& frame, const Weave& weave, const CameraView& camera) {
    const bool displace = cloth_mode_ == 3;
    const Mesh mesh = cloth_mesh(frame, weave, displace ? kDisplacementSubdivisions : 1, origin_);
    if (mesh.indices.empty()) return false;
    gl_.BindVertexArray(cloth_vao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, cloth_vbo_);
    gl_.BufferData(GL_ARRAY_BUFFER, mesh.vertices.size() * sizeof(float), mesh.vertices.data(),
                   GL_STREAM_DRAW);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(std::uint32_t),
                   mesh.indices.data(), GL_STREAM_DRAW);
    set_common_uniforms(cloth_program_, camera);
    gl_.Uniform1i(uniform(cloth_program_, "u_mode"), cloth_mode_);
    gl_.Uniform1f(uniform(cloth_program_, "u_bump"), 0.002f);
    gl_.Uniform1f(uniform(cloth_program_, "u_displacement"),
                  displace ? static_cast<float>(2.0 * torus_a_) : 0.0f);
    gl_.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh.indices.size()), GL_UNSIGNED_INT,
                     nullptr);
    stats_.instances += frame.size();
    return true;
  }

  RenderSettings settings_;
  std::unique_ptr<GlContext> context_;
  const GlApi& gl_;
  std::string renderer_name_;
  FrameStats stats_;
  Vector3f material_;
  int cloth_mode_ = 0;
  int samples_ = 1;

  GLuint sky_program_ = 0, prefilter_program_ = 0, ring_program_ = 0, impostor_program_ = 0,
         flat_program_ = 0, cloth_program_ = 0;
  GLuint sky_texture_ = 0, blurred_texture_ = 0;
  GLuint msaa_fbo_ = 0, msaa_color_ = 0, msaa_depth_ = 0;
  GLuint resolve_fbo_ = 0, resolve_color_ = 0, resolve_depth_ = 0;
  GLuint empty_vao_ = 0, flat_vao_ = 0, flat_vbo_ = 0, flat_ibo_ = 0;
  GLuint cloth_vao_ = 0, cloth_vbo_ = 0, cloth_ibo_ = 0;
  GLuint lod_vao_[kLodLevels] = {}, lod_vbo_[kLodLevels] = {}, lod_ibo_[kLodLevels] = {};
  GLuint instance_vbo_ = 0;
  int lod_index_count_[kLodLevels] = {};
  int flat_index_count_ = 0;
  float checker_ = 0.1f;
  double torus_a_ = -1.0, torus_c_ = -1.0;

  // per-frame scratch, kept to avoid reallocations
  Vector3d origin_ = Vector3d::Zero();
  Eigen::Matrix4f view_projection_ = Eigen::Matrix4f::Identity();
  std::array<std::vector<std::pair<double, int>>, kLodLevels> buckets_;
  std::array<int, kLodLevels + 1> level_offsets_{};  // first instance of each level, then the end
  std::vector<float> instance_data_;
  std::vector<unsigned char> readback_;
};

}  // namespace

Renderer::~Renderer() = default;

std::unique_ptr<Renderer> Renderer::create(const RenderSettings& settings) {
  auto context = create_context({settings.context, settings.osmesa_library, settings.egl_library});
  auto renderer = std::make_unique<GlRenderer>(settings, std::move(context));
  renderer->setup();
  return renderer;
}

std::vector<std::string> material_names() {
  std::vector<std::string> names;
  for (const Material& m : kMaterials) names.emplace_back(m.name);
  return names;
}

std::vector<std::string> cloth_shader_names() {
  return {std::begin(kClothShaders), std::end(kClothShaders)};
}

}  // namespace chainmail::render
