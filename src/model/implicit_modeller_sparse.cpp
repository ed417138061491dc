// The implicit modeller into an OpenVDB narrow band (model/implicit_modeller_sparse.hpp).

#include "isoforge/model/implicit_modeller_sparse.hpp"

#include "isoforge/model/distance_sparse.hpp"
#include "modeller_internal.hpp"

namespace isoforge {

DistanceGridResult implicit_modeller_vdb(const PolyData& input, const ImplicitModellerOptions& o) {
  model_detail::check_modeller_input(input);
  const ModellerGrid mg = implicit_modeller_grid(input.bounds(), o);
  return distance_grid(input, mg.grid, model_detail::modeller_distance_options(o, mg.max_distance));
}

}  // namespace isoforge
