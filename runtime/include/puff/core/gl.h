// GL through glad, and thin RAII owners for GL objects. Every owner deletes its object in the
// context that is current when it is destroyed: destroy GL objects before their context.
#pragma once

#include <glad/gl.h>

#include <string>
#include <utility>

#include <puff/core/error.h>

namespace puff::core {

/// A move-only owner of one GL name. Deleter is a function taking the name.
template <void (*Delete)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  ~GlName() { reset(); }

  GLuint get() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

namespace detail {
void deleteTexture(GLuint id);
void deleteBuffer(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteRenderbuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteProgram(GLuint id);
void deleteShader(GLuint id);
}  // namespace detail

using Texture = GlName<detail::deleteTexture>;
using Buffer = GlName<detail::deleteBuffer>;
using Framebuffer = GlName<detail::deleteFramebuffer>;
using Renderbuffer = GlName<detail::deleteRenderbuffer>;
using VertexArray = GlName<detail::deleteVertexArray>;
using Program = GlName<detail::deleteProgram>;
using ShaderObject = GlName<detail::deleteShader>;

Texture makeTexture(GLenum target);  ///< glCreateTextures
Buffer makeBuffer();                 ///< glCreateBuffers
Framebuffer makeFramebuffer();       ///< glCreateFramebuffers
Renderbuffer makeRenderbuffer();     ///< glCreateRenderbuffers
VertexArray makeVertexArray();       ///< glCreateVertexArrays

/// "" when glGetError() reports nothing, else the names of the pending errors (all drained).
std::string drainGlErrors();

}  // namespace puff::core
