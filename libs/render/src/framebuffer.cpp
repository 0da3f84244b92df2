#include "terralod/render/framebuffer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace terralod {
namespace {

static_assert(std::is_same_v<GLuint, uint32_t>, "GL names are stored as uint32_t");

constexpr GLenum kColorFormat = GL_RGBA8;
constexpr GLenum kDepthFormat = GL_DEPTH_COMPONENT32F;

std::string statusName(GLenum status) {
  switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED:
      return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_UNSUPPORTED:
      return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
      return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    default:
      return "framebuffer status " + std::to_string(status);
  }
}

GLint getInteger(GLenum name) {
  GLint value = 0;
  glGetIntegerv(name, &value);
  return value;
}

}  // namespace

Result<Framebuffer> Framebuffer::create(int width, int height, int samples) {
  const std::string subject = "framebuffer " + std::to_string(width) + "x" +
                              std::to_string(height) +
                              (samples > 0 ? " with " + std::to_string(samples) + " samples" : "");
  const GLint maxWidth = getInteger(GL_MAX_FRAMEBUFFER_WIDTH);
  const GLint maxHeight = getInteger(GL_MAX_FRAMEBUFFER_HEIGHT);
  const GLint maxTexture = getInteger(GL_MAX_TEXTURE_SIZE);
  if (width < 1 || height < 1 || width > std::min(maxWidth, maxTexture) ||
      height > std::min(maxHeight, maxTexture))
    return makeError(subject, "size must be between 1x1 and " +
                                  std::to_string(std::min(maxWidth, maxTexture)) + "x" +
                                  std::to_string(std::min(maxHeight, maxTexture)));
  const GLint maxSamples = getInteger(GL_MAX_SAMPLES);
  if (samples < 0 || samples > maxSamples)
    return makeError(subject, "samples must be between 0 and " + std::to_string(maxSamples));

  Framebuffer target;
  target.mWidth = width;
  target.mHeight = height;
  target.mSamples = samples;

  glCreateTextures(GL_TEXTURE_2D, 1, &target.mColorTexture);
  glTextureStorage2D(target.mColorTexture, 1, kColorFormat, width, height);
  // Nearest filtering keeps the texture complete without mipmaps and samples it 1:1.
  glTextureParameteri(target.mColorTexture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(target.mColorTexture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  if (samples == 0) {
    glCreateTextures(GL_TEXTURE_2D, 1, &target.mDepthTexture);
    glTextureStorage2D(target.mDepthTexture, 1, kDepthFormat, width, height);
    glCreateFramebuffers(1, &target.mDrawFramebuffer);
    glNamedFramebufferTexture(target.mDrawFramebuffer, GL_COLOR_ATTACHMENT0, target.mColorTexture,
                              0);
    glNamedFramebufferTexture(target.mDrawFramebuffer, GL_DEPTH_ATTACHMENT, target.mDepthTexture,
                              0);
  } else {
    glCreateRenderbuffers(1, &target.mMultisampleColor);
    glNamedRenderbufferStorageMultisample(target.mMultisampleColor, samples, kColorFormat, width,
                                          height);
    // Depth in a texture, as without multisampling, so later passes can read it (texelFetch).
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &target.mDepthTexture);
    glTextureStorage2DMultisample(target.mDepthTexture, samples, kDepthFormat, width, height,
                                  GL_TRUE);
    glCreateFramebuffers(1, &target.mDrawFramebuffer);
    glNamedFramebufferRenderbuffer(target.mDrawFramebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                   target.mMultisampleColor);
    glNamedFramebufferTexture(target.mDrawFramebuffer, GL_DEPTH_ATTACHMENT, target.mDepthTexture,
                              0);
    glCreateFramebuffers(1, &target.mResolveFramebuffer);
    glNamedFramebufferTexture(target.mResolveFramebuffer, GL_COLOR_ATTACHMENT0,
                              target.mColorTexture, 0);
  }
  for (GLuint framebuffer : {target.mDrawFramebuffer, target.mResolveFramebuffer}) {
    if (framebuffer == 0) continue;
    glNamedFramebufferDrawBuffer(framebuffer, GL_COLOR_ATTACHMENT0);
    glNamedFramebufferReadBuffer(framebuffer, GL_COLOR_ATTACHMENT0);
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      return makeError(subject, "incomplete (" + statusName(status) + ")");
  }
  return target;
}

Framebuffer::~Framebuffer() {
  release();
}

Framebuffer::Framebuffer(Framebuffer&& other) noexcept {
  *this = std::move(other);
}

Framebuffer& Framebuffer::operator=(Framebuffer&& other) noexcept {
  if (this == &other) return *this;
  release();
  mWidth = std::exchange(other.mWidth, 0);
  mHeight = std::exchange(other.mHeight, 0);
  mSamples = std::exchange(other.mSamples, 0);
  mDrawFramebuffer = std::exchange(other.mDrawFramebuffer, 0);
  mResolveFramebuffer = std::exchange(other.mResolveFramebuffer, 0);
  mColorTexture = std::exchange(other.mColorTexture, 0);
  mDepthTexture = std::exchange(other.mDepthTexture, 0);
  mMultisampleColor = std::exchange(other.mMultisampleColor, 0);
  return *this;
}

void Framebuffer::release() {
  // A moved-from target makes no GL calls, so it may die without a current context. The
  // colour texture is created first: without it nothing else exists.
  if (mColorTexture == 0) return;
  // Deleting name 0 is a no-op, so a half-built target releases cleanly.
  const GLuint framebuffers[] = {mDrawFramebuffer, mResolveFramebuffer};
  glDeleteFramebuffers(2, framebuffers);
  glDeleteRenderbuffers(1, &mMultisampleColor);
  const GLuint textures[] = {mColorTexture, mDepthTexture};
  glDeleteTextures(2, textures);
  mDrawFramebuffer = mResolveFramebuffer = mMultisampleColor = 0;
  mColorTexture = mDepthTexture = 0;
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, mDrawFramebuffer);
  glViewport(0, 0, mWidth, mHeight);
}

void Framebuffer::resolve() const {
  if (mResolveFramebuffer == 0) return;
  glBlitNamedFramebuffer(mDrawFramebuffer, mResolveFramebuffer, 0, 0, mWidth, mHeight, 0, 0, mWidth,
                         mHeight, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

Image Framebuffer::readPixels() const {
  resolve();
  Image image;
  image.width = mWidth;
  image.height = mHeight;
  image.rgba.resize(size_t(mWidth) * size_t(mHeight) * 4);
  // Read straight from the texture (no framebuffer binding to disturb), into client memory
  // with tight rows whatever pack state the caller left behind.
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glGetTextureImage(mColorTexture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(image.rgba.size()),
                    image.rgba.data());
  // GL's row 0 is the bottom one; Image rows go top first.
  const size_t rowBytes = size_t(mWidth) * 4;
  std::vector<uint8_t> row(rowBytes);
  for (int top = 0, bottom = mHeight - 1; top < bottom; ++top, --bottom) {
    uint8_t* a = image.rgba.data() + size_t(top) * rowBytes;
    uint8_t* b = image.rgba.data() + size_t(bottom) * rowBytes;
    std::memcpy(row.data(), a, rowBytes);
    std::memcpy(a, b, rowBytes);
    std::memcpy(b, row.data(), rowBytes);
  }
  return image;
}

Status bindFramebufferOfSize(std::optional<Framebuffer>& target, int width, int height) {
  if (!target || target->width() != width || target->height() != height) {
    target.reset();  // free the old one's memory first
    auto created = Framebuffer::create(width, height);
    if (!created) return created.error();
    target.emplace(std::move(created).value());
  }
  target->bind();
  return {};
}

}  // namespace terralod
