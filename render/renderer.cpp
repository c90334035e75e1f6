#include "render/renderer.hpp"

#include <chrono>

#include "render/gl.hpp"
#include "render/image.hpp"
#include "render/mesh.hpp"
#include "render/scene_view.hpp"
#include "render/settings.hpp"
#include "render/shaders.hpp"
#include "render/sky.hpp"
#include "render/targets.hpp"

namespace chainmail::render {
namespace {

using Eigen::Vector3d;

// the GL side of the one rendering path: scene_view works out what to draw, this uploads and
// draws it
class GlRenderer final : public Renderer {
 public:
  GlRenderer(const RenderSettings& settings, std::unique_ptr<GlContext> context)
      : settings_(settings), context_(std::move(context)), gl_(context_->gl()) {}

  ~GlRenderer() override {
    for (GLuint program : {sky_program_, prefilter_program_, ring_program_, impostor_program_,
                           flat_program_, cloth_program_}) {
      if (program) gl_.DeleteProgram(program);
    }
    const GLuint textures[] = {sky_.sharp, sky_.blurred};
    gl_.DeleteTextures(2, textures);
    delete_panel_targets(gl_, targets_);
    gl_.DeleteVertexArrays(kLodLevels, lod_vao_);
    const GLuint vaos[] = {empty_vao_, flat_vao_, cloth_vao_};
    gl_.DeleteVertexArrays(3, vaos);
    gl_.DeleteBuffers(kLodLevels, lod_vbo_);
    gl_.DeleteBuffers(kLodLevels, lod_ibo_);
    const GLuint buffers[] = {instance_vbo_, flat_vbo_, flat_ibo_, cloth_vbo_, cloth_ibo_};
    gl_.DeleteBuffers(5, buffers);
  }

  void setup() {
    look_ = resolve_settings(settings_);  // settings that must name something we have
    build_programs();
    renderer_name_ = text(GL_RENDERER) + " / " + text(GL_VERSION);
    gl_.GenVertexArrays(1, &empty_vao_);
    targets_ = make_panel_targets(gl_, settings_.width, settings_.height, settings_.samples);
    sky_ = make_sky_textures(gl_, prefilter_program_, empty_vao_);
    make_buffers();
    gl_.Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    check_gl(gl_, "setting up");
  }

  Image render(const Scene& scene, const Weave& weave, const std::vector<Panel>& panels) override {
    const auto start = std::chrono::steady_clock::now();
    stats_ = FrameStats{};
    if (panels.empty()) throw RenderError("render: no panels to draw");

    // one camera for all panels: the scene's, or framing every panel's fabric
    std::vector<const RingFrame*> frames;
    for (const Panel& panel : panels) frames.push_back(panel.frame);
    const SharedView view =
        shared_view(scene, frames, static_cast<double>(settings_.width) / settings_.height,
                    settings_.view_from);
    // float positions relative to the camera target keep precision far from the world origin
    origin_ = view.origin;
    view_projection_ = view.camera.view_projection(origin_);
    checker_ = view.checker;
    upload_scene_mesh(scene, view.focus, view.fabric_radius);
    ensure_torus_meshes(scene.ring);

    std::vector<Image> images;
    images.reserve(panels.size());
    for (const Panel& panel : panels) {
      images.push_back(render_panel(scene, weave, view.camera, panel));
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
  std::string text(GLenum name) const {
    const auto* value = reinterpret_cast<const char*>(gl_.GetString(name));
    return value ? value : "?";
  }
  GLint uniform(GLuint program, const char* name) const {
    return gl_.GetUniformLocation(program, name);
  }

  // every program up front, so a missing or broken shader fails here and not mid-run
  void build_programs() {
    const ShaderFiles files(shader_dirs(settings_.shader_dir));
    sky_program_ = build_program(gl_, files, "fullscreen.vert", "sky.frag");
    prefilter_program_ = build_program(gl_, files, "fullscreen.vert", "prefilter.frag");
    const std::string blur = settings_.live_blur ? "#define LIVE_BLUR 1\n" : "";
    ring_program_ = build_program(gl_, files, "ring.vert", "ring.frag", blur);
    impostor_program_ = build_program(gl_, files, "ring_impostor.vert", "ring_impostor.frag", blur);
    flat_program_ = build_program(gl_, files, "flat.vert", "flat.frag");
    cloth_program_ = build_program(gl_, files, "cloth.vert", "cloth.frag");
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
    make_mesh_array(flat_vao_, flat_vbo_, flat_ibo_);
    attribute(0, 3, 10, 0);
    attribute(1, 3, 10, 3);
    attribute(2, 4, 10, 6);
    make_mesh_array(cloth_vao_, cloth_vbo_, cloth_ibo_);
    attribute(0, 3, 9, 0);
    attribute(1, 3, 9, 3);
    attribute(2, 2, 9, 6);
    attribute(3, 1, 9, 8);
    gl_.BindVertexArray(0);
    check_gl(gl_, "creating vertex arrays");
  }

  // a vertex array with its vertex and index buffers, left bound for its attributes
  void make_mesh_array(GLuint& vao, GLuint& vbo, GLuint& ibo) {
    gl_.GenVertexArrays(1, &vao);
    gl_.GenBuffers(1, &vbo);
    gl_.GenBuffers(1, &ibo);
    gl_.BindVertexArray(vao);
    gl_.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
  }

  // float attribute `index` of `size` floats at float `offset` in a `stride`-float vertex
  void attribute(GLuint index, int size, int stride, size_t offset) {
    gl_.EnableVertexAttribArray(index);
    gl_.VertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, stride * sizeof(float),
                            reinterpret_cast<const void*>(offset * sizeof(float)));
  }

  // vertices and indices into the bound vertex array's buffers
  void upload_mesh(GLuint vbo, const Mesh& mesh, GLenum usage) {
    gl_.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl_.BufferData(GL_ARRAY_BUFFER, mesh.vertices.size() * sizeof(float), mesh.vertices.data(),
                   usage);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(std::uint32_t),
                   mesh.indices.data(), usage);
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
      upload_mesh(lod_vbo_[level], mesh, GL_STATIC_DRAW);
      lod_index_count_[level] = static_cast<int>(mesh.indices.size());
    }
    gl_.BindVertexArray(0);
  }

  void upload_scene_mesh(const Scene& scene, const Vector3d& focus, double fabric_radius) {
    const Mesh mesh = scene_mesh(scene, origin_, focus, 4.0 * fabric_radius);
    flat_index_count_ = static_cast<int>(mesh.indices.size());
    if (flat_index_count_ == 0) return;
    gl_.BindVertexArray(flat_vao_);
    upload_mesh(flat_vbo_, mesh, GL_STREAM_DRAW);
    gl_.BindVertexArray(0);
  }

  void set_vector(GLuint program, const char* name, const Vector3d& v) {
    gl_.Uniform3f(uniform(program, name), static_cast<float>(v.x()), static_cast<float>(v.y()),
                  static_cast<float>(v.z()));
  }

  void set_common_uniforms(GLuint program, const CameraView& camera) {
    gl_.UseProgram(program);
    gl_.UniformMatrix4fv(uniform(program, "u_view_projection"), 1, GL_FALSE,
                         view_projection_.data());
    set_vector(program, "u_eye", camera.eye - origin_);
    set_vector(program, "u_light_dir", sun_direction());
    gl_.Uniform3f(uniform(program, "u_material"), look_.material.x(), look_.material.y(),
                  look_.material.z());
    gl_.Uniform1i(uniform(program, "u_env"), 0);
    gl_.Uniform1i(uniform(program, "u_env_blurred"), 1);
  }

  // one panel: opaque things multisampled, the sky behind them, the resolve, then the ray-cast
  // rings single-sampled, the read-back and the label
  Image render_panel(const Scene& scene, const Weave& weave, const CameraView& camera,
                     const Panel& panel) {
    begin_panel();
    draw_flat(camera);
    // the fabric: cloth, or the rings' meshes (the ray-cast rings come after the resolve)
    int raycast_rings = 0;
    if (panel.frame && (!panel.as_cloth || !draw_cloth(*panel.frame, weave, camera))) {
      raycast_rings = draw_ring_meshes(scene, *panel.frame, camera);
    }
    draw_sky(camera);
    resolve_samples(gl_, targets_, raycast_rings > 0);
    if (raycast_rings > 0) draw_raycast_rings(camera);
    Image image = read_panel(gl_, targets_, readback_);
    if (settings_.labels) draw_label(image, panel_label(panel));
    return image;
  }

  // the drawing target cleared to black, the environment bound to texture units 0 and 1
  void begin_panel() {
    gl_.BindFramebuffer(GL_FRAMEBUFFER, targets_.draw_fbo());
    gl_.Viewport(0, 0, settings_.width, settings_.height);
    gl_.DepthMask(GL_TRUE);
    gl_.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl_.ActiveTexture(GL_TEXTURE0);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, sky_.sharp);
    gl_.ActiveTexture(GL_TEXTURE1);
    gl_.BindTexture(GL_TEXTURE_CUBE_MAP, sky_.blurred);
  }

  // ground, support and colliders
  void draw_flat(const CameraView& camera) {
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    if (flat_index_count_ == 0) return;
    set_common_uniforms(flat_program_, camera);
    set_vector(flat_program_, "u_origin", origin_);
    gl_.Uniform1f(uniform(flat_program_, "u_checker"), checker_);
    gl_.BindVertexArray(flat_vao_);
    gl_.DrawElements(GL_TRIANGLES, flat_index_count_, GL_UNSIGNED_INT, nullptr);
  }

  // sky after the opaque things, only where nothing was drawn (at the far plane), so it costs no
  // hidden pixels; before the ray-cast rings, whose antialiased edges blend over it
  void draw_sky(const CameraView& camera) {
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LEQUAL);
    gl_.DepthMask(GL_FALSE);
    gl_.Disable(GL_CULL_FACE);
    gl_.UseProgram(sky_program_);
    const Eigen::Matrix3f ray_basis = sky_ray_basis(camera);
    gl_.UniformMatrix3fv(uniform(sky_program_, "u_ray_basis"), 1, GL_FALSE, ray_basis.data());
    gl_.Uniform1i(uniform(sky_program_, "u_env"), 0);
    gl_.BindVertexArray(empty_vao_);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);
    gl_.DepthMask(GL_TRUE);
    gl_.BindVertexArray(0);
  }

  // instanced tori: scene_view culls, picks levels and packs the instances; one upload per frame
  // (orphaning the old store), then one draw per mesh level. Returns how many rings are left for
  // the ray-cast level.
  int draw_ring_meshes(const Scene& scene, const RingFrame& frame, const CameraView& camera) {
    const double radius = scene.ring.centre_radius + scene.ring.wire_radius;
    const LodChoice lod{settings_.lod, settings_.lod_scale, radius,
                        camera.focal_pixels(settings_.height)};
    pack_ring_instances(frame, ring_frustum(camera, radius), lod, origin_, instances_);
    for (int level = 0; level < kLodLevels; ++level) {
      stats_.per_lod[level] += instances_.count(level);
    }
    stats_.instances += instances_.total();
    if (instances_.total() == 0) return 0;

    gl_.BindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
    const auto bytes = static_cast<GLsizeiptr>(instances_.data.size() * sizeof(float));
    gl_.BufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_STREAM_DRAW);
    gl_.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, instances_.data.data());

    set_common_uniforms(ring_program_, camera);
    gl_.Uniform1f(uniform(ring_program_, "u_spread"), kBlurSpread);
    gl_.Enable(GL_CULL_FACE);
    gl_.CullFace(GL_BACK);
    for (int level = 0; level < kMeshLevels; ++level) draw_level(level);
    gl_.Disable(GL_CULL_FACE);
    return instances_.count(kMeshLevels);
  }

  // the last level: bounding boxes, the torus ray-cast in each. Drawn single-sampled after the
  // resolve, back to front and blended by the coverage the shader computes, so these rings are
  // antialiased without multisampling (whose cost on a software rasterizer grows with the number
  // of tiny primitives, not with pixels)
  void draw_raycast_rings(const CameraView& camera) {
    gl_.BindFramebuffer(GL_FRAMEBUFFER, targets_.resolve_fbo);
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
    const int count = instances_.count(level);
    if (count == 0) return;
    gl_.BindVertexArray(lod_vao_[level]);
    gl_.BindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
    const size_t first = static_cast<size_t>(instances_.offsets[level]) * kInstanceFloats;
    attribute(2, 3, kInstanceFloats, first);
    attribute(3, 4, kInstanceFloats, first + 3);
    gl_.DrawElementsInstanced(GL_TRIANGLES, lod_index_count_[level], GL_UNSIGNED_INT, nullptr,
                              count);
  }

  // the cloth baseline's look; false when the weave has no quads (a chain): draw rings instead
  bool draw_cloth(const RingFrame& frame, const Weave& weave, const CameraView& camera) {
    const bool displace = look_.cloth_mode == kDisplacementMode;
    const Mesh mesh = cloth_mesh(frame, weave, displace ? kDisplacementSubdivisions : 1, origin_);
    if (mesh.indices.empty()) return false;
    gl_.BindVertexArray(cloth_vao_);
    upload_mesh(cloth_vbo_, mesh, GL_STREAM_DRAW);
    set_common_uniforms(cloth_program_, camera);
    gl_.Uniform1i(uniform(cloth_program_, "u_mode"), look_.cloth_mode);
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
  ResolvedSettings look_;

  GLuint sky_program_ = 0, prefilter_program_ = 0, ring_program_ = 0, impostor_program_ = 0,
         flat_program_ = 0, cloth_program_ = 0;
  SkyTextures sky_;
  PanelTargets targets_;
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
  RingInstances instances_;
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

}  // namespace chainmail::render
