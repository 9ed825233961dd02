// libFuzzer harness: a mesh file of one format (PUFF_FUZZ_MESH_EXT, e.g. ".ply"), loaded as puffbake
// loads its sources (mesh::loadMesh), then, when it loads, with its coordinates kept as a level of
// detail is.
#include <puff/mesh/mesh.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = puff::fuzz::writeInput(std::string("mesh") + PUFF_FUZZ_MESH_EXT, data, size);
  puff::mesh::LoadInfo info;
  auto mesh = puff::mesh::loadMesh(file, &info);
  puff::fuzz::expectCleanError(mesh);
  if (mesh.ok()) puff::fuzz::expectCleanError(puff::mesh::loadMesh(file, nullptr, puff::mesh::Normalize::kNo));
  return 0;
}
