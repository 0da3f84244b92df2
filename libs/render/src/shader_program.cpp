#include "terralod/render/shader_program.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace terralod {
namespace {

// Info logs are several lines ("0:3(1): error: ..."); keep one per message, indented under
// the line that says which stage failed, and drop the trailing blank ones.
std::string formatLog(const std::string& log) {
  std::string out;
  size_t start = 0;
  while (start < log.size()) {
    size_t end = log.find('\n', start);
    if (end == std::string::npos) end = log.size();
    std::string line = log.substr(start, end - start);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\0'))
      line.pop_back();
    if (!line.empty()) out += "\n  " + line;
    start = end + 1;
  }
  return out.empty() ? " (the driver gave no log)" : out;
}

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 0)), '\0');
  if (length > 0) glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log;
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 0)), '\0');
  if (length > 0) glGetProgramInfoLog(program, length, nullptr, log.data());
  return log;
}

struct Stage {
  GLenum type;
  const char* name;
  const std::string* source;
};

}  // namespace

Result<ShaderProgram> ShaderProgram::create(const std::string& name, const ShaderSources& sources) {
  std::vector<Stage> stages = {{GL_VERTEX_SHADER, "vertex", &sources.vertex},
                               {GL_FRAGMENT_SHADER, "fragment", &sources.fragment}};
  if (!sources.geometry.empty())
    stages.push_back({GL_GEOMETRY_SHADER, "geometry", &sources.geometry});

  // The program owns the shaders from here on: deleting them after linking (or on any
  // failure) lets GL free them with the program.
  ShaderProgram program(glCreateProgram());
  std::vector<GLuint> shaders;
  auto deleteShaders = [&] {
    for (GLuint shader : shaders) {
      glDetachShader(program.mProgram, shader);
      glDeleteShader(shader);
    }
  };
  for (const Stage& stage : stages) {
    if (stage.source->empty()) {
      deleteShaders();
      return makeError(name, std::string(stage.name) + " shader source is empty");
    }
    const GLuint shader = glCreateShader(stage.type);
    shaders.push_back(shader);
    glAttachShader(program.mProgram, shader);
    const char* text = stage.source->c_str();
    const GLint length = GLint(stage.source->size());
    glShaderSource(shader, 1, &text, &length);
    glCompileShader(shader);
    GLint compiled = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE) {
      const std::string log = shaderLog(shader);
      deleteShaders();
      return makeError(name,
                       std::string(stage.name) + " shader does not compile:" + formatLog(log));
    }
  }
  glLinkProgram(program.mProgram);
  deleteShaders();
  GLint linked = GL_FALSE;
  glGetProgramiv(program.mProgram, GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE)
    return makeError(name, "program does not link:" + formatLog(programLog(program.mProgram)));
  return program;
}

ShaderProgram::~ShaderProgram() {
  // A moved-from program makes no GL calls, so it may die without a current context.
  if (mProgram != 0) glDeleteProgram(mProgram);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : mProgram(std::exchange(other.mProgram, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (mProgram != 0) glDeleteProgram(mProgram);
    mProgram = std::exchange(other.mProgram, 0);
  }
  return *this;
}

void ShaderProgram::use() const {
  glUseProgram(mProgram);
}

int ShaderProgram::uniformLocation(const char* uniformName) const {
  return glGetUniformLocation(mProgram, uniformName);
}

}  // namespace terralod
