# Generates a glad 2 GL loader (compatibility profile 4.5, which also covers every GL 1.x entry
# point the fixed-function path uses) into the build tree at configure time. Not committed.
#
# The loader is Puff's own and private: a game loads GL with its own glad, GLEW, epoxy
# or GLFW, and hands Puff its getProcAddress (puff::core::initGl). So that both loaders link into
# one program, every global symbol glad defines is renamed here, after generation:
#   glad_glX -> puff_glad_glX,  GLAD_GL_VERSION_4_5 -> PUFF_GLAD_GL_VERSION_4_5,
#   gladLoadGL -> puffGladLoadGL,  <glad/gl.h> -> <puff/glad/gl.h>.
# The header is never installed and no public Puff header includes it; Puff's sources reach it
# through runtime/private/puff/gl_api.h (target puff_gl_api, build tree only).
find_program(PUFF_GLAD_EXECUTABLE glad REQUIRED DOC "glad 2 generator (Debian: python3-glad)")
set(_glad_raw ${CMAKE_BINARY_DIR}/glad-raw)
set(_glad_dir ${CMAKE_BINARY_DIR}/puff_glad)
set(_glad_args --quiet --reproducible --api gl:compatibility=4.5 --out-path ${_glad_raw} c)
string(REPLACE ";" " " _glad_stamp_text "${_glad_args} prefix=puff_glad_ v1")
if(NOT EXISTS ${_glad_dir}/src/gl.c OR NOT EXISTS ${_glad_dir}/include/puff/glad/gl.h
   OR NOT EXISTS ${_glad_dir}/stamp.txt)
  set(_glad_regen TRUE)
else()
  file(READ ${_glad_dir}/stamp.txt _glad_old)
  if(NOT _glad_old STREQUAL _glad_stamp_text)
    set(_glad_regen TRUE)
  endif()
endif()
# Renames glad's global symbols in `text` (see above). CMake's regex has no word boundary: the
# character before each name is captured and put back.
function(_puff_glad_prefix in out)
  file(READ ${in} _text)
  string(REGEX REPLACE "([^A-Za-z0-9_])glad_" "\\1puff_glad_" _text "${_text}")
  string(REGEX REPLACE "([^A-Za-z0-9_])GLAD_GL_" "\\1PUFF_GLAD_GL_" _text "${_text}")
  string(REGEX REPLACE "([^A-Za-z0-9_])gladLoad" "\\1puffGladLoad" _text "${_text}")
  string(REPLACE "#include <glad/gl.h>" "#include <puff/glad/gl.h>" _text "${_text}")
  file(WRITE ${out} "${_text}")
endfunction()
if(_glad_regen)
  message(STATUS "Generating glad GL loader in ${_glad_dir}")
  file(REMOVE_RECURSE ${_glad_raw} ${_glad_dir})
  execute_process(COMMAND ${PUFF_GLAD_EXECUTABLE} ${_glad_args}
                  RESULT_VARIABLE _glad_rc OUTPUT_QUIET ERROR_VARIABLE _glad_err)
  if(NOT _glad_rc EQUAL 0 OR NOT EXISTS ${_glad_raw}/src/gl.c)
    message(FATAL_ERROR "glad failed (${_glad_rc}): ${_glad_err}")
  endif()
  _puff_glad_prefix(${_glad_raw}/src/gl.c ${_glad_dir}/src/gl.c)
  _puff_glad_prefix(${_glad_raw}/include/glad/gl.h ${_glad_dir}/include/puff/glad/gl.h)
  file(REMOVE_RECURSE ${_glad_raw})
  file(WRITE ${_glad_dir}/stamp.txt "${_glad_stamp_text}")
endif()

# The loader's code. Linked into puff_core only (one set of function pointers per program, also
# with shared libraries: the other Puff libraries reach it through libpuff_core). Installed as an
# archive for static builds; its header is not installed.
add_library(puff_glad STATIC ${_glad_dir}/src/gl.c)
set_target_properties(puff_glad PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME glad_private)
target_include_directories(puff_glad PRIVATE ${_glad_dir}/include)
install(TARGETS puff_glad EXPORT puff_coreTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})

# What Puff's own sources (libraries, apps, tests) include to call GL: <puff/gl_api.h>, and the
# C++/GLSL contract <puff/shader_contract.h>, which reads <common/contract.glsl> from the shaders'
# root. Build tree only: link it as $<BUILD_INTERFACE:puff_gl_api> so that no installed target names it.
add_library(puff_gl_api INTERFACE)
target_include_directories(puff_gl_api INTERFACE ${_glad_dir}/include ${PROJECT_SOURCE_DIR}/runtime/private
                                                 ${PROJECT_SOURCE_DIR}/shaders)
