#pragma once
/// \file
/// Streamlines (VTK's vtkStreamTracer): curves everywhere tangent to a vector field, integrated
/// from seed points through `ImageData`, `StructuredGrid`, `UnstructuredGrid` or `PolyData`
/// with RK2, RK4 or adaptive RK45, forward, backward or both. Method, step units and
/// measurements: docs/algorithms/streamline.md.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

enum class StreamIntegrator { RK2, RK4, RK45 };
enum class StreamDirection { Forward, Backward, Both };

/// Why a streamline ended: the values of VTK's "ReasonForTermination" array.
enum class StreamTermination : std::uint8_t {
  OutOfDomain = 1,  ///< the next step left the dataset (or entered a cell without vectors)
  OutOfLength = 4,  ///< `max_length` reached
  OutOfSteps = 5,   ///< `max_steps` taken
  Stagnation = 6,   ///< speed fell below `terminal_speed`
};

struct StreamlineOptions {
  /// Point array of 3 components to follow; "" = the active vectors.
  std::string vectors;
  StreamIntegrator integrator = StreamIntegrator::RK45;
  StreamDirection direction = StreamDirection::Both;
  /// Step lengths in cell lengths (the input's mean cell size: its bounding-box diagonal over
  /// the d-th root of its cell count, d its dimension), all > 0. RK2 and RK4 take `step`;
  /// RK45 starts with it and adapts within [min_step, max_step].
  double step = 0.2;
  double min_step = 0.01;
  double max_step = 1.0;
  /// RK45: the largest local position error of an accepted step, in cell lengths (> 0).
  double max_error = 1e-6;
  std::size_t max_steps = 2000;  ///< per direction, ≥ 1
  /// Arc length of one direction, world units (> 0; infinity: no limit).
  double max_length = std::numeric_limits<double>::infinity();
  /// Speeds at or below this stop a line (≥ 0).
  double terminal_speed = 1e-12;
  /// Adds "Vorticity" (the curl of the field, a point vector), "AngularVelocity" (half the
  /// vorticity along the flow direction), "Rotation" (its integral over time, radians) and
  /// "Normals" (active: a frame carried along the line, turned by the rotation; `ribbon`
  /// orients stream ribbons by it) at every line point.
  bool vorticity = true;
  ProgressCallback progress{};  ///< fraction of seeds done; false cancels
};

struct StreamlineStats {
  std::size_t seeds = 0;           ///< seed points
  std::size_t seeds_outside = 0;   ///< seeds in no cell of the input (no line)
  std::size_t lines = 0;           ///< polylines written (one per seed and direction)
  std::size_t points = 0;          ///< their points
  std::size_t steps = 0;           ///< accepted integration steps
  std::size_t rejected_steps = 0;  ///< RK45 steps redone with a smaller step
  /// Lines ended by each reason, indexed by the `StreamTermination` value.
  std::array<std::size_t, 7> by_reason{};
  double cell_length = 0;          ///< the step unit, world units
};

using StreamlineResult = Result<PolyData, StreamlineStats>;

/// Streamlines of `input`'s vector field from the points of `seeds` (any dataset; its cells
/// are ignored). Each seed inside the input gives one polyline per direction, starting at the
/// seed (a backward line runs against the flow). Line points carry every point array of the
/// input interpolated, "IntegrationTime" (negative backward), "ArcLength" and, with
/// `vorticity`, "Vorticity", "AngularVelocity", "Rotation" and "Normals"; line cells carry
/// "SeedIds" (the seed's point id) and "ReasonForTermination" (`StreamTermination`). A step
/// that would leave the domain is halved down to `min_step` (RK45) or 1/1024 of `step`, so
/// lines end close to the boundary. Seeds are integrated in parallel; the output does not
/// depend on the thread count.
/// \throw Error if the input is invalid, has no such 3-component point array, the options are
/// out of range (non-finite, ≤ 0 steps, min_step > max_step, max_steps 0) or the seeds hold a
/// non-finite point; `Cancelled` through the progress callback.
[[nodiscard]] StreamlineResult streamlines(DatasetRef input, DatasetRef seeds,
                                           const StreamlineOptions& options = {});

}  // namespace isoforge
