// Distances of meshes to one reference (see reference_distance.hpp).

#include "reference_distance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "isoforge/core/mesh_topology.hpp"
#include "mesh_distance.hpp"

namespace isoforge::verify {

namespace {

struct OneWay {
  double max = 0, rms = 0;
};

OneWay measure_one_way(const Samples& s, const MeshDistance& to) {
  const std::vector<double> d = to.distances(s.points);
  OneWay w;
  double sum = 0, wsum = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    w.max = std::max(w.max, d[i]);
    sum += s.weights[i] * d[i] * d[i];
    wsum += s.weights[i];
  }
  w.rms = wsum > 0 ? std::sqrt(sum / wsum) : 0.0;
  return w;
}

// Samples of `mesh`, about `budget` at most (see ReferenceDistance), and the spacing used (0 for
// points and centroids).
std::pair<Samples, double> budget_samples(const PolyData& mesh, double spacing,
                                          std::size_t budget) {
  const auto tris = triangulate_faces(mesh);
  const auto P = [&](Index id) { return mesh.points[static_cast<std::size_t>(id)]; };
  if (7 * tris.size() > budget) {
    Samples s;
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      s.points.push_back(mesh.points[i]);
      s.weights.push_back(0);
    }
    for (const auto& t : tris) {
      s.points.push_back((P(t[0]) + P(t[1]) + P(t[2])) / 3.0);
      s.weights.push_back(0.5 * norm(cross(P(t[1]) - P(t[0]), P(t[2]) - P(t[0]))));
    }
    return {std::move(s), 0.0};
  }
  std::vector<double> longest(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const auto& t = tris[f];
    longest[f] =
        std::max({norm(P(t[1]) - P(t[0])), norm(P(t[2]) - P(t[1])), norm(P(t[0]) - P(t[2]))});
  }
  const auto count = [&](double h) {  // sample_mesh's count at spacing h
    std::size_t c = 0;
    for (const double l : longest) {
      std::size_t n = std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(l / h)));
      n += n % 2;
      c += (n + 1) * (n + 2) / 2 + 1;
    }
    return c;
  };
  for (std::size_t c = count(spacing); c > budget; c = count(spacing)) {
    spacing *= 1.05 * std::sqrt(static_cast<double>(c) / static_cast<double>(budget));
  }
  return {sample_mesh(mesh, spacing), spacing};
}

}  // namespace

ReferenceDistance::ReferenceDistance(const PolyData& reference, double spacing,
                                     std::size_t max_samples)
    : diagonal_(reference.bounds().diagonal()),
      spacing_(spacing > 0 ? spacing : 0.5 * mean_edge_length(reference)),
      max_samples_(max_samples),
      tree_(std::make_unique<MeshDistance>(reference)) {
  auto [samples, used] = budget_samples(reference, spacing_, max_samples_);
  samples_ = std::move(samples);
  reference_spacing_ = used;
}

ReferenceDistance::~ReferenceDistance() = default;

ReferenceError ReferenceDistance::measure(const PolyData& mesh) const {
  const MeshDistance tree(mesh);
  const OneWay ab = measure_one_way(samples_, tree);
  const auto [mesh_samples, mesh_spacing] = budget_samples(mesh, spacing_, max_samples_);
  const OneWay ba = measure_one_way(mesh_samples, *tree_);
  ReferenceError e;
  e.hausdorff = std::max(ab.max, ba.max);
  e.rms = std::sqrt(0.5 * (ab.rms * ab.rms + ba.rms * ba.rms));
  e.max_ref_to_mesh = ab.max;
  e.max_mesh_to_ref = ba.max;
  e.rms_ref_to_mesh = ab.rms;
  e.rms_mesh_to_ref = ba.rms;
  e.relative_hausdorff = e.hausdorff / diagonal_;
  e.relative_rms = e.rms / diagonal_;
  e.spacing_mesh = mesh_spacing;
  e.samples_mesh = mesh_samples.points.size();
  return e;
}

}  // namespace isoforge::verify
