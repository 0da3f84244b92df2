#pragma once
// Shared by every GlContext implementation: what a fresh context is, and whether it will do.

#include <string>

#include "terralod/core/result.h"
#include "terralod/render/gl_context.h"

namespace terralod {

/// Reads renderer, version and profile from the context current on the calling thread.
GlInfo readCurrentGlInfo(std::string platform);

/// Fails, naming what the context offers, unless it is OpenGL 4.5 or newer, core profile.
Status requireGl45Core(const GlInfo& info);

/// In debug builds, routes KHR_debug messages above notification level to stderr; a no-op
/// in release builds. Needs the context current on the calling thread.
void installDebugOutput();

}  // namespace terralod
