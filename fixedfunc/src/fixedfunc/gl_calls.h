// The one door from puff::fixedfunc to GL. Every GL call in fixedfunc/src/fixedfunc is written
// FF_GL(glName, args...): it records "glName" in the installed call log (setCallLog), then calls
// the function through glad. The tests check the log against the OpenGL 1.5 entry points and scan
// the sources for any gl* call that does not come through here.
#pragma once

#include <puff/gl_api.h>

namespace puff::fixedfunc::detail {

/// Appends `name` to the installed call log, if any.
void recordCall(const char* name);
/// Whether glad has loaded GL at all (its glGetString pointer is set).
bool loaderReady();

}  // namespace puff::fixedfunc::detail

// `#fn` is taken before glad's `#define glX puff_glad_glX` expands, so the log holds the GL name.
#define FF_GL(fn, ...) (::puff::fixedfunc::detail::recordCall(#fn), fn(__VA_ARGS__))
