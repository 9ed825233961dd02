#include <puff/bake/baker.h>

#include "atlas_files.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <new>

#include <puff/bake/raster.h>
#include <puff/core/files.h>
#include <puff/core/number_text.h>

namespace puff::bake {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// What one bake may hold in memory. Per sample of the cell being resolved: two RGBA32F GL
// targets, their readback copies, masks, two distance transforms and the signed distances
// (about 100 bytes), and with the back map (multi-view atlases) an R32F target, its readback and
// its samples (12 more). Per atlas texel at level 0: the decoded maps (9 floats, 10 with the back
// map), the mip chain (a third more) and one encoded copy at a time (about 64 bytes).
constexpr double kMaxBakeBytes = 12.0 * (1u << 30);
constexpr double kBytesPerSample = 100.0, kBackBytesPerSample = 12.0, kBytesPerAtlasTexel = 64.0;

// The most samples per texel side, up to 4, that keep a cell within 4096^2 samples; at least 2
// (clean edges) while that fits the memory budget on its own.
int autoSupersample(int cellSize) {
  const int ss = std::clamp(4096 / cellSize, 1, 4);
  if (ss >= 2) return ss;
  return std::pow(2.0 * cellSize, 2.0) * kBytesPerSample <= kMaxBakeBytes / 2 ? 2 : 1;
}

struct Geometry {
  int supersample, margin, content, columns, rows, views;
  float flange;
};

std::string gib(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f GiB", bytes / (1u << 30));
  return b;
}

// Readers take a relative source path from the sidecar's directory (the reference and the fixed
// path load the mesh again), so a mesh named relative to the working directory is stored relative
// to the output directory; an absolute one stays absolute.
std::string pathFromSidecar(const std::string& path, const fs::path& outDir) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  std::error_code ec;
  const fs::path mesh = fs::weakly_canonical(fs::absolute(path), ec);
  const fs::path dir = ec ? fs::path() : fs::weakly_canonical(fs::absolute(outDir), ec);
  if (ec) return fs::absolute(path).string();
  const fs::path relative = mesh.lexically_relative(dir);
  return relative.empty() ? mesh.string() : relative.generic_string();
}

Result<Geometry> planGeometry(const BakeOptions& o, int variations) {
  Geometry g{};
  g.supersample = o.supersample > 0 ? o.supersample : autoSupersample(o.cellSize);
  if (static_cast<long long>(o.cellSize) * g.supersample > kMaxCellSize) {
    return Error{"--size " + std::to_string(o.cellSize) + " with --supersample " + std::to_string(g.supersample) +
                 " is " + std::to_string(o.cellSize * g.supersample) + " samples across, above the " +
                 std::to_string(kMaxCellSize) + " a GL framebuffer can hold"};
  }
  // Each side of a cell keeps a margin: the flange rounded up, then a guard band so the flange's
  // antialiased edge and the first mip levels stay clear of the cell border. Checked in floating
  // point before any cast: a flange of 1e10 texels must not wrap an int.
  const auto guardBand = [](int size) { return std::max(2, size / 32); };
  const auto contentOf = [&](int size) {
    return size - 2.0 * (std::ceil(double(o.flange.texels(size))) + guardBand(size));
  };
  if (contentOf(o.cellSize) < 4.0) {
    int least = o.cellSize + 1;  // a percentage flange grows with the cell, so search
    while (least <= kMaxCellSize && contentOf(least) < 4.0) ++least;
    const double flange = o.flange.texels(o.cellSize);
    std::string fix = least <= kMaxCellSize ? "; the least --size that fits is " + std::to_string(least) : "";
    if (flange > 0.0) fix += (fix.empty() ? "; " : ", or ") + std::string("lower --flange");
    return Error{"--size " + std::to_string(o.cellSize) + " leaves no room for the puff: each side of the cell keeps " +
                 "the flange (" + core::numberText(static_cast<float>(flange)) + " texels, rounded up) and a " +
                 std::to_string(guardBand(o.cellSize)) + "-texel guard band, and the puff needs 4 texels" + fix};
  }
  g.flange = o.flange.texels(o.cellSize);
  g.margin = static_cast<int>(std::ceil(g.flange)) + guardBand(o.cellSize);
  g.content = o.cellSize - 2 * g.margin;
  g.views = o.viewGrid * o.viewGrid;
  const int cells = variations * g.views;
  g.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cells))));
  g.rows = (cells + g.columns - 1) / g.columns;
  if (static_cast<long long>(g.columns) * o.cellSize > kMaxAtlasSize ||
      static_cast<long long>(g.rows) * o.cellSize > kMaxAtlasSize) {
    return Error{"the atlas would be " + std::to_string(g.columns * o.cellSize) + "x" +
                 std::to_string(g.rows * o.cellSize) + " texels, above the " + std::to_string(kMaxAtlasSize) +
                 " limit: lower --size, --views or the variation count"};
  }
  const double samples = std::pow(static_cast<double>(o.cellSize) * g.supersample, 2.0);
  const double atlasTexels = static_cast<double>(cells) * o.cellSize * o.cellSize;
  const double perSample = kBytesPerSample + (g.views > 1 ? kBackBytesPerSample : 0.0);
  const double bytes = samples * perSample + atlasTexels * kBytesPerAtlasTexel;
  if (bytes > kMaxBakeBytes) {
    return Error{"--size " + std::to_string(o.cellSize) + " x " + std::to_string(cells) + " cells at --supersample " +
                 std::to_string(g.supersample) + " needs about " + gib(bytes) + ", more than the " +
                 gib(kMaxBakeBytes) + " a bake may use: lower --size, --supersample, --views or the variations"};
  }
  return g;
}

// --lod auto's chosen mesh of one variation. PLY: binary-exact enough (9 digits), carries colours and normals.
std::string lodFileName(const std::string& name, int variation) {
  return name + "_lod" + std::to_string(variation) + ".ply";
}

std::string mapFileName(const std::string& name, const char* map, int level, const std::string& ext) {
  return name + "_" + map + (level == 0 ? "" : ".mip" + std::to_string(level)) + "." + ext;
}

// The atlas's layout and its maps' format; the cells, sources and map files are added as they are made.
core::AtlasDesc describeAtlas(const BakeOptions& o, const Geometry& g, int variations) {
  const int cellSize = o.cellSize;
  core::AtlasDesc desc;
  desc.fileFormat = o.format == MapFormat::kExr ? "exr" : "png";
  desc.cellSize = cellSize;
  desc.columns = g.columns;
  desc.rows = g.rows;
  desc.width = g.columns * cellSize;
  desc.height = g.rows * cellSize;
  desc.margin = g.margin;
  desc.contentSize = g.content;
  desc.supersample = g.supersample;
  desc.flangeTexels = g.flange;
  desc.distanceRange = static_cast<float>(g.margin);
  desc.mipLevels = o.mips ? mipLevelCount(cellSize) : 1;
  desc.variations = variations;
  desc.views = g.views;
  desc.viewGrid = o.viewGrid;
  desc.viewLayout = o.viewLayout == ViewLayout::kOct ? "oct" : "hemioct";
  return desc;
}

// Renders a mesh from every view direction and resolves each view into a cell's maps: with the
// bake's rasterizer, or (for --lod auto's trials) a cheaper one.
struct ViewRenderer {
  ViewRenderer(const BakeOptions& options, const Geometry& geometry) : o(options), g(geometry) {}

  const BakeOptions& o;
  const Geometry& g;
  std::unique_ptr<PuffRasterizer> rasterizer, lodRasterizer;
  int lodSupersample = 1;
  SampleBuffer samples;
  std::vector<glm::vec3> viewDirs;

  Result<void> create() {
    PUFF_TRY_ASSIGN(rasterizer, PuffRasterizer::create(o.cellSize * g.supersample,
                                                       g.views > 1 ? RasterSides::kFrontAndBack : RasterSides::kFront));
    // --lod auto rasterizes a mesh a dozen times or more; two samples per texel side still place
    // silhouettes to a quarter texel, and cost a quarter of four.
    lodSupersample = std::min(g.supersample, 2);
    if (o.lodAuto && lodSupersample != g.supersample) {
      PUFF_TRY_ASSIGN(auto lod, PuffRasterizer::create(o.cellSize * lodSupersample));
      lodRasterizer = std::move(lod);
    }
    viewDirs.resize(static_cast<std::size_t>(g.views));
    for (int v = 0; v < g.views; ++v)
      viewDirs[static_cast<std::size_t>(v)] = viewDirection(o.viewLayout, o.viewGrid, v);
    return {};
  }

  // `back`: with the back map (a multi-view atlas's; --lod auto's trials compare without it).
  std::vector<CellMaps> render(PuffRasterizer& r, int ss, const mesh::TriMesh& m, float flange, bool back) {
    r.setMesh(m, o.defaultColor);
    std::vector<CellMaps> maps;
    for (const glm::vec3& dir : viewDirs) {
      r.render(viewRotation(dir), g.margin * ss, g.content * ss, samples,
               back ? RasterSides::kFrontAndBack : RasterSides::kFront);
      maps.push_back(resolveCell(samples, ss, flange));
    }
    return maps;
  }

  PuffRasterizer& lodRaster() { return lodRasterizer ? *lodRasterizer : *rasterizer; }
};

// One bake's description and report, filled as the variations are rasterized and the files written.
struct AtlasBake {
  const BakeOptions& o;
  const Geometry& g;
  const ProgressFn& progress;
  core::AtlasDesc desc;
  BakeReport result;
  std::deque<mesh::TriMesh> lodMeshes;  // --lod auto: each variation's chosen mesh, written beside the atlas

  void report(std::string_view stage, int done, int total) const {
    if (progress) progress(stage, done, total);
  }

  // One variation's views (its level of detail chosen first with --lod auto) into level 0, its
  // cells and source into the description.
  void rasterizeVariation(ViewRenderer& views, const PuffSource& src, int var, AtlasLevel& level0) {
    const int cellSize = o.cellSize;
    const int totalCells = desc.variations * g.views;
    const mesh::TriMesh* bakeMesh = &src.mesh;
    mesh::TriMesh reduced;
    if (o.lodAuto) {
      const std::string stage = "choosing level of detail, variation " + std::to_string(var);
      const LodTolerances tolerances{o.lodNormalTolerance, o.lodSilhouetteTolerance, o.lodDepthTolerance,
                                     o.lodColorTolerance};
      LodResult lod = chooseLod(
          src.mesh,
          [&](const mesh::TriMesh& m) { return views.render(views.lodRaster(), views.lodSupersample, m, 0.0f, false); },
          tolerances, src.normalsAuthored ? mesh::DecimatedNormals::kFromSource : mesh::DecimatedNormals::kRecompute,
          &reduced, [&](int step, int maxSteps) { report(stage, step, maxSteps); });
      result.lod.push_back(lod);
      lodMeshes.push_back(std::move(reduced));
      bakeMesh = &lodMeshes.back();
    } else {
      result.lod.emplace_back();
    }
    core::AtlasSource prov = src.provenance;
    prov.path = pathFromSidecar(prov.path, o.outDir);
    prov.faces = src.mesh.faceCount();
    prov.facesBaked = bakeMesh->faceCount();
    prov.defaultColor = o.defaultColor;
    if (o.lodAuto) prov.lodMesh = lodFileName(o.name, var);
    desc.sources.push_back(prov);
    if (o.lodAuto) report("rasterizing", var * g.views, desc.variations * g.views);
    const std::vector<CellMaps> cells =
        views.render(*views.rasterizer, g.supersample, *bakeMesh, g.flange, !level0.back.pixels.empty());
    for (int v = 0; v < g.views; ++v) {
      const int index = var * g.views + v;
      core::AtlasCell cell;
      cell.variation = var;
      cell.view = v;
      cell.rect = {(index % g.columns) * cellSize, (index / g.columns) * cellSize, cellSize, cellSize};
      cell.viewDir = views.viewDirs[static_cast<std::size_t>(v)];
      const glm::mat3 rot = viewRotation(cell.viewDir);
      cell.viewUp = glm::vec3(rot[0][1], rot[1][1], rot[2][1]);  // second row
      placeCell(level0, cells[static_cast<std::size_t>(v)], cell.rect[0], cell.rect[1]);
      desc.cells.push_back(cell);
      report("rasterizing", index + 1, totalCells);
    }
  }

  // Writes every map level (named by its content), the LOD meshes, the contact sheet and the
  // sidecar to staged files; the renames at the end make the bake appear whole, the sidecar's last,
  // and then the atlas it replaced is removed (atlas_files.h).
  Result<void> write(const std::vector<AtlasLevel>& levels) {
    core::OutputTransaction tx;
    PUFF_TRY(tx.prepareDirectory(o.outDir));
    const fs::path sidecar = o.outDir / (o.name + ".json");
    const std::vector<fs::path> replaced = detail::filesNamedBy(sidecar);
    const std::string ext = desc.fileFormat;
    const core::PixelType mapType = o.format == MapFormat::kExr ? core::PixelType::kHalf : core::PixelType::kUInt8;
    const core::PixelType distType = o.format == MapFormat::kExr ? core::PixelType::kHalf : core::PixelType::kUInt16;
    // Every file: the maps, the LOD meshes, the contact sheets (the main one, and one per variation
    // of a multi-view atlas) and the sidecar.
    const int sheets = o.contactSheet ? 1 + (desc.views > 1 ? desc.variations : 0) : 0;
    const bool back = !levels[0].back.pixels.empty();
    const int totalFiles = desc.mipLevels * (back ? 4 : 3) + 1 + sheets + static_cast<int>(lodMeshes.size());
    int written = 0;
    report("writing", 0, totalFiles);
    std::vector<fs::path> contentNamed;  // the files a killed run would leave behind
    // Each file is staged, written, then named by its content (NAME_color.mip1.HASH.png).
    auto put = [&](const char* map, const char* key, int level, const core::Image& img,
                   core::PixelType type) -> Result<void> {
      const fs::path staged = tx.stage(o.outDir / mapFileName(o.name, map, level, ext));
      PUFF_TRY(core::writeImage(staged, img, type, {{"puff:map", map}, {"puff:level", std::to_string(level)}},
                                o.outDir / mapFileName(o.name, map, level, ext)));
      PUFF_TRY_ASSIGN(auto target, tx.nameByContent(staged));
      desc.maps[key].levels.push_back(target.filename().string());
      result.files.push_back(target);
      contentNamed.push_back(target);
      report("writing", ++written, totalFiles);
      return {};
    };
    for (int l = 0; l < desc.mipLevels; ++l) {
      const AtlasLevel& lv = levels[static_cast<std::size_t>(l)];
      PUFF_TRY(put("normal_depth", "normalDepth", l, encodeNormalDepth(lv.normalDepth), mapType));
      PUFF_TRY(put("color", "color", l, lv.color, mapType));
      PUFF_TRY(put("distance", "distance", l, encodeDistance(lv.distance, desc.distanceRange), distType));
      if (back) PUFF_TRY(put("back", "back", l, encodeBack(lv.back), mapType));
    }
    // The meshes the atlas was baked from, with the normals the bake used, so a consumer that draws
    // the mesh itself (the fixed path) draws the same level of detail.
    for (std::size_t var = 0; var < lodMeshes.size(); ++var) {
      const fs::path staged = tx.stage(o.outDir / lodFileName(o.name, static_cast<int>(var)));
      PUFF_TRY(mesh::saveMesh(lodMeshes[var], staged, mesh::SaveNormals::kYes));
      PUFF_TRY_ASSIGN(auto target, tx.nameByContent(staged));
      desc.sources[var].lodMesh = target.filename().string();
      result.files.push_back(target);
      contentNamed.push_back(target);
      result.lodMeshes.push_back(target);
      report("writing", ++written, totalFiles);
    }
    PUFF_TRY(writeContactSheet(tx, levels[0], [&] { report("writing", ++written, totalFiles); }));
    result.sidecar = sidecar;
    // Paths need not be UTF-8 on Linux: replace what JSON cannot hold rather than throw.
    const std::string text = core::toJson(desc).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    PUFF_TRY(core::writeFileBytes(tx.stage(result.sidecar), text, result.sidecar));
    result.files.push_back(result.sidecar);
    report("writing", totalFiles, totalFiles);
    // What killed runs left, then this run's own list, then the renames; the sidecar's is last.
    detail::removeAbandoned(o.outDir, o.name, sidecar);
    detail::writePending(o.outDir, o.name, contentNamed);
    PUFF_TRY(tx.commit());
    detail::removeSuperseded(o.outDir, o.name, replaced, result.files);
    if (!o.contactSheet && !replaced.empty()) {
      std::error_code ec;  // the replaced atlas's contact sheet would show what is no longer there
      fs::remove(o.outDir / (o.name + "_contact.png"), ec);
    }
    if (!replaced.empty()) removeStaleViewSheets();
    result.desc = std::move(desc);
    return {};
  }

  // The replaced atlas's view sheets (NAME_contact_vI.png) that this bake did not write again:
  // views or variations it no longer has.
  void removeStaleViewSheets() const {
    const std::string prefix = o.name + "_contact_v";
    std::error_code ec;
    std::vector<fs::path> stale;
    for (const auto& e : fs::directory_iterator(o.outDir, ec)) {
      const std::string n = e.path().filename().string();
      if (n.size() <= prefix.size() + 4 || n.rfind(prefix, 0) != 0 || n.substr(n.size() - 4) != ".png") continue;
      const std::string digits = n.substr(prefix.size(), n.size() - prefix.size() - 4);
      if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
      if (std::find(result.viewSheets.begin(), result.viewSheets.end(), e.path()) == result.viewSheets.end()) {
        stale.push_back(e.path());
      }
    }
    for (const fs::path& p : stale) fs::remove(p, ec);
  }

  Result<void> writeContactSheet(core::OutputTransaction& tx, const AtlasLevel& level0,
                                 const std::function<void()>& wrote) {
    if (!o.contactSheet) return {};
    result.contactSheet = o.outDir / (o.name + "_contact.png");
    const int thumb = std::min(o.cellSize, 160);
    // One row per variation, up to a sheet about 8192 pixels tall; beyond that the first ones only.
    result.contactSheetRows = std::min(desc.variations, 8192 / (thumb + 4));
    const core::Image sheet = contactSheet(level0, desc, thumb, result.contactSheetRows);
    PUFF_TRY(core::writeImage(tx.stage(result.contactSheet), sheet, core::PixelType::kUInt8, {}, result.contactSheet));
    result.files.push_back(result.contactSheet);
    wrote();
    // A multi-view atlas: each variation's views as a grid, at most about 2048 pixels on a side;
    // numbered from 0, as a scene's "variations" count them.
    if (desc.views > 1) {
      for (int v = 0; v < desc.variations; ++v) {
        const fs::path file = o.outDir / (o.name + "_contact_v" + std::to_string(v) + ".png");
        const core::Image views = viewSheet(level0, desc, v, 2048);
        PUFF_TRY(core::writeImage(tx.stage(file), views, core::PixelType::kUInt8, {}, file));
        result.viewSheets.push_back(file);
        result.files.push_back(file);
        wrote();
      }
    }
    return {};
  }
};

}  // namespace

Result<void> validate(const BakeOptions& o, int variations) {
  if (o.cellSize < 8 || o.cellSize > kMaxCellSize) {
    return Error{"--size must be in [8, " + std::to_string(kMaxCellSize) + "], got " + std::to_string(o.cellSize)};
  }
  if (o.supersample < 0 || o.supersample > 16)
    return Error{"--supersample must be in [0, 16], got " + std::to_string(o.supersample)};
  if (!(o.flange.value >= 0.0f) || !std::isfinite(o.flange.value) ||
      (o.flange.fractionOfCell && o.flange.value >= 0.5f)) {
    return Error{"--flange must be a finite width >= 0 (texels, or a percentage below 50%)"};
  }
  if (o.viewGrid < 1 || o.viewGrid > 16) return Error{"--views must be in [1, 16], got " + std::to_string(o.viewGrid)};
  for (int c = 0; c < 3; ++c) {
    if (!(o.defaultColor[c] >= 0.0f && o.defaultColor[c] <= 1.0f)) return Error{"--color components must be in [0, 1]"};
  }
  if (!(o.lodNormalTolerance > 0.0f) || !(o.lodSilhouetteTolerance > 0.0f) || !(o.lodDepthTolerance > 0.0f) ||
      !(o.lodColorTolerance > 0.0f)) {
    return Error{
        "--lod-normal-tolerance, --lod-silhouette-tolerance, --lod-depth-tolerance and --lod-color-tolerance must be "
        "positive"};
  }
  // A leading dot would hide the atlas's files (and "." or ".." make "..json").
  if (o.name.empty() || o.name.find('/') != std::string::npos || o.name.front() == '.')
    return Error{"--name must be a plain file prefix (no '/', not starting with '.'), got \"" + o.name + "\""};
  if (variations < 1) return Error{"nothing to bake: give mesh files or --generate"};
  PUFF_TRY(planGeometry(o, variations));
  return {};
}

Result<std::vector<PuffSource>> loadSources(const std::vector<fs::path>& meshFiles,
                                            const std::optional<GeneratorSpec>& gen, const ProgressFn& progress) {
  std::vector<PuffSource> sources;
  const int files = static_cast<int>(meshFiles.size());
  for (const fs::path& file : meshFiles) {
    if (progress) progress("loading meshes", static_cast<int>(sources.size()), files);
    // The bytes for the provenance hash, read first so that a file that cannot be read says why; one
    // over the size limit is not read here, and loadMesh refuses it without reading it.
    std::error_code ec;
    const bool tooLarge = fs::is_regular_file(file, ec) && fs::file_size(file, ec) > mesh::kMaxMeshFileBytes;
    std::string bytes;
    if (!tooLarge) {
      auto read = core::readFileBytes(file);
      if (!read) return read.error();
      bytes = std::move(*read);
    }
    mesh::LoadInfo info;
    Result<mesh::TriMesh> m = Error{};
    try {
      m = mesh::loadMesh(file, &info);
    } catch (const std::bad_alloc&) {  // a header declaring billions of elements
      return Error::at(file, "out of memory while reading (does the header declare absurd counts?)");
    } catch (const std::exception& e) {
      return Error::at(file, std::string("cannot read: ") + e.what());
    }
    if (!m) return m.error();
    PuffSource s;
    s.provenance.path = file.string();
    s.provenance.hash = "fnv1a64:" + core::fnv1a64Hex(bytes);
    s.provenance.faces = m->faceCount();
    s.normalsAuthored = info.hadNormals;
    s.separatedFaces = info.separatedFaces;
    s.volumeFraction = info.volumeFraction;
    s.mesh = std::move(*m);
    sources.push_back(std::move(s));
  }
  if (progress && files > 0) progress("loading meshes", files, files);
  if (gen) {
    if (gen->count < 1 || gen->count > 256)
      return Error{"--variations must be in [1, 256], got " + std::to_string(gen->count)};
    for (int i = 0; i < gen->count; ++i) {
      if (progress) progress("generating puffs", i, gen->count);
      PuffSource s;
      s.provenance.generator = gen->kind;
      if (!mesh::isGeneratorKind(gen->kind)) {
        return Error{"--generate must be sphere, lumpy or cluster, got \"" + gen->kind + "\""};
      }
      // Each variation is the generator with its seed advanced by the variation's index.
      mesh::Generator g{gen->kind, gen->sphere, gen->lumpy, gen->cluster};
      g.lumpy.seed += static_cast<std::uint64_t>(i);
      g.cluster.seed += static_cast<std::uint64_t>(i);
      PUFF_TRY_ASSIGN(s.mesh, mesh::generate(g));
      s.provenance.params = mesh::generatorToJson(g);
      s.provenance.faces = s.mesh.faceCount();
      sources.push_back(std::move(s));
    }
    if (progress) progress("generating puffs", gen->count, gen->count);
  }
  return sources;
}

Result<BakeReport> bakeAtlas(const std::vector<PuffSource>& sources, const BakeOptions& o, const ProgressFn& progress) {
  const int variations = static_cast<int>(sources.size());
  PUFF_TRY(validate(o, variations));
  const Geometry g = *planGeometry(o, variations);
  AtlasBake bake{o, g, progress, describeAtlas(o, g, variations), {}, {}};

  ViewRenderer views{o, g};
  PUFF_TRY(views.create());

  const core::AtlasDesc& desc = bake.desc;
  AtlasLevel level0{core::Image(desc.width, desc.height, 4),
                    core::Image(desc.width, desc.height, 4),
                    core::Image(desc.width, desc.height, 1, desc.distanceRange),
                    {}};
  for (std::size_t i = 2; i < level0.normalDepth.pixels.size(); i += 4) level0.normalDepth.pixels[i] = 1.0f;  // N = +z
  // The back map bounds a puff seen from any side (the tumbling hull): only a multi-view atlas's.
  if (desc.views > 1) level0.back = core::Image(desc.width, desc.height, 1, kNoBack);

  // Each stage says when it starts (0 done), so that its clock and rate count its first step too.
  for (int var = 0; var < variations; ++var) {
    if (!o.lodAuto || var > 0) bake.report("rasterizing", var * g.views, variations * g.views);
    bake.rasterizeVariation(views, sources[static_cast<std::size_t>(var)], var, level0);
  }

  std::vector<AtlasLevel> levels;
  levels.push_back(std::move(level0));
  if (desc.mipLevels > 1) bake.report("mip levels", 0, desc.mipLevels - 1);
  for (int l = 1; l < desc.mipLevels; ++l) {
    levels.push_back(buildMipLevel(levels[0], o.cellSize, l, desc.alphaThreshold));
    bake.report("mip levels", l, desc.mipLevels - 1);
  }

  PUFF_TRY(bake.write(levels));
  return std::move(bake.result);
}

}  // namespace puff::bake
