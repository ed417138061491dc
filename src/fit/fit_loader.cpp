// The public fitting functions: they reach the Ceres-based implementations through
// detail/fit_ops.hpp (loading libisoforge_fit on the first call in a shared build).

#include "detail/fit_ops.hpp"
#include "isoforge/core/plugin.hpp"

namespace isoforge {

namespace {

const fit_detail::FitOps& ops(const char* what) {
#ifdef ISOFORGE_ONE_LIBRARY
  (void)what;
  return *isoforge_fit_ops();
#else
  using Entry = const fit_detail::FitOps* (*)();
  static const auto entry =
      reinterpret_cast<Entry>(plugin_symbol(ISOFORGE_FIT_LIBRARY, "isoforge_fit_ops", what));
  return *entry();
#endif
}

}  // namespace

FitResult fit_primitive(DatasetRef points, const FitOptions& options) {
  return ops("fit_primitive").fit_primitive(points, options);
}

RefineResult refine_mesh(const PolyData& original, const PolyData& simplified,
                         const RefineOptions& options) {
  return ops("refine_mesh").refine_mesh(original, simplified, options);
}

const char* to_string(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::Plane:
      return "plane";
    case PrimitiveKind::Sphere:
      return "sphere";
    case PrimitiveKind::Cylinder:
      return "cylinder";
    case PrimitiveKind::Cone:
      return "cone";
    case PrimitiveKind::Quadric:
      return "quadric";
  }
  return "?";
}

const char* to_string(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::None:
      return "none";
    case RobustLoss::Huber:
      return "huber";
    case RobustLoss::Cauchy:
      return "cauchy";
  }
  return "?";
}

}  // namespace isoforge
