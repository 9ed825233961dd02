// puff_cook_scene: a scene and every asset it names, cooked (bake/cook.h), so that a program without
// an image library renders it: the GPU benchmark's scenes (tests/bench/gpu.sh, docs/bench/gpu.md).
//   puff_cook_scene SCENE.json -o OUT.json [--art-dir DIR] [-q]
// OUT.json is the scene with its assets in OUT.cooked/ beside it: the atlas as atlas.json
// (bake::cookAtlas), the ramp, ambient gradient, plate and media detail videos as ramp.puffimg,
// gradient.puffimg, plate.puffimg, temperature-detail.puffimg and opacity-detail.puffimg
// (bake::cookImage), the objects' meshes and the fixed path's puff mesh copied as they are (Puff
// reads them itself) as mesh-N.EXT, one per source file. The scene is written last, with every field
// (scene::toJson) and its paths relative to it. The assets are cooked into a hidden folder beside it
// first and put in place of OUT.cooked/ whole, so a failed cook changes nothing. The cel path renders
// it exactly as SCENE.json; the atlas's source meshes (which the fixed path and the cel reference
// read, not the cel path) stay where the atlas names them. Errors: one line, exit 1 (2 for bad
// usage).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>

#include <unistd.h>

#include <puff/bake/cook.h>
#include <puff/core/files.h>
#include <puff/io/openimageio.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include <cli/app.h>

#include "bench_usage.h"
#include "harness.h"

namespace fs = std::filesystem;

namespace puff {

namespace {

// Adds what one cooked asset wrote to the scene's whole.
void add(bake::Cooked& total, const bake::Cooked& one) {
  total.files.insert(total.files.end(), one.files.begin(), one.files.end());
  total.bytesRead += one.bytesRead;
  total.bytesWritten += one.bytesWritten;
}

// Where assets are written (`staged`, a folder renamed to `final` once all are there) and where the
// scene names them (`final`).
struct Dirs {
  fs::path staged, final;
};

// Cooks the image at `path` (if any) into NAME.puffimg and points `path` there.
Result<void> cookImageField(fs::path& path, const Dirs& dirs, const char* name, bake::Cooked& total) {
  if (path.empty()) return {};
  const std::string file = std::string(name) + ".puffimg";
  PUFF_TRY_ASSIGN(auto cooked, bake::cookImage(path, dirs.staged / file));
  add(total, cooked);
  path = dirs.final / file;
  return {};
}

// Copies the mesh at `path` (if any) as mesh-N.EXT, once per source file (`copied`), and points
// `path` there.
Result<void> copyMesh(fs::path& path, const Dirs& dirs, std::map<fs::path, fs::path>& copied, bake::Cooked& total) {
  if (path.empty()) return {};
  auto it = copied.find(path);
  if (it == copied.end()) {
    const std::string file = "mesh-" + std::to_string(copied.size()) + path.extension().string();
    PUFF_TRY_ASSIGN(auto bytes, core::readFileBytes(path));
    PUFF_TRY(core::writeFileAtomic(dirs.staged / file, bytes));
    total.files.push_back(dirs.final / file);
    total.bytesRead += bytes.size();
    total.bytesWritten += bytes.size();
    it = copied.emplace(path, dirs.final / file).first;
  }
  path = it->second;
  return {};
}

// Cooks every asset `s` names into dirs.staged and points `s` at them in dirs.final.
Result<void> cookAssets(scene::Scene& s, const Dirs& dirs, bake::Cooked& total) {
  if (!s.atlas.empty()) {
    PUFF_TRY_ASSIGN(auto cooked, bake::cookAtlas(s.atlas, dirs.staged / "atlas.json"));
    add(total, cooked);
    s.atlas = dirs.final / "atlas.json";
  }
  PUFF_TRY(cookImageField(s.ramp, dirs, "ramp", total));
  PUFF_TRY(cookImageField(s.ambientGradient, dirs, "gradient", total));
  PUFF_TRY(cookImageField(s.plate, dirs, "plate", total));
  if (s.media) {
    PUFF_TRY(cookImageField(s.media->temperatureDetail, dirs, "temperature-detail", total));
    PUFF_TRY(cookImageField(s.media->opacityDetail, dirs, "opacity-detail", total));
  }
  std::map<fs::path, fs::path> meshes;
  for (scene::ObjectSpec& object : s.objects) PUFF_TRY(copyMesh(object.mesh, dirs, meshes, total));
  return copyMesh(s.fixed.puff, dirs, meshes, total);
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
  const std::string stem = out.stem().string(), pid = std::to_string(getpid());
  const fs::path dir = out.parent_path();
  const Dirs dirs{dir / ("." + stem + ".cooked.tmp-" + pid), dir / (stem + ".cooked")};
  const bench::ScopedDir staged{dirs.staged};  // gone once renamed into place, or on an error
  bake::Cooked total;
  PUFF_TRY(cookAssets(s, dirs, total));
  // The new assets in place of the old (set aside until the scene is written), then the scene.
  const fs::path old = dir / ("." + stem + ".cooked.old-" + pid);
  const bool hadOld = fs::exists(dirs.final, ec);
  if (hadOld) fs::rename(dirs.final, old, ec);
  if (!ec) fs::rename(dirs.staged, dirs.final, ec);
  if (ec) {
    const std::string why = ec.message();
    if (hadOld && !fs::exists(dirs.final)) fs::rename(old, dirs.final, ec);
    return Error::at(dirs.final, "cannot put the cooked assets in place: " + why);
  }
  s.file = out;
  const std::string text = scene::jsonText(scene::toJson(s)) + "\n";
  if (auto written = core::writeFileAtomic(out, text); !written) {
    fs::remove_all(dirs.final, ec);
    if (hadOld) fs::rename(old, dirs.final, ec);
    return written.error();
  }
  if (hadOld) fs::remove_all(old, ec);
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
