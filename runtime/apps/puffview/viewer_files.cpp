// What the viewer writes: scratch images (edited ramp and gradient, checkerboard), saved scenes, screenshots.
#include <puffview/viewer.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include <puff/cel/frame.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/scene/file_edit.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include <unistd.h>

namespace puff::view {

namespace fs = std::filesystem;

namespace {

fs::path normalAbsolute(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}

// Paths inside the art directory are written as "${PUFF_ART}/..." again, so a saved scene keeps
// working with another build's art directory (toJson writes them relative to the scene).
void restoreArtPaths(nlohmann::json& j, const fs::path& sceneDir, const fs::path& artDir) {
  if (artDir.empty()) return;
  const fs::path art = normalAbsolute(artDir);
  if (j.is_structured()) {
    for (auto& item : j) restoreArtPaths(item, sceneDir, artDir);
    return;
  }
  if (!j.is_string()) return;
  const std::string s = j.get<std::string>();
  if (s.empty() || s.starts_with("${")) return;
  const fs::path full = normalAbsolute(fs::path(s).is_absolute() ? fs::path(s) : sceneDir / s);
  const fs::path rel = full.lexically_relative(art);
  std::error_code ec;
  if (rel.empty() || *rel.begin() == ".." || !fs::is_regular_file(full, ec)) return;
  j = "${PUFF_ART}/" + rel.generic_string();
}

}  // namespace

// ---- scratch images --------------------------------------------------------------------------

const fs::path& Viewer::scratchDir() {
  if (scratch_.empty()) {
    std::error_code ec;
    const fs::path base = fs::temp_directory_path(ec);
    scratch_ = (ec ? fs::path("/tmp") : base) / ("puffview-" + std::to_string(::getpid()));
    fs::create_directories(scratch_, ec);
  }
  return scratch_;
}

Result<fs::path> Viewer::writeScratch(const char* kind, const core::Image& image) {
  std::string bytes(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size() * sizeof(float));
  bytes += std::to_string(image.width) + "x" + std::to_string(image.height) + "x" + std::to_string(image.channels);
  const fs::path file = scratchDir() / (std::string(kind) + "." + core::fnv1a64Hex(bytes).substr(0, 12) + ".png");
  std::error_code ec;
  if (fs::exists(file, ec)) return file;  // named by its content: already written
  core::OutputTransaction tx;
  PUFF_TRY(core::writeImage(tx.stage(file), image, core::PixelType::kUInt8, {}, file));
  PUFF_TRY(tx.commit());
  return file;
}

scene::Scene Viewer::shown(const scene::Scene& s) {
  if (!s.transparent) return s;
  // 8-pixel squares of two light greys (display values), one plate pixel per pixel of the image the
  // window shows at its own size (the plate is stretched to the frame drawn).
  // Made once per size: shown() runs on every edit, and the plate is the same file each time.
  const glm::ivec2 size = imageSize();
  if (size == checkerSize_ && !checkerPlate_.empty()) {
    scene::Scene copy = s;
    copy.transparent = false;
    copy.alpha.reset();
    copy.plate = checkerPlate_;
    return copy;
  }
  core::Image checker(size.x, size.y, 3);
  for (int y = 0; y < checker.height; ++y) {
    for (int x = 0; x < checker.width; ++x) {
      const float v = ((x / 8) + (y / 8)) % 2 == 0 ? 0.62f : 0.78f;
      for (int c = 0; c < 3; ++c) checker.at(x, y, c) = v;
    }
  }
  auto plate = writeScratch("checker", checker);
  if (!plate) {
    setStatus("cannot draw the checkerboard under the transparent frame: " + plate.error().message);
    return s;
  }
  checkerSize_ = size;
  checkerPlate_ = *plate;
  return shown(s);
}

Result<void> Viewer::setRamp(const core::Image& ramp) {
  PUFF_TRY(cel::Ramp::check(ramp, "the edited ramp"));
  PUFF_TRY_ASSIGN(auto file, writeScratch("ramp", ramp));
  scene_.ramp = file;
  return applyEdit();
}

Result<void> Viewer::setAmbientGradient(const core::Image& gradient) {
  PUFF_TRY(cel::Gradient::check(gradient, "the edited gradient"));
  PUFF_TRY_ASSIGN(auto file, writeScratch("gradient", gradient));
  scene_.ambientGradient = file;
  return applyEdit();
}

// ---- save ------------------------------------------------------------------------------------

fs::path Viewer::besideScene(const fs::path& target, const fs::path& image, const char* suffix) const {
  if (image.empty() || scratch_.empty() || image.parent_path() != scratch_) return image;
  return target.parent_path() / (target.stem().string() + suffix);
}

Result<void> Viewer::readerCheck(const scene::Scene& s) const {
  PUFF_TRY(scene::parseScene(scene::toJson(s), s.file, options_.artDir));
  return {};
}

nlohmann::json Viewer::writtenJson(const scene::Scene& s, const fs::path& target) const {
  scene::Scene copy = s;
  copy.file = target;  // toJson writes paths relative to where the file will be
  nlohmann::json j = scene::toJson(copy);
  restoreArtPaths(j, target.parent_path(), options_.artDir);
  return j;
}

Result<std::string> Viewer::sceneText(const scene::Scene& s, const fs::path& target, bool* wrote) const {
  const nlohmann::json after = writtenJson(s, target);
  if (auto check = scene::parseScene(after, target, options_.artDir); !check) return check.error();
  const std::string whole = scene::jsonText(after) + "\n";
  if (wrote) *wrote = diskText_.empty();
  if (diskText_.empty()) return whole;
  // The artist's file, changed only where the scene changed. The text must read back as the scene:
  // a field the file leaves out takes its default, which may follow a field the edit changed, so
  // whatever reads back otherwise is written out too; text that never reads back as the scene (or
  // a file that is not JSON) gives way to the whole scene.
  auto kept = scene::editSceneText(diskText_, writtenJson(saved_, saved_.file), after);
  for (int pass = 0; pass < 3 && kept; ++pass) {
    const nlohmann::json j = nlohmann::json::parse(*kept, nullptr, false);
    auto back = scene::parseScene(j, target, options_.artDir);
    if (!back) break;
    const nlohmann::json backJson = writtenJson(*back, target);
    if (backJson == after) return *kept;
    kept = scene::editSceneText(*kept, backJson, after);
  }
  if (wrote) *wrote = true;
  return whole;
}

Result<fs::path> Viewer::save(const fs::path& file) {
  auto saved = writeScene(file.empty() ? scene_.file : file);
  if (!saved) {
    setStatus(saved.error().message);
    if (!options_.quiet) std::fprintf(stderr, "puffview: error: %s\n", saved.error().message.c_str());
  }
  return saved;
}

Result<fs::path> Viewer::writeScene(const fs::path& target) {
  // Never write what would not load, and never overwrite newer text edits that failed to load.
  if (!editError_.empty()) {
    return Error::at(target, "not saved: the panel holds a value the scene rejects (" + editError_ + ")");
  }
  if (!fileError_.empty() && target == scene_.file) {
    return Error::at(target,
                     "not saved: the file on disk has edits that do not load (fix them there, or Save as another "
                     "file); saving would overwrite them");
  }
  // A ramp or gradient edited in the panel goes beside the scene file, and the saved scene names it
  // there. Everything is checked, then staged, then renamed into place together: a failure at any
  // step changes no file, and the viewer's scene stays as it was.
  scene::Scene out = scene_;
  out.ramp = besideScene(target, scene_.ramp, "_ramp.png");
  out.ambientGradient = besideScene(target, scene_.ambientGradient, "_gradient.png");
  bool wroteWhole = false;
  auto text = sceneText(out, target, &wroteWhole);
  if (!text) return Error::at(target, "not saved: " + text.error().message);
  core::OutputTransaction tx;
  for (const auto& [from, to] : {std::pair{scene_.ramp, out.ramp}, {scene_.ambientGradient, out.ambientGradient}}) {
    if (from == to) continue;
    std::error_code ec;
    fs::copy_file(from, tx.stage(to), fs::copy_options::overwrite_existing, ec);
    if (ec) return Error::at(to, "not saved: cannot write: " + ec.message());
  }
  if (auto r = core::writeFileBytes(tx.stage(target), *text, target); !r)
    return Error{"not saved: " + r.error().message};
  if (auto r = tx.commit(); !r) return Error{"not saved: " + r.error().message};
  diskText_ = *text;
  out.file = target;
  const bool moved = target != scene_.file;
  const fs::path oldAutosave = autosavePath();
  if (out.ramp != scene_.ramp || out.ambientGradient != scene_.ambientGradient) {
    scene_.ramp = committed_.ramp = out.ramp;
    scene_.ambientGradient = committed_.ambientGradient = out.ambientGradient;
    (void)applyEdit();
  }
  scene_.file = target;
  if (moved) {
    watchScene();
  } else {
    watcher_.markSeen(target);  // our own write is not an outside change to reload
  }
  markSaved();
  if (moved) {  // Save as: the edits kept under the old name are saved now too
    std::error_code ec;
    fs::remove(oldAutosave, ec);
  }
  // The artist's own text gave way to the whole scene, one key a line: said, not done silently.
  const std::string how =
      wroteWhole ? " (every field, one a line: the file as last read could not take the edits in place)" : "";
  setStatus("saved " + target.string() + how);
  if (!options_.quiet) std::printf("puffview: saved %s%s\n", target.c_str(), how.c_str());
  return target;
}

// ---- screenshots -----------------------------------------------------------------------------

Result<fs::path> Viewer::saveScreenshot(const fs::path& file) {
  fs::path target = file;
  if (target.empty()) {
    const fs::path dir = options_.screenshotDir.empty() ? scene_.file.parent_path() : options_.screenshotDir;
    char number[32];
    std::snprintf(number, sizeof number, "_f%04d", frame_);
    const std::string base = scene_.file.stem().string() + number;
    target = dir / (base + ".png");
    std::error_code ec;
    for (int k = 2; fs::exists(target, ec); ++k) target = dir / (base + "_" + std::to_string(k) + ".png");
  }
  PUFF_TRY_ASSIGN(auto image, readWindow());
  core::OutputTransaction tx;
  if (!target.parent_path().empty()) {
    if (auto r = tx.prepareDirectory(target.parent_path()); !r) return r.error();
  }
  const fs::path temp = tx.stage(target);
  if (auto r = core::writeImage(temp, image, core::PixelType::kUInt8, {}, "screenshot.png"); !r)
    return Error::at(target, r.error().message);
  if (auto r = tx.commit(); !r) return r.error();
  setStatus("screenshot " + target.string());
  return target;
}

}  // namespace puff::view
