#pragma once
// A linked GLSL program built from source text, with compile and link errors returned (not
// printed, not thrown) so a bad shader is a failed Result naming the stage and the line.

#include <cstdint>
#include <string>

#include "terralod/core/result.h"

namespace terralod {

/// GLSL sources, each complete with its own "#version 450 core" line (and any #extension
/// lines after it). An empty geometry source means the program has no geometry stage.
struct ShaderSources {
  std::string vertex;
  std::string fragment;
  std::string geometry;
};

/// Owns a GL program object. Create, use and destroy it on the thread where its GlContext is
/// current, and destroy it before that context. Movable, not copyable.
class ShaderProgram {
 public:
  /// Compiles every stage and links them. On failure the error reads
  /// "<name>: <stage> shader does not compile:" (or "program does not link:") followed by
  /// the driver's info log, one line per message.
  static Result<ShaderProgram> create(const std::string& name, const ShaderSources& sources);

  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  /// Makes it the current program (glUseProgram).
  void use() const;
  /// Location of an active uniform, or -1 when the program has none by that name.
  int uniformLocation(const char* uniformName) const;
  /// The GL program name, for glProgramUniform* and friends.
  uint32_t id() const { return mProgram; }

 private:
  explicit ShaderProgram(uint32_t program) : mProgram(program) {}

  uint32_t mProgram = 0;
};

}  // namespace terralod
