#include "render/gl.hpp"

#include <dlfcn.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "render/types.hpp"

#if defined(__SANITIZE_ADDRESS__)
// Sanitizer builds: LeakSanitizer calls this hook in every program that links the renderer. Mesa
// (OSMesaMakeCurrent, llvmpipe, the EGL driver) keeps a few small per-process allocations that it
// never frees; only those libraries are suppressed, leaks in our code are still reported.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\nleak:libgallium\nleak:libLLVM\nleak:libEGL_mesa.so\nleak:libglapi."
         "so\n";
}
// no "Suppressions used" table on stderr: a refused input still gets its one line
extern "C" const char* __lsan_default_options() {
  return "print_suppressions=0";
}
#endif

namespace chainmail::render {
namespace {

// OSMesa constants and entry points, declared here so that no OSMesa header is needed to build
constexpr int kOsmesaFormat = 0x22, kOsmesaDepthBits = 0x30, kOsmesaStencilBits = 0x31,
              kOsmesaAccumBits = 0x32, kOsmesaProfile = 0x33, kOsmesaCoreProfile = 0x34,
              kOsmesaMajor = 0x36, kOsmesaMinor = 0x37;
using OsmesaContext = void*;
using OsmesaProc = void (*)();
using OsmesaCreateContextAttribs = OsmesaContext (*)(const int*, OsmesaContext);
using OsmesaDestroyContext = void (*)(OsmesaContext);
using OsmesaMakeCurrent = unsigned char (*)(OsmesaContext, void*, GLenum, GLsizei, GLsizei);
using OsmesaGetProcAddress = OsmesaProc (*)(const char*);
// core profile 3.3; the tiny default buffer is never drawn into (all drawing goes to FBOs)
constexpr int kOsmesaCoreAttributes[] = {kOsmesaFormat,
                                         GL_RGBA,
                                         kOsmesaDepthBits,
                                         24,
                                         kOsmesaStencilBits,
                                         0,
                                         kOsmesaAccumBits,
                                         0,
                                         kOsmesaProfile,
                                         kOsmesaCoreProfile,
                                         kOsmesaMajor,
                                         3,
                                         kOsmesaMinor,
                                         3,
                                         0};

// dlopen the first library of `names` that loads; records why each failed
void* open_library(const std::vector<std::string>& names, std::string& why) {
  for (const std::string& name : names) {
    if (void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL)) return handle;
    const char* error = dlerror();
    why += (why.empty() ? "" : "; ") + std::string(error ? error : name + ": not found");
  }
  return nullptr;
}

template <typename Function>
Function symbol(void* library, const char* name) {
  return reinterpret_cast<Function>(dlsym(library, name));
}

// fills every member of the table; false names the first entry point that is missing
template <typename Loader>
bool load_api(GlApi& api, Loader&& load, std::string& missing) {
#define CHAINMAIL_GL_LOAD(type, name)                  \
  api.name = reinterpret_cast<type>(load("gl" #name)); \
  if (!api.name) {                                     \
    missing = "gl" #name;                              \
    return false;                                      \
  }
  CHAINMAIL_GL_FUNCTIONS(CHAINMAIL_GL_LOAD)
#undef CHAINMAIL_GL_LOAD
  return true;
}

// the library handles stay open for the life of the process: Mesa's driver threads and atexit
// handlers may outlive a context, and unloading under them is unsafe

class OsmesaGlContext final : public GlContext {
 public:
  // returns null and fills `why` when OSMesa is unavailable
  static std::unique_ptr<OsmesaGlContext> make(const std::string& library, std::string& why) {
    const std::vector<std::string> names =
        library.empty()
            ? std::vector<std::string>{"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}
            : std::vector<std::string>{library};
    void* handle = open_library(names, why);
    if (!handle) return nullptr;
    auto create = symbol<OsmesaCreateContextAttribs>(handle, "OSMesaCreateContextAttribs");
    auto destroy = symbol<OsmesaDestroyContext>(handle, "OSMesaDestroyContext");
    auto make_current = symbol<OsmesaMakeCurrent>(handle, "OSMesaMakeCurrent");
    auto get_proc = symbol<OsmesaGetProcAddress>(handle, "OSMesaGetProcAddress");
    if (!create || !destroy || !make_current || !get_proc) {
      why = "libOSMesa lacks OSMesaCreateContextAttribs (needs Mesa >= 12)";
      return nullptr;
    }
    OsmesaContext context = create(kOsmesaCoreAttributes, nullptr);
    if (!context) {
      why = "OSMesaCreateContextAttribs could not make a 3.3 core context";
      return nullptr;
    }
    auto result = std::unique_ptr<OsmesaGlContext>(new OsmesaGlContext);
    result->context_ = context;
    result->destroy_ = destroy;
    result->make_current_ = make_current;
    if (!make_current(context, result->buffer_.data(), GL_UNSIGNED_BYTE, kBufferSize,
                      kBufferSize)) {
      why = "OSMesaMakeCurrent failed";
      return nullptr;
    }
    std::string missing;
    if (!load_api(
            result->api_, [&](const char* name) { return get_proc(name); }, missing)) {
      why = "OSMesa context lacks " + missing;
      return nullptr;
    }
    return result;
  }

  ~OsmesaGlContext() override {
    make_current_(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
    destroy_(context_);
  }
  std::string name() const override { return "osmesa"; }

 private:
  static constexpr int kBufferSize = 4;
  OsmesaGlContext() = default;
  OsmesaContext context_ = nullptr;
  OsmesaDestroyContext destroy_ = nullptr;
  OsmesaMakeCurrent make_current_ = nullptr;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(kBufferSize * kBufferSize * 4);
};

class EglGlContext final : public GlContext {
 public:
  // returns null and fills `why` when EGL surfaceless is unavailable
  static std::unique_ptr<EglGlContext> make(const std::string& library, std::string& why) {
    const std::vector<std::string> names =
        library.empty() ? std::vector<std::string>{"libEGL.so.1", "libEGL.so"}
                        : std::vector<std::string>{library};
    void* handle = open_library(names, why);
    if (!handle) return nullptr;
    auto result = std::unique_ptr<EglGlContext>(new EglGlContext);
    EglGlContext& e = *result;
    if (!e.load_entry_points(handle, why) || !e.open_surfaceless_display(why) ||
        !e.create_core_context(why) || !e.make_current_and_load_gl(why)) {
      return nullptr;
    }
    return result;
  }

  ~EglGlContext() override {
    if (display_ == EGL_NO_DISPLAY) return;
    make_current_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) destroy_context_(display_, context_);
    terminate_(display_);
  }
  std::string name() const override { return "egl"; }

 private:
  EglGlContext() = default;

  // the EGL entry points, through eglGetProcAddress or else the library's own symbols
  bool load_entry_points(void* handle, std::string& why) {
    get_proc_ = symbol<PFNEGLGETPROCADDRESSPROC>(handle, "eglGetProcAddress");
    query_string_ = symbol<PFNEGLQUERYSTRINGPROC>(handle, "eglQueryString");
    if (!get_proc_ || !query_string_) {
      why = "libEGL lacks eglGetProcAddress";
      return false;
    }
#define CHAINMAIL_EGL_LOAD(type, member, name)      \
  member = reinterpret_cast<type>(get_proc_(name)); \
  if (!member) member = symbol<type>(handle, name); \
  if (!member) {                                    \
    why = "libEGL lacks " name;                     \
    return false;                                   \
  }
    CHAINMAIL_EGL_LOAD(PFNEGLINITIALIZEPROC, initialize_, "eglInitialize")
    CHAINMAIL_EGL_LOAD(PFNEGLTERMINATEPROC, terminate_, "eglTerminate")
    CHAINMAIL_EGL_LOAD(PFNEGLBINDAPIPROC, bind_api_, "eglBindAPI")
    CHAINMAIL_EGL_LOAD(PFNEGLCHOOSECONFIGPROC, choose_config_, "eglChooseConfig")
    CHAINMAIL_EGL_LOAD(PFNEGLCREATECONTEXTPROC, create_context_, "eglCreateContext")
    CHAINMAIL_EGL_LOAD(PFNEGLDESTROYCONTEXTPROC, destroy_context_, "eglDestroyContext")
    CHAINMAIL_EGL_LOAD(PFNEGLMAKECURRENTPROC, make_current_, "eglMakeCurrent")
#undef CHAINMAIL_EGL_LOAD
    return true;
  }

  // the surfaceless platform needs no window system and no GPU (Mesa falls back to llvmpipe)
  bool open_surfaceless_display(std::string& why) {
    const char* client = query_string_(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client || !std::strstr(client, "EGL_MESA_platform_surfaceless")) {
      why = "EGL has no EGL_MESA_platform_surfaceless";
      return false;
    }
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(get_proc_("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) {
      why = "EGL lacks eglGetPlatformDisplayEXT";
      return false;
    }
    display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || !initialize_(display_, &major, &minor)) {
      why = "eglInitialize failed on the surfaceless platform";
      display_ = EGL_NO_DISPLAY;
      return false;
    }
    if (!bind_api_(EGL_OPENGL_API)) {
      why = "eglBindAPI(EGL_OPENGL_API) failed";
      return false;
    }
    const char* display_extensions = query_string_(display_, EGL_EXTENSIONS);
    if (!display_extensions || !std::strstr(display_extensions, "EGL_KHR_surfaceless_context")) {
      why = "EGL display has no EGL_KHR_surfaceless_context";
      return false;
    }
    return true;
  }

  // an OpenGL 3.3 core context on any config (it never draws to a surface)
  bool create_core_context(std::string& why) {
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                        EGL_DONT_CARE, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!choose_config_(display_, config_attributes, &config, 1, &count) || count < 1) {
      why = "eglChooseConfig found no OpenGL config";
      return false;
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         3,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    context_ = create_context_(display_, config, EGL_NO_CONTEXT, context_attributes);
    if (context_ == EGL_NO_CONTEXT) {
      why = "eglCreateContext could not make a 3.3 core context";
      return false;
    }
    return true;
  }

  bool make_current_and_load_gl(std::string& why) {
    if (!make_current_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      why = "eglMakeCurrent (surfaceless) failed";
      return false;
    }
    std::string missing;
    const PFNEGLGETPROCADDRESSPROC get_proc = get_proc_;
    if (!load_api(
            api_, [&](const char* name) { return get_proc(name); }, missing)) {
      why = "EGL context lacks " + missing;
      return false;
    }
    return true;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  PFNEGLGETPROCADDRESSPROC get_proc_ = nullptr;
  PFNEGLQUERYSTRINGPROC query_string_ = nullptr;
  PFNEGLINITIALIZEPROC initialize_ = nullptr;
  PFNEGLTERMINATEPROC terminate_ = nullptr;
  PFNEGLBINDAPIPROC bind_api_ = nullptr;
  PFNEGLCHOOSECONFIGPROC choose_config_ = nullptr;
  PFNEGLCREATECONTEXTPROC create_context_ = nullptr;
  PFNEGLDESTROYCONTEXTPROC destroy_context_ = nullptr;
  PFNEGLMAKECURRENTPROC make_current_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> create_context(const ContextOptions& options) {
  const std::string& kind = options.kind;
  if (kind != "auto" && kind != "osmesa" && kind != "egl") {
    throw RenderError("render: unknown GL context '" + kind + "' (expected auto, osmesa or egl)");
  }
  // auto: OSMesa first (Mesa < 25.1), then EGL surfaceless
  std::string attempts;
  if (kind == "auto" || kind == "osmesa") {
    std::string why;
    if (auto context = OsmesaGlContext::make(options.osmesa_library, why)) return context;
    attempts += "OSMesa: " + why;
  }
  if (kind == "auto" || kind == "egl") {
    std::string why;
    if (auto context = EglGlContext::make(options.egl_library, why)) return context;
    attempts += (attempts.empty() ? "" : " | ") + std::string("EGL surfaceless: ") + why;
  }
  throw RenderError("render: no OpenGL available, could not create a headless GL 3.3 context (" +
                    attempts + ")");
}

void check_gl(const GlApi& gl, const char* what) {
  if (const GLenum error = gl.GetError(); error != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof(code), "0x%04x", error);
    throw RenderError(std::string("render: GL error ") + code + " while " + what);
  }
}

void check_framebuffer(const GlApi& gl, const char* what) {
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError(std::string("render: incomplete framebuffer for ") + what);
  }
}

}  // namespace chainmail::render
