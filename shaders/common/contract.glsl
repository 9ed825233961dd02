// What Puff's C++ and its GLSL must agree on, written once. The shaders #include this file; the
// libraries read it through <puff/shader_contract.h> (runtime/private), as C++ constants. Only
// #define lines and comments, which both languages read alike.
// The uniform blocks are mirrored by C++ structs (std140) whose sizes a GL test compares with
// what the driver reports for every program (ShaderContract, tests/unit/shader_test.cpp); binding points
// are assigned by name when a program is made (core::assignBindPoints), so none is fixed here.

// ---- limits: array lengths in the blocks and uniforms below ----
#define PUFF_MAX_LIGHTS 8       // explosion lights composed in one frame (ComposeBlock.uLights)
#define PUFF_MAX_MATERIALS 32   // media materials (MaterialBlock.uMaterials)
#define PUFF_MAX_FIRE_BANDS 8   // the cartoon fire's bands (CartoonBlock.uFireColors)
#define PUFF_MAX_BLUR_FRAMES 8  // frames motion blur averages (blur.frag: uHistory, uWeights)
#define PUFF_MAX_DEFERRED_SAMPLES 8  // samples per pixel the nailboards' deferred lit pass reads (more: every layer)

// ---- shade passes: the uPass of the nailboards and the opaque objects (cel::ShadePass) ----
#define PUFF_PASS_LIT 0         // Eq. 2 in full
#define PUFF_PASS_SHADOWED 1    // ambient only
#define PUFF_PASS_DEPTH_ONLY 2  // depth only, no colour

// ---- what the lit passes write: FrameBlock's uOutput.x (cel::FrameOutput) ----
#define PUFF_OUTPUT_COLOUR 0  // Eq. 2, scene-linear
#define PUFF_OUTPUT_NORMAL 1  // the camera-space normal n as 0.5 n + 0.5 (x right, y up, z toward the camera)
#define PUFF_OUTPUT_DEPTH 2   // 0.5 + (uOutputScale.x - view distance) * uOutputScale.y: nearer is brighter
#define PUFF_OUTPUT_INK 3     // the ink's share of the covered pixel, [0, 1]
#define PUFF_OUTPUT_MOTION 4  // the screen motion m to the next frame (pixels, x right, y up) as 0.5 + m * uOutputScale.z

// ---- uniform locations of the programs set by location ----
// media/blur.frag
#define PUFF_LOC_BLUR_COUNT 0
#define PUFF_LOC_BLUR_WEIGHTS 1  // PUFF_MAX_BLUR_FRAMES locations
#define PUFF_LOC_BLUR_VIEWPORT (PUFF_LOC_BLUR_WEIGHTS + PUFF_MAX_BLUR_FRAMES)
// media/downsample.frag
#define PUFF_LOC_DOWNSAMPLE_FACTOR 0
// media/resolve_depth.frag, media/resolve_host_depth_ms.frag
#define PUFF_LOC_RESOLVE_SAMPLES 0
// media/host_depth.glsl (the host-depth resolves)
#define PUFF_LOC_HOST_PROJ_ZW 1
#define PUFF_LOC_HOST_PLANES 2
#define PUFF_LOC_HOST_ORIGIN 3
// media/cartoon_flood.frag
#define PUFF_LOC_FLOOD_STEP 0
// output/view.frag
#define PUFF_LOC_VIEW_TRANSFORM 0
#define PUFF_LOC_VIEW_ORIGIN 1
#define PUFF_LOC_VIEW_KNEE 2
// output/plate.frag
#define PUFF_LOC_PLATE_ORIGIN 0
// cel/opaque.{vert,frag}, cel/opaque_caster.frag, reference/object_{light,id}
#define PUFF_LOC_OPAQUE_MODEL 0
#define PUFF_LOC_OPAQUE_NORMAL_MATRIX 1
#define PUFF_LOC_OPAQUE_ALBEDO 2
#define PUFF_LOC_OPAQUE_CEL 3
#define PUFF_LOC_OPAQUE_PASS 4
#define PUFF_LOC_OPAQUE_ID 5
// cel/opaque_volume.{vert,geom,frag} (the model matrix at PUFF_LOC_OPAQUE_MODEL)
#define PUFF_LOC_VOLUME_LENGTH 1
#define PUFF_LOC_VOLUME_FLOOR 2
#define PUFF_LOC_VOLUME_BIAS 3
