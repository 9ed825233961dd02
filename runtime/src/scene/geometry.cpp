#include <map>

#include <puff/scene/geometry.h>

namespace puff::scene {

Result<SceneGeometry> loadGeometry(const Scene& scene) {
  SceneGeometry g;
  std::shared_ptr<const mesh::TriMesh> plane, box, sphere;
  std::map<std::filesystem::path, std::shared_ptr<const mesh::TriMesh>> files;
  for (const ObjectSpec& o : scene.objects) {
    std::shared_ptr<const mesh::TriMesh> shape;
    switch (o.type) {
      case ObjectSpec::Type::kPlane:
        if (!plane) plane = std::make_shared<const mesh::TriMesh>(mesh::makePlane());
        shape = plane;
        break;
      case ObjectSpec::Type::kBox:
        if (!box) box = std::make_shared<const mesh::TriMesh>(mesh::makeBox());
        shape = box;
        break;
      case ObjectSpec::Type::kSphere:
        if (!sphere) sphere = std::make_shared<const mesh::TriMesh>(mesh::makeSphere());
        shape = sphere;
        break;
      case ObjectSpec::Type::kMesh: {
        auto& loaded = files[o.mesh];
        if (!loaded) {
          PUFF_TRY_ASSIGN(auto m, mesh::loadMesh(o.mesh));
          loaded = std::make_shared<const mesh::TriMesh>(std::move(m));
        }
        shape = loaded;
        break;
      }
    }
    g.shapes.push_back(std::move(shape));
  }
  return g;
}

}  // namespace puff::scene
