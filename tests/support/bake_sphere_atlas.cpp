// Bakes the tests' shared sphere atlas (sphere_bake.h) into a folder, once at build time: the suites
// that draw it copy the folder (sphere_atlas.h) instead of each baking their own.
#include <cstdio>
#include <filesystem>

#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>

#include "support/sphere_bake.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  puff::io::useOpenImageIO();  // the atlas's PNGs, as the tests read them
  auto context = puff::core::createGlContext({});
  if (!context) {
    std::fprintf(stderr, "%s: error: %s\n", argv[0], context.error().message.c_str());
    return 1;
  }
  const std::filesystem::path out = argv[1];
  std::error_code ignored;
  std::filesystem::remove_all(out, ignored);  // a stale bake's files (other content hashes) go
  auto sidecar = puff::test::bakeSphereAtlas(out);
  if (!sidecar) {
    std::fprintf(stderr, "%s: error: %s\n", argv[0], sidecar.error().message.c_str());
    return 1;
  }
  return 0;
}
