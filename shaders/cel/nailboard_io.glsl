// What the nailboards' vertex stage hands their fragment stage, declared once: `out` in the vertex
// stage (nailboard_vs.glsl), `in` in the fragment stage (nailboard_fs.glsl), and plain globals in
// the deferred shading pass (PUFF_DEFERRED), which computes them per pixel from the particle the
// visibility pre-pass left there (nailboard_setup.glsl). Needs PUFF_VIEWS.
#if defined(PUFF_DEFERRED)
#define PUFF_NB_VARYING
#define PUFF_NB_FLAT
#elif defined(PUFF_VERTEX_STAGE)
#define PUFF_NB_VARYING out
#define PUFF_NB_FLAT flat out
#else
#define PUFF_NB_VARYING in
#define PUFF_NB_FLAT flat in
#endif

PUFF_NB_VARYING vec2 vPuff;   // position on the billboard, puff diameters from the centre (x right, y up)
PUFF_NB_VARYING float vDist;  // camera-space distance along the view axis of the billboard plane here
PUFF_NB_VARYING vec3 vWorld;  // world-space point of the billboard plane here (shadow-map receivers)
PUFF_NB_FLAT uint vId;        // particle index + 1: the caster id of the shadow map (cel/shadow_map.glsl)
PUFF_NB_FLAT float vSize;
PUFF_NB_FLAT vec3 vTint;  // display multiplier of Eq. 2's C
PUFF_NB_FLAT float vTexelsPerPixel;  // level-0 atlas texels per screen pixel at the particle
PUFF_NB_FLAT ivec4 vCell;
PUFF_NB_FLAT vec4 vWeight;
PUFF_NB_FLAT vec4 vMap[PUFF_VIEWS];       // billboard (x, y) -> cell (x, y): columns (m00, m10), (m01, m11)
PUFF_NB_FLAT mat3 vNormalXf[PUFF_VIEWS];  // cell camera space -> camera (view) space
#if PUFF_VIEWS == 4
// An oriented puff's surface is found by marching its eye ray through the hull of its views
// (cel/hull_march.glsl, hullMarch), shaded by its four nearest views (vCell): the billboard's right,
// up and normal (toward the eye) in puff space, and puff space -> camera space.
PUFF_NB_FLAT int vHull;
PUFF_NB_FLAT int vHullBehind;  // a hemi-oct atlas seen from behind: some of the four cells stand for back views
PUFF_NB_FLAT mat3 vBillboardPuff;
PUFF_NB_FLAT mat3 vPuffToView;
#endif
#ifdef PUFF_HULL_OCCLUDER
// The occluder pass (hull_occluder.vert): the core's disc on the billboard (centre x, y and radius,
// puff diameters) and how far before the billboard plane its centre lies (view depth, world units).
PUFF_NB_FLAT vec4 vDisc;
#endif

// The outline switch and width (pixels), read by both stages: a small puff's quad grows to hold its band.
uniform int uOutlines;
uniform float uOutlineWidth;
