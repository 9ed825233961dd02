#include <puff/mesh/mesh.h>

namespace puff::mesh {

using nlohmann::json;

namespace {

// Reads a recorded parameter, keeping the default when it is absent.
template <class T>
Result<void> param(const json& params, const char* key, T& out, const std::string& where) {
  if (!params.contains(key)) return {};
  try {
    out = params.at(key).get<T>();
  } catch (const json::exception&) {
    return Error{where + "/params/" + key + ": not a number of the right kind"};
  }
  return {};
}

}  // namespace

bool isGeneratorKind(const std::string& kind) { return kind == "sphere" || kind == "lumpy" || kind == "cluster"; }

json generatorToJson(const Generator& g) {
  if (g.kind == "sphere") return {{"subdivisions", g.sphere.subdivisions}};
  if (g.kind == "lumpy") {
    const LumpyParams& p = g.lumpy;
    return {{"subdivisions", p.subdivisions},
            {"amplitude", p.amplitude},
            {"frequency", p.frequency},
            {"octaves", p.octaves},
            {"seed", p.seed}};
  }
  const ClusterParams& p = g.cluster;
  return {{"count", p.count},   {"radiusMin", p.radiusMin},       {"radiusMax", p.radiusMax},
          {"spread", p.spread}, {"subdivisions", p.subdivisions}, {"seed", p.seed}};
}

Result<Generator> generatorFromJson(const std::string& kind, const json& p, const std::string& where) {
  Generator g;
  g.kind = kind;
  if (kind == "sphere") {
    PUFF_TRY(param(p, "subdivisions", g.sphere.subdivisions, where));
  } else if (kind == "lumpy") {
    PUFF_TRY(param(p, "subdivisions", g.lumpy.subdivisions, where));
    PUFF_TRY(param(p, "amplitude", g.lumpy.amplitude, where));
    PUFF_TRY(param(p, "frequency", g.lumpy.frequency, where));
    PUFF_TRY(param(p, "octaves", g.lumpy.octaves, where));
    PUFF_TRY(param(p, "seed", g.lumpy.seed, where));
  } else if (kind == "cluster") {
    PUFF_TRY(param(p, "count", g.cluster.count, where));
    PUFF_TRY(param(p, "radiusMin", g.cluster.radiusMin, where));
    PUFF_TRY(param(p, "radiusMax", g.cluster.radiusMax, where));
    PUFF_TRY(param(p, "spread", g.cluster.spread, where));
    PUFF_TRY(param(p, "subdivisions", g.cluster.subdivisions, where));
    PUFF_TRY(param(p, "seed", g.cluster.seed, where));
  } else {
    return Error{where + "/generator: \"" + kind + "\" is not a generator this build knows"};
  }
  return g;
}

Result<TriMesh> generate(const Generator& g) {
  if (g.kind == "sphere") {
    PUFF_TRY(validate(g.sphere));
    return generateSphere(g.sphere);
  }
  if (g.kind == "lumpy") {
    PUFF_TRY(validate(g.lumpy));
    return generateLumpy(g.lumpy);
  }
  if (g.kind == "cluster") {
    PUFF_TRY(validate(g.cluster));
    return generateCluster(g.cluster);
  }
  return Error{"\"" + g.kind + "\" is not a generator (sphere, lumpy or cluster)"};
}

}  // namespace puff::mesh
