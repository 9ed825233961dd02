// A one-variation atlas of the unit sphere for tests that need analytic shapes: its silhouette is
// a circle, its depth map sqrt(1/4 - r^2) diameters. Needs a current GL context; no GoogleTest.
#pragma once

#include <filesystem>

#include <puff/bake/baker.h>
#include <puff/mesh/mesh.h>

namespace puff::test {

/// Bakes into `dir` (128-texel cells, a 4-texel flange, no contact sheet; `viewGrid` x `viewGrid`
/// views laid out by `layout`) and returns the sidecar.
inline Result<std::filesystem::path> bakeSphereAtlas(const std::filesystem::path& dir, int viewGrid = 1,
                                                     bake::ViewLayout layout = bake::BakeOptions{}.viewLayout) {
  bake::BakeOptions o;
  o.cellSize = 128;
  o.flange = {4.0f, false};
  o.viewGrid = viewGrid;
  o.viewLayout = layout;
  o.outDir = dir;
  o.contactSheet = false;
  bake::PuffSource src;
  src.mesh = mesh::generateSphere({6});
  src.provenance.generator = "sphere";
  src.provenance.params = {{"subdivisions", 6}};  // what the cel reference regenerates it from
  PUFF_TRY_ASSIGN(auto r, bake::bakeAtlas({src}, o));
  return r.sidecar;
}

}  // namespace puff::test
