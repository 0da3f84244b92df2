#include "terralod/render/gl_context.h"

#include <epoxy/gl.h>

#include <cstdio>

#include "current_gl_info.h"

namespace terralod {

std::string GlContext::description() const {
  const GlInfo& gl = info();
  return gl.platform + ", " + gl.renderer + ", OpenGL " + gl.version;
}

GlInfo readCurrentGlInfo(std::string platform) {
  auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "(unknown)");
  };
  GlInfo info;
  info.platform = std::move(platform);
  info.renderer = text(GL_RENDERER);
  info.version = text(GL_VERSION);
  // GL_MAJOR_VERSION and the profile mask exist from 3.0/3.2; an older context leaves
  // them unset, which requireGl45Core() then reports.
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  info.coreProfile = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  return info;
}

Status requireGl45Core(const GlInfo& info) {
  const bool recentEnough = info.major > 4 || (info.major == 4 && info.minor >= 5);
  if (recentEnough && info.coreProfile) return {};
  return makeError(info.platform, info.renderer + " offers OpenGL " + info.version +
                                      ", not OpenGL 4.5 core profile");
}

#ifndef NDEBUG
namespace {
void GLAPIENTRY printDebugMessage(GLenum, GLenum type, GLuint, GLenum severity, GLsizei,
                                  const GLchar* message, const void*) {
  const char* level = severity == GL_DEBUG_SEVERITY_HIGH ? "error" : "warning";
  if (type == GL_DEBUG_TYPE_PERFORMANCE) level = "performance";
  std::fprintf(stderr, "GL %s: %s\n", level, message);
}
}  // namespace

void installDebugOutput() {
  GLint flags = 0;
  glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
  if ((flags & GL_CONTEXT_FLAG_DEBUG_BIT) == 0) return;
  // Synchronous, so a message arrives inside the call that caused it (breakpoint-friendly).
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(printDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                        GL_FALSE);
  // ShaderProgram returns compile and link logs in its Result; printing them too is noise.
  glDebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr,
                        GL_FALSE);
}
#else
void installDebugOutput() {}
#endif

}  // namespace terralod
