#pragma once
// Private: the block engine of the distance fields (distance_engine.cpp) — the Scatter and
// Gather strategies over blocks of samples — and what the dense, sparse and modeller entry
// points share around it. See distance_engine.cpp for the methods.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "distance_signs.hpp"
#include "isoforge/model/distance.hpp"
#include "isoforge/spatial/primitives.hpp"

namespace isoforge::model_detail {

using u64 = std::uint64_t;

// Auto picks Gather when the primitives' reach volumes add up to more than this many times the
// volume they cover together (measured: one Gather sample costs about as much as 20 Scatter
// kernel calls, counting the rows' setup).
constexpr double kGatherRatio = 20;
// The same for points and segments on the dense path, whose row kernels cost less per call
// (bench_model's crossover: a helix of 1k .. 1M segments at 128³, the rows win up to a ratio of
// about 600).
constexpr double kRowGatherRatio = 500;

// Blocks are 8 x 8 x kz samples: kz = 8 for OpenVDB leaves, 64 on the dense path (longer rows
// amortize the per-row setup of the scan conversion).
constexpr int kMaxBlockVoxels = 8 * 8 * 64;

struct Task {
  u64 key;
  std::size_t begin, end;  // Scatter: range of pairs
};

struct Pair {
  u64 key;
  u32 prim;
};

// One computed block; the sample (i, j, k) of the block is at offset (i * 8 + j) * kz + k (for
// kz = 8, OpenVDB's leaf offset).
struct BlockOut {
  Index i0, j0, k0;  // first sample
  int ni, nj, nk;    // samples inside the grid
  int kz;            // block depth along z
  double value[kMaxBlockVoxels];
  std::uint8_t active[kMaxBlockVoxels];
  // Scratch of the strategies.
  double d2[kMaxBlockVoxels], rv[kMaxBlockVoxels];
  u32 who[kMaxBlockVoxels];
  double rowmax[64];  // the largest d2 of each of the 8 x 8 rows (an upper bound)
  bool row_dirty = false;
  std::vector<std::pair<double, u32>> order;
  std::size_t n_active = 0;
  std::size_t evals = 0;
};

/// The primitives of `input` for a distance field, balls where `options.radius_array` names
/// radii. \throw Error naming the problem (empty input, bad radius array or radius).
[[nodiscard]] PrimitiveSet distance_primitives(const PolyData& input,
                                               const DistanceOptions& options);

/// \throw Error unless the grid (dims, finite origin, positive finite spacing on every axis, at
/// most 2^30 samples per axis) and max_distance (positive, finite) are usable.
void check_common(const GridSpec& g, const DistanceOptions& o);

/// The strategy `o` asks for, or (Auto) Gather when Scatter's estimated kernel calls exceed
/// `gather_ratio` times the samples within reach, for blocks of depth `kz`; fills the counts of
/// `stats`. \throw Error if Gather is asked for with radii.
DistanceStrategy choose_strategy(const PrimitiveSet& P, const GridSpec& g, const DistanceOptions& o,
                                 int kz, double gather_ratio, DistanceStats& stats);

/// Computes every block of 8 x 8 x kz samples within reach (by `o.strategy` or the one Auto
/// picks) and hands it to sink(task index, block) — in parallel, from TBB workers — after
/// calling prepare(number of tasks) once. Reports progress from 0 to 0.95 of `o.progress`.
void run_blocks(const PrimitiveSet& P, const Pseudonormals* signs, const GridSpec& g,
                const DistanceOptions& o, int kz, DistanceStats& stats,
                const std::function<void(std::size_t)>& prepare,
                const std::function<void(std::size_t, const BlockOut&)>& sink);

}  // namespace isoforge::model_detail
