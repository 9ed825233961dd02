#include <algorithm>
#include <cmath>

#include <puff/bake/baker.h>

namespace puff::bake {

MapDifference compareCells(const CellMaps& ref, const CellMaps& cand) {
  PUFF_CHECK(ref.body.width == cand.body.width && ref.body.height == cand.body.height);
  for (const CellMaps* m : {&ref, &cand}) {
    PUFF_CHECK(m->normalDepth.width == m->body.width && m->normalDepth.height == m->body.height &&
               m->color.width == m->body.width && m->color.height == m->body.height);
  }
  MapDifference diff;
  double normalSum = 0.0, depthSum = 0.0, colorSum = 0.0;
  std::size_t both = 0;  // texels both cover
  for (int y = 0; y < ref.body.height; ++y) {
    for (int x = 0; x < ref.body.width; ++x) {
      if (ref.body.at(x, y) >= 0.5f && cand.body.at(x, y) >= 0.5f) {
        for (int c = 0; c < 3; ++c) {
          // Encoded units: (N+1)/2, so half the difference of the decoded normals.
          normalSum += 0.5 * std::abs(ref.normalDepth.at(x, y, c) - cand.normalDepth.at(x, y, c));
          colorSum += std::abs(ref.color.at(x, y, c) - cand.color.at(x, y, c));
        }
        // d, puff diameters toward the viewer: how far the surface moved in depth.
        depthSum += std::abs(ref.normalDepth.at(x, y, 3) - cand.normalDepth.at(x, y, 3));
        ++both;
      }
      const float dr = ref.distance.at(x, y), dc = cand.distance.at(x, y);
      if (std::min(std::abs(dr), std::abs(dc)) <= 1.0f) {
        diff.silhouetteTexels = std::max(diff.silhouetteTexels, std::abs(dr - dc));
      }
    }
  }
  if (both > 0) {
    const double n = static_cast<double>(both);
    diff.meanNormalError = static_cast<float>(normalSum / (3.0 * n));
    diff.meanColorError = static_cast<float>(colorSum / (3.0 * n));
    diff.meanDepthError = static_cast<float>(depthSum / n);
  }
  return diff;
}

LodResult chooseLod(const mesh::TriMesh& full,
                    const std::function<std::vector<CellMaps>(const mesh::TriMesh&)>& rasterize,
                    const LodTolerances& tolerances, mesh::DecimatedNormals normals, mesh::TriMesh* chosen,
                    const std::function<void(int step, int maxSteps)>& onStep) {
  const std::vector<CellMaps> reference = rasterize(full);
  LodResult result;
  result.facesBefore = result.facesAfter = full.faceCount();
  if (chosen) *chosen = full;

  auto evaluate = [&](const mesh::TriMesh& candidate, MapDifference& worst) {
    const std::vector<CellMaps> maps = rasterize(candidate);
    worst = {};
    for (std::size_t v = 0; v < maps.size(); ++v) {
      const MapDifference d = compareCells(reference[v], maps[v]);
      worst.meanNormalError = std::max(worst.meanNormalError, d.meanNormalError);
      worst.silhouetteTexels = std::max(worst.silhouetteTexels, d.silhouetteTexels);
      worst.meanDepthError = std::max(worst.meanDepthError, d.meanDepthError);
      worst.meanColorError = std::max(worst.meanColorError, d.meanColorError);
    }
    return worst.meanNormalError <= tolerances.normal && worst.silhouetteTexels <= tolerances.silhouette &&
           worst.meanDepthError <= tolerances.depth && worst.meanColorError <= tolerances.color;
  };

  // Invariant: `hi` faces is known to pass (the full mesh does, with zero error).
  std::size_t lo = std::min<std::size_t>(full.faceCount(), 8), hi = full.faceCount();
  const int maxSteps = static_cast<int>(std::ceil(std::log2(static_cast<double>(hi - lo) + 1.0)));
  while (lo < hi) {
    if (onStep) onStep(result.evaluations, maxSteps);
    const std::size_t mid = lo + (hi - lo) / 2;
    mesh::TriMesh candidate = mesh::decimate(full, mid, normals);
    MapDifference d;
    ++result.evaluations;
    if (evaluate(candidate, d)) {
      hi = std::min(mid, candidate.faceCount());
      if (candidate.faceCount() < result.facesAfter) {
        result.facesAfter = candidate.faceCount();
        result.normalError = d.meanNormalError;
        result.silhouetteError = d.silhouetteTexels;
        result.depthError = d.meanDepthError;
        result.colorError = d.meanColorError;
        if (chosen) *chosen = std::move(candidate);
      }
    } else {
      lo = mid + 1;
    }
  }
  return result;
}

}  // namespace puff::bake
