// puff_cook_scene: a scene and every asset it names, cooked (bake/cook.h), so that a program without
// an image library renders it: the GPU benchmark's scenes (tests/bench/gpu.sh, docs/bench/gpu.md).
//   puff_cook_scene SCENE.json -o OUT.json [--art-dir DIR] [-q]
// OUT.json is the scene with its assets in OUT.cooked/ beside it: the atlas as atlas.json
// (bake::cookAtlas), the ramp, ambient gradient, plate and media detail videos as ramp.puffimg,
// gradient.puffimg, plate.puffimg, temperature-detail.puffimg and opacity-detail.puffimg
// (bake::cookImage), the objects' meshes and the fixed path's puff mesh copied as they are (Puff
// reads them itself) as mesh-N.EXT, one per source file. The scene is written last, with every field
// (scene::toJson) and its paths relative to it, so a scene already at OUT.json is replaced only once
// its assets are in place. It renders exactly as SCENE.json does. Errors: one line, exit 1 (2 for
// bad usage).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>

#include <puff/bake/cook.h>
#include <puff/core/files.h>
#include <puff/io/openimageio.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include <cli/app.h>

#include "bench_usage.h"

namespace fs = std::filesystem;

namespace puff {

namespace {

// Adds what one cooked asset wrote to the scene's whole.
void add(bake::Cooked& total, const bake::Cooked& one) {
  total.files.insert(total.files.end(), one.files.begin(), one.files.end());
  total.bytesRead += one.bytesRead;
  total.bytesWritten += one.bytesWritten;
}

// Cooks the image at `path` (if any) into assets/NAME.puffimg and points `path` there.
Result<void> cookImageField(fs::path& path, const fs::path& assets, const char* name, bake::Cooked& total) {
  if (path.empty()) return {};
  const fs::path to = assets / (std::string(name) + ".puffimg");
  PUFF_TRY_ASSIGN(auto cooked, bake::cookImage(path, to));
  add(total, cooked);
  path = to;
  return {};
}

// Copies the mesh at `path` (if any) into assets/mesh-N.EXT, once per source file (`copied`), and
// points `path` there.
Result<void> copyMesh(fs::path& path, const fs::path& assets, std::map<fs::path, fs::path>& copied,
                      bake::Cooked& total) {
  if (path.empty()) return {};
  auto it = copied.find(path);
  if (it == copied.end()) {
    const fs::path to = assets / ("mesh-" + std::to_string(copied.size()) + path.extension().string());
    PUFF_TRY_ASSIGN(auto bytes, core::readFileBytes(path));
    PUFF_TRY(core::writeFileAtomic(to, bytes));
    total.files.push_back(to);
    total.bytesRead += bytes.size();
    total.bytesWritten += bytes.size();
    it = copied.emplace(path, to).first;
  }
  path = it->second;
  return {};
}

}  // namespace

// The scene at `in` and its assets cooked into `out` (see the file's comment).
Result<bake::Cooked> cookScene(const fs::path& in, const fs::path& out, const fs::path& artDir) {
  PUFF_TRY_ASSIGN(scene::Scene s, scene::loadScene(in, artDir));
  std::error_code ec;
  if (out.extension() != ".json") return Error::at(out, "a scene cooks into a scene: name a .json file");
  if (fs::weakly_canonical(in, ec) == fs::weakly_canonical(out, ec)) {
    return Error::at(out, "is the scene being cooked; name another file for the cooked scene");
  }
  const fs::path assets = out.parent_path() / (out.stem().string() + ".cooked");
  bake::Cooked total;
  if (!s.atlas.empty()) {
    const fs::path to = assets / "atlas.json";
    PUFF_TRY_ASSIGN(auto cooked, bake::cookAtlas(s.atlas, to));
    add(total, cooked);
    s.atlas = to;
  }
  PUFF_TRY(cookImageField(s.ramp, assets, "ramp", total));
  PUFF_TRY(cookImageField(s.ambientGradient, assets, "gradient", total));
  PUFF_TRY(cookImageField(s.plate, assets, "plate", total));
  if (s.media) {
    PUFF_TRY(cookImageField(s.media->temperatureDetail, assets, "temperature-detail", total));
    PUFF_TRY(cookImageField(s.media->opacityDetail, assets, "opacity-detail", total));
  }
  std::map<fs::path, fs::path> meshes;
  for (scene::ObjectSpec& object : s.objects) PUFF_TRY(copyMesh(object.mesh, assets, meshes, total));
  PUFF_TRY(copyMesh(s.fixed.puff, assets, meshes, total));
  s.file = out;
  const std::string text = scene::jsonText(scene::toJson(s)) + "\n";
  PUFF_TRY(core::writeFileAtomic(out, text));
  total.files.push_back(out);
  total.bytesRead += fs::file_size(in, ec);
  total.bytesWritten += text.size();
  return total;
}

}  // namespace puff

using namespace puff;

namespace {

constexpr const char* kUsage =
    "usage: puff_cook_scene SCENE.json -o OUT.json [--art-dir DIR] [-q]\n"
    "Writes the scene to OUT.json with every asset it names cooked into OUT.cooked/ beside it (the atlas and\n"
    "images as Puff's .puffimg, which puff::core reads with no image library; meshes copied), the scene last.\n"
    "  -o FILE        the cooked scene (.json)\n"
    "  -q             print errors only\n"
    "  --art-dir DIR  ";

int usage(const char* argument) {
  if (!bench::isHelp(argument)) std::fprintf(stderr, "puff_cook_scene: error: %s\n", argument);
  std::fprintf(bench::usageStream(argument), "%s%s\n", kUsage, cli::kArtDirHelp);
  return bench::usageExit(argument);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path in, out, artDir;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    if (bench::isHelp(a)) return usage(a);
    if ((!std::strcmp(a, "-o") || !std::strcmp(a, "--art-dir")) && i + 1 < argc) {
      (!std::strcmp(a, "-o") ? out : artDir) = argv[++i];
    } else if (!std::strcmp(a, "-q")) {
      quiet = true;
    } else if (a[0] != '-' && in.empty()) {
      in = a;
    } else {
      return usage((std::string("unknown or incomplete argument \"") + a + "\"").c_str());
    }
  }
  if (in.empty() || out.empty()) return usage("SCENE.json and -o OUT.json are required");
  if (artDir.empty()) artDir = cli::defaultArtDir();
  io::useOpenImageIO();
  auto cooked = cookScene(in, out, artDir);
  if (!cooked) {
    std::fprintf(stderr, "puff_cook_scene: error: %s\n", cooked.error().message.c_str());
    return 1;
  }
  if (!quiet) {
    std::printf("puff_cook_scene: wrote %s: scene cooked into %zu files, %ju bytes\n", out.c_str(),
                cooked->files.size(), cooked->bytesWritten);
  }
  return 0;
}
