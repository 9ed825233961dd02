#include <puff/core/bind_points.h>
#include <puff/gl_api.h>

#include <algorithm>
#include <vector>

namespace puff::core {

void assignBindPoints(GLuint program, std::initializer_list<BindPoint> points) {
  for (const BindPoint& p : points) {
    switch (p.kind) {
      case BindPoint::Kind::kUniformBlock: {
        const GLuint index = glGetUniformBlockIndex(program, p.name);
        if (index != GL_INVALID_INDEX) glUniformBlockBinding(program, index, p.point);
        break;
      }
      case BindPoint::Kind::kStorageBlock: {
        const GLuint index = glGetProgramResourceIndex(program, GL_SHADER_STORAGE_BLOCK, p.name);
        if (index != GL_INVALID_INDEX) glShaderStorageBlockBinding(program, index, p.point);
        break;
      }
      case BindPoint::Kind::kSampler: {
        const GLint location = glGetUniformLocation(program, p.name);
        if (location < 0) break;
        std::vector<GLint> units(static_cast<std::size_t>(p.count));
        for (int i = 0; i < p.count; ++i) units[static_cast<std::size_t>(i)] = static_cast<GLint>(p.point) + i;
        glProgramUniform1iv(program, location, p.count, units.data());
        break;
      }
    }
  }
}

Result<void> checkBindPoints(const std::string& what, GLenum limit, const std::vector<NamedPoint>& points) {
  // The first GL call of every renderer's create: without Puff's GL functions it would call a null
  // pointer, so it returns what the host forgot instead.
  if (!glLoaded())
    return Error{"Puff's GL functions are not loaded (checking " + what +
                 "): make a GL 4.5 context current and call puff::core::initGl(getProcAddress) first"};
  GLint max = 0;
  glGetIntegerv(limit, &max);
  const char* kind = limit == GL_MAX_UNIFORM_BUFFER_BINDINGS          ? "uniform buffer binding"
                     : limit == GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS ? "shader storage buffer binding"
                                                                      : "texture unit";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const NamedPoint& a = points[i];
    const long long last = static_cast<long long>(a.point) + a.count - 1;
    if (last >= max) {
      return Error{what + "." + a.name + ": " + kind + " " + std::to_string(last) + " is beyond this GL's " +
                   std::to_string(max) + " (0 to " + std::to_string(max - 1) + ")"};
    }
    for (std::size_t j = 0; j < i; ++j) {
      const NamedPoint& b = points[j];
      const bool overlap =
          a.point < b.point + static_cast<GLuint>(b.count) && b.point < a.point + static_cast<GLuint>(a.count);
      if (overlap) {
        return Error{what + "." + a.name + " and " + what + "." + b.name + ": both use " + kind + " " +
                     std::to_string(std::max(a.point, b.point)) + "; they must differ"};
      }
    }
  }
  return {};
}

void bindTextureAndNoSampler(GLuint unit, GLuint texture) {
  glBindTextureUnit(unit, texture);
  glBindSampler(unit, 0);
}

}  // namespace puff::core
