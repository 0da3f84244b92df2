#include "egl_headless_context.h"

#include <epoxy/gl.h>

#include <map>
#include <mutex>
#include <string_view>
#include <vector>

#include "current_gl_info.h"

namespace terralod {
namespace {

constexpr EGLint kMaxDevices = 16;

std::string eglErrorName(EGLint code) {
  switch (code) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    default:
      return "EGL error " + std::to_string(code);
  }
}

std::string lastEglError() {
  return eglErrorName(eglGetError());
}

// EGL displays are process-wide: asking twice for the same device returns the same handle,
// and one eglTerminate() invalidates every context on it. So each context holds a reference
// and the last one out terminates. The count has to be as global as the state it mirrors.
class DisplayReferences {
 public:
  static DisplayReferences& instance() {
    static DisplayReferences references;
    return references;
  }
  void acquire(EGLDisplay display) {
    std::lock_guard lock(mMutex);
    ++mCounts[display];
  }
  void release(EGLDisplay display) {
    std::lock_guard lock(mMutex);
    auto it = mCounts.find(display);
    if (it == mCounts.end() || --it->second > 0) return;
    mCounts.erase(it);
    eglTerminate(display);
  }

 private:
  std::mutex mMutex;
  std::map<EGLDisplay, int> mCounts;
};

// Holds a display reference until the context that needs it exists.
class DisplayReference {
 public:
  explicit DisplayReference(EGLDisplay display) : mDisplay(display) {
    DisplayReferences::instance().acquire(display);
  }
  ~DisplayReference() {
    if (mDisplay != EGL_NO_DISPLAY) DisplayReferences::instance().release(mDisplay);
  }
  DisplayReference(const DisplayReference&) = delete;
  DisplayReference& operator=(const DisplayReference&) = delete;
  void handOver() { mDisplay = EGL_NO_DISPLAY; }

 private:
  EGLDisplay mDisplay;
};

// Whether a space-separated extension list names `name` exactly (not as a prefix).
bool hasWord(std::string_view list, std::string_view name) {
  for (size_t start = 0; start < list.size();) {
    size_t end = list.find(' ', start);
    if (end == std::string_view::npos) end = list.size();
    if (list.substr(start, end - start) == name) return true;
    start = end + 1;
  }
  return false;
}

std::string join(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : "; ") + part;
  return out;
}

// OpenGL 4.5 core (with the debug flag in debug builds).
std::vector<EGLint> contextAttributes() {
  std::vector<EGLint> attributes = {
      EGL_CONTEXT_MAJOR_VERSION_KHR,       4,
      EGL_CONTEXT_MINOR_VERSION_KHR,       5,
      EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR};
#ifndef NDEBUG
  attributes.insert(attributes.end(), {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
#endif
  attributes.push_back(EGL_NONE);
  return attributes;
}

}  // namespace

Result<std::unique_ptr<GlContext>> GlContext::createHeadless(HeadlessPlatform platform) {
  return EglHeadlessContext::create(platform);
}

Result<std::unique_ptr<GlContext>> EglHeadlessContext::create(HeadlessPlatform platform) {
  // The client extension string is null on an EGL 1.4 without EGL_EXT_client_extensions,
  // and then neither platform exists.
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!clientExtensions) eglGetError();  // clear EGL_BAD_DISPLAY so it is not reported later
  auto hasClientExtension = [&](std::string_view name) {
    return clientExtensions && hasWord(clientExtensions, name);
  };
  std::vector<std::string> failures;
  bool anyDisplay = false;

  if (platform != HeadlessPlatform::kSurfaceless) {
    if (!hasClientExtension("EGL_EXT_platform_device") ||
        !hasClientExtension("EGL_EXT_device_enumeration")) {
      failures.push_back("EGL device platform: not supported by this EGL");
    } else {
      EGLDeviceEXT devices[kMaxDevices];
      EGLint count = 0;
      if (!eglQueryDevicesEXT(kMaxDevices, devices, &count) || count == 0) {
        failures.push_back("EGL device platform: no devices");
      }
      for (EGLint i = 0; i < count; ++i) {
        // Naming the device only matters when there is a choice.
        std::string name = "EGL device platform";
        if (count > 1)
          name += " (device " + std::to_string(i) + " of " + std::to_string(count) + ")";
        EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display == EGL_NO_DISPLAY) {
          failures.push_back(name + ": no display (" + lastEglError() + ")");
          continue;
        }
        anyDisplay = true;
        auto context = open(display, name);
        if (context.ok()) return context;
        failures.push_back(context.error().message);
      }
    }
  }

  if (platform != HeadlessPlatform::kDevice) {
    const std::string name = "EGL surfaceless platform";
    if (!hasClientExtension("EGL_MESA_platform_surfaceless")) {
      failures.push_back(name + ": not supported by this EGL");
    } else {
      EGLDisplay display =
          eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (display == EGL_NO_DISPLAY) {
        failures.push_back(name + ": no display (" + lastEglError() + ")");
      } else {
        anyDisplay = true;
        auto context = open(display, name);
        if (context.ok()) return context;
        failures.push_back(context.error().message);
      }
    }
  }

  return makeError("", std::string(anyDisplay ? "no EGL display offers an OpenGL 4.5 core context"
                                              : "no EGL display available") +
                           ": " + join(failures));
}

Result<std::unique_ptr<GlContext>> EglHeadlessContext::open(EGLDisplay display,
                                                            const std::string& platform) {
  EGLint eglMajor = 0, eglMinor = 0;
  if (!eglInitialize(display, &eglMajor, &eglMinor))
    return makeError(platform, "eglInitialize failed (" + lastEglError() + ")");
  DisplayReference reference(display);

  // Without a surfaceless make-current we would need a pbuffer, which device displays on
  // some drivers do not offer; every driver we target has the extension.
  if (!epoxy_has_egl_extension(display, "EGL_KHR_surfaceless_context"))
    return makeError(platform, "EGL_KHR_surfaceless_context not supported");
  if (!epoxy_has_egl_extension(display, "EGL_KHR_create_context") &&
      epoxy_egl_version(display) < 15)
    return makeError(platform, "cannot request a GL version (no EGL_KHR_create_context)");
  if (!eglBindAPI(EGL_OPENGL_API))
    return makeError(platform, "desktop OpenGL not supported (" + lastEglError() + ")");

  // Rendering only ever goes to framebuffer objects, so any config will do; skip choosing one
  // when the display allows it.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!epoxy_has_egl_extension(display, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint found = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &found) || found == 0)
      return makeError(platform, "no config renders desktop OpenGL");
  }

  EGLContext context =
      eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes().data());
  if (context == EGL_NO_CONTEXT)
    return makeError(platform, "cannot create an OpenGL 4.5 core context (" + lastEglError() + ")");

  std::unique_ptr<EglHeadlessContext> owner(new EglHeadlessContext(display, config, context));
  reference.handOver();
  owner->mInfo.platform = platform;
  if (Status current = owner->makeCurrent(); !current) return current.error();
  owner->mInfo = readCurrentGlInfo(platform);
  if (Status usable = requireGl45Core(owner->mInfo); !usable) return usable.error();
  installDebugOutput();
  return std::unique_ptr<GlContext>(std::move(owner));
}

Result<std::unique_ptr<GlContext>> EglHeadlessContext::createShared() {
  eglBindAPI(EGL_OPENGL_API);
  EGLContext context = eglCreateContext(mDisplay, mConfig, mContext, contextAttributes().data());
  if (context == EGL_NO_CONTEXT)
    return makeError(mInfo.platform,
                     "cannot create a shared OpenGL context (" + lastEglError() + ")");
  DisplayReferences::instance().acquire(mDisplay);
  std::unique_ptr<EglHeadlessContext> shared(new EglHeadlessContext(mDisplay, mConfig, context));
  shared->mInfo = mInfo;
  return std::unique_ptr<GlContext>(std::move(shared));
}

EglHeadlessContext::~EglHeadlessContext() {
  releaseCurrent();
  eglDestroyContext(mDisplay, mContext);
  // No eglReleaseThread(): it would also drop contexts of other APIs current on this thread.
  DisplayReferences::instance().release(mDisplay);
}

Status EglHeadlessContext::makeCurrent() {
  // The bound API is per thread, and this may be a thread that never bound one.
  eglBindAPI(EGL_OPENGL_API);
  if (!eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext))
    return makeError(mInfo.platform, "eglMakeCurrent failed (" + lastEglError() + ")");
  return {};
}

void EglHeadlessContext::releaseCurrent() {
  eglBindAPI(EGL_OPENGL_API);
  if (eglGetCurrentContext() == mContext)
    eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace terralod
