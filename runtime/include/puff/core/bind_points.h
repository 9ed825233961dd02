// Binding points chosen at run time: a program's uniform blocks, storage blocks and samplers are
// pointed at the indices and texture units a host chose (cel::Bindings, media::Bindings), after
// linking, so the shaders' `layout(binding = N)` values are never what is used. Needs a current
// GL 4.5 context.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::core {

/// One of a program's resources and the binding point it gets.
struct BindPoint {
  enum class Kind { kUniformBlock, kStorageBlock, kSampler };
  Kind kind;
  const char* name;  ///< the block's name (not its instance) or the sampler uniform's name
  GlId point;        ///< buffer index or texture unit; a sampler array takes point, point + 1, ...
  int count = 1;     ///< elements of a sampler array (its name is then "uName[0]")
};

/// Points `program`'s resources at `points`: glUniformBlockBinding, glShaderStorageBlockBinding
/// (indices introspected by name) and glProgramUniform1i(v) for samplers. A resource the program
/// does not have, or that the linker dropped as unused, is skipped. Changes no bound GL state.
void assignBindPoints(GlId program, std::initializer_list<BindPoint> points);

/// A named binding point for checkBindPoints: what the error message calls it.
struct NamedPoint {
  std::string name;
  GlId point = 0;
  int count = 1;  ///< consecutive points from `point` (a sampler array)
};

/// Checks a set of points of one kind that one program (or one call) uses together: each below the
/// limit GL reports for `limit` (GL_MAX_UNIFORM_BUFFER_BINDINGS, GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
/// or GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, queried), and no two the same. `what` names the
/// options in the error, e.g. "cel::Bindings". Needs a current GL context; before initGl it returns
/// an error saying to call it (the renderers' create calls check their bindings first).
Result<void> checkBindPoints(const std::string& what, GlEnum limit, const std::vector<NamedPoint>& points);

/// Binds `texture` to `unit` (glBindTextureUnit, so on the texture's own target) and no sampler
/// object there (glBindSampler(unit, 0)): a host's sampler on the unit would override the
/// texture's filtering and wrapping.
void bindTextureAndNoSampler(GlId unit, GlId texture);

}  // namespace puff::core
