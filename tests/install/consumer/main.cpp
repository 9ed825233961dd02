// Bakes a generated puff through the installed library and loads it back through the sidecar,
// with the shaders embedded in the installed puff::core.
#include <cstdio>
#include <filesystem>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();  // the atlas is baked and read as PNG
  if (argc != 2) return 2;
  auto context = puff::core::createGlContext({});
  if (!context) {
    std::fprintf(stderr, "consumer: %s\n", context.error().message.c_str());
    return 1;
  }
  std::vector<puff::bake::PuffSource> sources(1);
  sources[0].mesh = puff::mesh::generateSphere({3});
  sources[0].provenance.generator = "sphere";
  puff::bake::BakeOptions options;
  options.cellSize = 32;
  options.outDir = argv[1];
  auto baked = puff::bake::bakeAtlas(sources, options);
  if (!baked) {
    std::fprintf(stderr, "consumer: %s\n", baked.error().message.c_str());
    return 1;
  }
  auto atlas = puff::core::loadAtlas(baked->sidecar);
  if (!atlas) {
    std::fprintf(stderr, "consumer: %s\n", atlas.error().message.c_str());
    return 1;
  }
  std::printf("consumer: %s: %dx%d atlas, %d mip levels\n", baked->sidecar.c_str(), atlas->desc.width,
              atlas->desc.height, atlas->desc.mipLevels);
  return atlas->desc.width == 32 ? 0 : 1;
}
