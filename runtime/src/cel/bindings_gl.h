// Internal: points a cel program's blocks and samplers at the host's chosen binding points.
#pragma once

#include <puff/cel/bindings.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>

namespace puff::cel::detail {

/// Every cel resource by name (shaders/common/frame.glsl, shaders/cel/*): the ones `program` lacks
/// are skipped.
void assignBindPoints(GLuint program, const Bindings& b);

}  // namespace puff::cel::detail
