#include <map>
#include <string>

#include <puff/render/cel_scene.h>

namespace puff::render {

Result<core::Atlas> loadSceneAtlas(const scene::Scene& scene) {
  // A file's error names the scene and the JSON pointer that led to the file, then the file.
  auto atlas = core::loadAtlas(scene.atlas);
  if (!atlas) return Error::at(scene.file, "/atlas: " + atlas.error().message);
  if (scene.atlasLevel == 0) return atlas;
  auto level = core::atlasFromLevel(*atlas, scene.atlasLevel);
  if (!level) return Error::at(scene.file, "/atlasLevel: " + level.error().message);
  return level;
}

Result<void> checkOrientedPuffs(const scene::Scene& scene, const core::AtlasDesc& atlas) {
  if (atlas.views > 1) return {};
  const std::string where = scene::orientedPuffs(scene);
  if (where.empty()) return {};
  return Error::at(scene.file, where + ": oriented puffs turn in 3D, but the atlas " + scene.atlas.string() +
                                   " holds one view per variation; bake it with views from every side "
                                   "(puffbake bake --views 5 --view-layout oct, or hemioct) or drop oriented");
}

std::shared_ptr<const cel::TriangleMesh> toTriangleMesh(const mesh::TriMesh& m) {
  auto out = std::make_shared<cel::TriangleMesh>();
  out->positions = m.positions;
  out->normals = m.normals;
  out->indices.reserve(m.triangles.size() * 3);
  for (const glm::uvec3& t : m.triangles) {
    out->indices.insert(out->indices.end(), {t.x, t.y, t.z});
  }
  return out;
}

Result<std::unique_ptr<CelScene>> CelScene::create(const scene::Scene& scene, const scene::SceneGeometry& geometry) {
  std::unique_ptr<CelScene> c(new CelScene());
  PUFF_TRY_ASSIGN(c->opaque_, cel::OpaqueRenderer::create());
  if (!scene.ramp.empty()) {
    auto ramp = cel::Ramp::load(scene.ramp, scene.rampSmooth ? cel::RampFilter::kLinear : cel::RampFilter::kNearest);
    if (!ramp) return Error::at(scene.file, "/ramp: " + ramp.error().message);
    c->ramp_ = std::move(*ramp);
  } else {
    c->ramp_ = cel::Ramp::twoTone();
  }
  if (!scene.ambientGradient.empty()) {
    auto g = cel::Gradient::load(scene.ambientGradient);
    if (!g) return Error::at(scene.file, "/ambient/gradient: " + g.error().message);
    c->gradient_ = std::move(*g);
  }

  std::vector<cel::OpaqueObject> objects;
  std::map<const mesh::TriMesh*, std::shared_ptr<const cel::TriangleMesh>> uploaded;  // each shape converted once
  float floorHeight = 0.0f;
  bool haveFloor = false;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const scene::ObjectSpec& o = scene.objects[i];
    cel::OpaqueObject obj;
    obj.name = o.name.empty() ? "objects/" + std::to_string(i) : o.name;
    obj.transform = scene::objectTransform(o);
    obj.albedo = scene::linearAlbedo(o);
    obj.cel = o.cel;
    auto& mesh = uploaded[geometry.shapes[i].get()];
    if (!mesh) mesh = toTriangleMesh(*geometry.shapes[i]);
    obj.mesh = mesh;
    c->fitsShadowMap_.push_back(o.type != scene::ObjectSpec::Type::kPlane);
    // Shadow volumes may stop at the lowest horizontal plane: nothing below it is seen.
    if (o.type == scene::ObjectSpec::Type::kPlane && o.rotateDegrees == glm::vec3(0.0f) && o.path.empty() &&
        (!haveFloor || o.translate.y < floorHeight)) {
      floorHeight = o.translate.y;
      haveFloor = true;
    }
    objects.push_back(std::move(obj));
  }
  if (haveFloor) c->floorPlane_ = glm::vec4(0.0f, 1.0f, 0.0f, -floorHeight);
  if (auto set = c->opaque_->setObjects(std::move(objects)); !set) return Error::at(scene.file, set.error().message);
  return c;
}

CelScene::~CelScene() = default;

bool CelScene::needsRebuild(const scene::Scene& a, const scene::Scene& b) {
  return a.ramp != b.ramp || a.rampSmooth != b.rampSmooth || a.ambientGradient != b.ambientGradient ||
         a.objects != b.objects;
}

cel::Frame CelScene::prepare(const scene::Scene& s, const scene::FrameInputs& inputs, const cel::Viewport& viewport,
                             const cel::Viewport& drawViewport) {
  cel::Frame f{scene::sharedFrameFor(s, inputs.camera, viewport.width, viewport.height)};
  f.viewport = drawViewport;
  f.ambientGradient = gradient_.has_value();
  ramp_->bind();
  if (gradient_) gradient_->bind();
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    if (s.objects[i].path.empty()) continue;
    auto moved = opaque_->setTransform(i, scene::objectTransform(s.objects[i], inputs.time));
    PUFF_CHECK(moved.ok());  // the scene's checks keep transforms finite and invertible
  }
  return f;
}

cel::OpaqueRenderer& CelScene::opaque() { return *opaque_; }
cel::FrameBlock& CelScene::block() { return block_; }
glm::vec4 CelScene::floorPlane() const { return floorPlane_; }

cel::Bounds CelScene::objectBounds() const {
  cel::Bounds b;
  for (std::size_t i = 0; i < opaque_->count(); ++i) b.add(opaque_->worldBounds(i));
  return b;
}

cel::Bounds CelScene::casterBounds() const {
  cel::Bounds b;
  for (std::size_t i = 0; i < fitsShadowMap_.size(); ++i) {
    if (fitsShadowMap_[i]) b.add(opaque_->worldBounds(i));
  }
  return b;
}

}  // namespace puff::render
