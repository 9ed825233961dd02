// The RAII owners' deleters and creators. Creation uses direct state access (glCreate*), so a new
// name is a complete object at once and nothing needs to be bound to create it.
#include <puff/core/gl.h>

#include <cstdio>

namespace puff::core {

namespace detail {
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteRenderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteProgram(GLuint id) { glDeleteProgram(id); }
void deleteShader(GLuint id) { glDeleteShader(id); }
}  // namespace detail

Texture makeTexture(GLenum target) {
  GLuint id = 0;
  glCreateTextures(target, 1, &id);
  return Texture(id);
}

Buffer makeBuffer() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return Buffer(id);
}

Framebuffer makeFramebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return Framebuffer(id);
}

Renderbuffer makeRenderbuffer() {
  GLuint id = 0;
  glCreateRenderbuffers(1, &id);
  return Renderbuffer(id);
}

VertexArray makeVertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return VertexArray(id);
}

namespace {
std::string glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
      return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
      return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST:
      return "GL_CONTEXT_LOST";
  }
  char hex[32];
  std::snprintf(hex, sizeof hex, "GL error 0x%04x", error);
  return hex;
}
}  // namespace

std::string drainGlErrors() {
  std::string names;
  // Bounded: without a current context (or after GL_CONTEXT_LOST) glGetError may never return
  // GL_NO_ERROR. Each error flag is reported once per drain, so a few iterations cover them all.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR) break;
    if (!names.empty()) names += ", ";
    names += glErrorName(error);
    if (error == GL_CONTEXT_LOST) break;
  }
  return names;
}

}  // namespace puff::core
