// puff::fixedfunc: cartoon smoke on fixed-function OpenGL 1.x (McGuire & Fein 2006, §4.4).
//
// Each frame (drawFrame):
//   1. Puff texture. The puff mesh is drawn four times, into the four cells of a 2x2 grid at the
//      bottom-left of the viewport, with the texture-unit trick: the camera-space light direction L
//      is the first row of unit 0's texture matrix and glTexGen(GL_NORMAL_MAP) makes (s,t,r) the
//      eye-space normal N, so s = N.L indexes the 1D ramp q (clamp-to-edge gives max(0, N.L)).
//      GL_MODULATE with the vertex colour C.K_L, then unit 1 adds the constant K_a
//      (GL_COMBINE/GL_ADD): texel = K_a + C.K_L.q(N.L) (Eq. 2). Coverage is the alpha (cleared to
//      0, mesh 1). glCopyTexSubImage2D copies the grid into one texture: render-to-texture the GL 1.x
//      way, through the framebuffer being drawn (that region is overwritten).
//   2. Clear the viewport (background colour, depth 1) unless FixedFrame::clear is false, draw
//      opaque objects (cel: the same trick; smooth: fixed-function Lambert lighting).
//   3. Outlines: per particle a larger black billboard with the same cell, pushed back along the
//      view ray by d, alpha tested, so it shows only as a ring around the puff's silhouette and
//      where a particle's outline lies behind no nearer particle body (Fig. 7).
//   4. Particles: view-aligned billboards with their cell (variation % 4), alpha test > 0.5, depth
//      tested and written with the ordinary (hyperbolic) depth buffer.
//
// Limits (the paper's): one directional light, a uniform ambient term K_a, no shadows, no
// nailboard depth (billboards are flat), no ambient gradient.
//
// GL requirements: a current compatibility-profile context of version >= 1.3 (GL_NORMAL_MAP
// texgen, texture env combine, two texture units), loaded through glad (puff::core contexts are).
// Only OpenGL 1.0-1.5 entry points are called (no shader, framebuffer or buffer objects); vertex
// data goes through client-side vertex arrays. The framebuffer being drawn (the host's FBO or
// window) must have an alpha channel, read and draw buffers must name the same surface, and no
// program (glUseProgram) and, in GL >= 3.0, no vertex array object may be bound: drawFrame checks
// these and fails otherwise. A buffer bound to GL_ARRAY_BUFFER / GL_ELEMENT_ARRAY_BUFFER is
// unbound for the frame and rebound after.
//
// State: every call saves and restores all GL state it touches (glPushAttrib(GL_ALL_ATTRIB_BITS),
// glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS), the projection, modelview and per-unit texture
// matrices, the active and client-active texture unit), so it runs inside a host's frame. What it
// does change: the pixels of the viewport (step 1 overwrites the bottom-left 2*cellSize square
// first) and the depth buffer inside the viewport.
//
// Drawing into the host's frame (FixedFrame::clear = false): the host draws first (its background,
// its opaque scene with depth in the same buffer), then calls drawFrame, which clears nothing. The
// corner step 1 draws through is read back before it (colour and depth, glReadPixels as floats)
// and written back after it (glDrawPixels), so every pixel the puffs and objects do not cover keeps
// the host's colour and depth exactly (8-bit colour and 16/24-bit depth round-trip through floats
// exactly); the puffs are depth-tested against the host's depth (GL_LESS, the standard [0, 1]
// hyperbolic depth of a GL 1.x projection). Stencil is never touched. The particles write colour,
// not alpha (the alpha write mask is off in step 4): the host's alpha stays under them.
//
// Colours are display values in [0, 1] with no sRGB conversion: what GL 1.x's 8-bit framebuffer
// blends. (The programmable paths take scene-linear colours and encode them inside, puff/core/frame.h.)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/mesh/mesh.h>

namespace puff::fixedfunc {

/// Installs a log that receives the name of every GL function the fixed path calls ("glBegin",
/// ...), in call order; nullptr (the default) stops logging. For tests: not thread-safe.
void setCallLog(std::vector<std::string>* log);

/// One smoke particle.
struct Billboard {
  glm::vec3 position{0.0f};  ///< world-space centre
  float size = 1.0f;         ///< world-space diameter of the puff (the mesh's unit sphere), > 0
  int variation = 0;         ///< any integer; variation mod 4 (made non-negative) picks the cell
  /// Multiplies C in K_a + C K_L q (display values, each clamped to [0, 1]; white = untinted):
  /// the sprite is K_a + tint (texel - K_a), one texture-combine interpolation.
  glm::vec3 tint{1.0f};
};

enum class ObjectShading {
  kCel,     ///< albedo * (K_a + K_L * q(max(0, N.L))), through the texgen/ramp trick
  kSmooth,  ///< albedo * (K_a + K_L * max(0, N.L)), fixed-function GL_LIGHT0
};

/// An opaque object: a triangle mesh with per-vertex normals (positions, normals, triangles;
/// colours are ignored; puff::mesh makes the primitives), placed in the world by `transform`.
struct FixedObject {
  mesh::TriMesh mesh;
  glm::mat4 transform{1.0f};  ///< object -> world, affine and invertible (normals use GL_NORMALIZE)
  glm::vec3 albedo{0.8f};     ///< >= 0
  ObjectShading shading = ObjectShading::kCel;
};

struct FixedViewport {
  int x = 0, y = 0;           ///< lower-left corner, GL window coordinates (pixels)
  int width = 0, height = 0;  ///< > 0 and both >= 2 * cellSize (the puff texture pass uses them)
};

/// What one frame needs from the host.
struct FixedFrame {
  glm::mat4 view{1.0f};        ///< world -> camera (rigid: rotation + translation)
  glm::mat4 projection{1.0f};  ///< camera -> clip, perspective or orthographic (GL conventions)
  FixedViewport viewport;
  glm::vec3 lightDirection{0.0f, 1.0f, 0.0f};      ///< world space, pointing toward the light; non-zero
  glm::vec3 lightColor{1.0f};                      ///< K_L, >= 0
  glm::vec3 ambientColor{0.25f};                   ///< uniform K_a, >= 0
  glm::vec4 background{0.6f, 0.75f, 0.95f, 1.0f};  ///< clear colour of the viewport
  /// true: clear the viewport to `background` and depth 1 (the standalone renderer's frame). false:
  /// draw into the host's frame as it is, clearing nothing (`background` unused); see "Drawing into
  /// the host's frame" above.
  bool clear = true;
};

struct FixedStyle {
  bool outlines = true;        ///< draw the black backing billboards
  float outlineScale = 1.1f;   ///< outline billboard size / particle size on screen, >= 1
  float outlineOffset = 0.0f;  ///< d in world units; <= 0 means the billboard's width (the paper's)
  bool shading = true;         ///< false: flat C.K_L + K_a (no ramp)
  glm::vec3 puffColor{1.0f};   ///< C, multiplied by the mesh's vertex colours if it has any
};

class FixedRenderer {
 public:
  /// Checks the current context (compatibility, GL >= 1.3, two texture units, a texture of
  /// 2*cellSize texels) and creates the puff texture and the default two-tone ramp (black below
  /// N.L = 0.5, white from 0.5). `puff` needs positions, unit normals (one per position) and
  /// triangles, and should lie within the unit sphere (the billboard shows [-1, 1]^2 of it; more is
  /// cut off). `cellSize`: texels per orientation, a power of two in [8, 1024] (GL 1.x textures are
  /// powers of two). Errors: "fixedfunc: ..." naming the problem (no GL loaded, core profile,
  /// version too old, bad mesh, bad cell size).
  static Result<std::unique_ptr<FixedRenderer>> create(const mesh::TriMesh& puff, int cellSize = 128);
  /// Deletes the textures: the context must be current.
  ~FixedRenderer();
  FixedRenderer(const FixedRenderer&) = delete;
  FixedRenderer& operator=(const FixedRenderer&) = delete;

  /// Sets the quantization ramp q from the middle row of `ramp` (the row puff::cel uses; 1 channel:
  /// grey, 3 or 4: RGB, alpha ignored; width >= 1, values clamped to [0, 1]). Nearest filtering,
  /// clamp to edge. The ramp is resampled (nearest) to 256 texels, or the next power of two above a
  /// wider one, so its bands change within 1/512 in N.L of where puff::cel's (which samples the ramp
  /// as it is) change. Errors on an empty image or a bad channel count, keeping the old ramp.
  Result<void> setRamp(const core::Image& ramp);

  /// Replaces the opaque objects. Errors (keeping the previous set) on an empty mesh, normals not
  /// one per position, an index out of range, a non-finite transform or a negative albedo:
  /// "fixedfunc: object #i: problem".
  Result<void> setObjects(std::vector<FixedObject> objects);

  /// Draws one frame (steps 1-4 above) into the current framebuffer. Errors, drawing nothing, on a
  /// viewport smaller than 2*cellSize, a zero light direction, non-finite matrices, or a context
  /// state the path cannot draw in (see "GL requirements"); billboards with a size <= 0 or a
  /// non-finite position are skipped.
  Result<void> drawFrame(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                         const FixedStyle& style = {});
  /// The benchmarks' fill-rate floor of this path, a GL 1.x bare-quad pass: the frame drawFrame
  /// draws (clear, objects) with each billboard a bare quad of its cell, alpha tested, untinted and
  /// without its outline, and no puff texture pass (the texture is drawn once, on the first call,
  /// with the default style). Its image is drawFrame's with outlines off for untinted billboards
  /// once the texture holds the same puffs. Errors as drawFrame's.
  Result<void> drawFloorFrame(const FixedFrame& frame, const std::vector<Billboard>& billboards);

  /// The puff texture (GL_TEXTURE_2D, RGBA8, 2*cellSize square) as the last drawFrame left it. Cell
  /// k (0..3) is column k % 2, row k / 2 counted from texel (0, 0); it shows the mesh in
  /// [-cellExtent(), cellExtent()]^2 (a margin of two texels keeps cells apart under filtering).
  unsigned puffTexture() const;
  int cellSize() const { return cellSize_; }
  float cellExtent() const;
  /// GL_VERSION of the context at create, e.g. "1.3 Mesa 22.3.6".
  const std::string& contextVersion() const { return contextVersion_; }

 private:
  struct Impl;
  explicit FixedRenderer(std::unique_ptr<Impl> impl, int cellSize, std::string contextVersion);
  // Steps 2-4 (the frame's clear, the objects, the billboards; `bare`: the floor's), the state saved.
  void drawScene(const FixedFrame& frame, const std::vector<Billboard>& billboards, const FixedStyle& style, bool bare);
  std::unique_ptr<Impl> impl_;
  int cellSize_;
  std::string contextVersion_;
};

}  // namespace puff::fixedfunc
