// Booleans and offsets of distance fields (model/csg.hpp).
//
// Methods implemented: Boolean set operations on implicit functions as min/max (Ricci,
// "A constructive geometry for computer graphics", Computer Journal 16(2), 1973; the chapter's
// Equations 1.15-1.17); OpenVDB's narrow-band level-set CSG (Museth, "VDB", ACM TOG 32(3), 2013:
// tools::csgUnion/csgIntersection/csgDifference and their Copy forms); offsets of distance
// fields by a constant shift, with the narrow band re-trimmed to where values stay exact.

#include "isoforge/model/csg.hpp"

#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/io/vdb.hpp"

namespace isoforge {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void check_level_set(const openvdb::FloatGrid& g, const char* which) {
  if (g.getGridClass() != openvdb::GRID_LEVEL_SET) {
    throw Error(std::string("csg: grid ") + which + " ('" + g.getName() +
                "') is not a level set; offset an unsigned distance field first");
  }
  if (!(g.background() > 0)) {
    throw Error(std::string("csg: grid ") + which + " has background " + num(g.background()) +
                ", a level set needs a positive one");
  }
}

void check_same_transform(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  if (a.transform() != b.transform()) {
    throw Error("csg: the grids have different transforms (voxel size " + num(a.voxelSize()[0]) +
                " vs " + num(b.voxelSize()[0]) + "); sample both on the same grid");
  }
}

// Values − distance, re-banded to half width `band` (≤ background − |distance|): active values
// at or beyond it become inactive ±band, and every inactive value ±band by its sign.
void shift(openvdb::FloatGrid& field, double distance, double band) {
  const float nb = static_cast<float>(band);
  const float d = static_cast<float>(distance);
  using Leaf = openvdb::FloatTree::LeafNodeType;
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(field.tree());
  leaves.foreach ([&](Leaf& leaf, std::size_t) {
    for (openvdb::Index i = 0; i < Leaf::SIZE; ++i) {
      if (!leaf.isValueOn(i)) continue;
      const float v = leaf.getValue(i) - d;
      if (v >= nb) {
        leaf.setValueOff(i, nb);
      } else if (v <= -nb) {
        leaf.setValueOff(i, -nb);
      } else {
        leaf.setValueOnly(i, v);
      }
    }
  });
  openvdb::tools::changeLevelSetBackground(field.tree(), nb);
  openvdb::tools::pruneLevelSet(field.tree());
  field.setGridClass(openvdb::GRID_LEVEL_SET);
}

void shift(openvdb::FloatGrid& field, double distance) {
  const double bg = field.background();
  if (!(bg > 0)) {
    throw Error("offset: the field's background is " + num(bg) + ", must be positive");
  }
  if (!std::isfinite(distance)) throw Error("offset: the distance is not finite");
  if (!(std::abs(distance) < bg)) {
    throw Error("offset: |distance| = " + num(std::abs(distance)) +
                " is not inside the narrow band (half width " + num(bg) + ")");
  }
  shift(field, distance, bg - std::abs(distance));
}

// Gives the grid with the wider band the narrower one, so that both backgrounds are equal (the
// booleans are exact only where both inputs are known). Returns the grid to use for `g`.
const openvdb::FloatGrid& narrowed(const openvdb::FloatGrid& g, float band,
                                   openvdb::FloatGrid::Ptr& holder) {
  if (g.background() == band) return g;
  holder = g.deepCopy();
  shift(*holder, 0.0, band);
  return *holder;
}

const DataArray& scalars_of(const ImageData& img, const char* what) {
  const DataArray* s = img.point_data.scalars();
  if (!s) throw Error(std::string(what) + ": the image has no active scalars");
  if (s->components() != 1) {
    throw Error(std::string(what) + ": the scalars '" + s->name() + "' have " +
                std::to_string(s->components()) + " components, need 1");
  }
  return *s;
}

}  // namespace

std::string_view csg_operation_name(CsgOperation op) {
  switch (op) {
    case CsgOperation::Union:
      return "union";
    case CsgOperation::Intersection:
      return "intersection";
    case CsgOperation::Difference:
      return "difference";
  }
  return "?";
}

CsgOperation csg_operation_from_name(std::string_view name) {
  if (name == "union") return CsgOperation::Union;
  if (name == "intersection") return CsgOperation::Intersection;
  if (name == "difference") return CsgOperation::Difference;
  throw Error("csg: unknown operation '" + std::string(name) +
              "' (union, intersection or difference)");
}

openvdb::FloatGrid::Ptr csg(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b,
                            CsgOperation op) {
  ensure_openvdb_initialized();
  check_level_set(a, "A");
  check_level_set(b, "B");
  check_same_transform(a, b);
  const float band = std::min(a.background(), b.background());
  openvdb::FloatGrid::Ptr ha, hb;
  const openvdb::FloatGrid& na = narrowed(a, band, ha);
  const openvdb::FloatGrid& nb = narrowed(b, band, hb);
  openvdb::FloatGrid::Ptr r;
  switch (op) {
    case CsgOperation::Union:
      r = openvdb::tools::csgUnionCopy(na, nb);
      break;
    case CsgOperation::Intersection:
      r = openvdb::tools::csgIntersectionCopy(na, nb);
      break;
    case CsgOperation::Difference:
      r = openvdb::tools::csgDifferenceCopy(na, nb);
      break;
  }
  r->setGridClass(openvdb::GRID_LEVEL_SET);
  r->setName(a.getName());
  return r;
}

void csg_in_place(openvdb::FloatGrid& a, openvdb::FloatGrid& b, CsgOperation op) {
  ensure_openvdb_initialized();
  check_level_set(a, "A");
  check_level_set(b, "B");
  check_same_transform(a, b);
  const float band = std::min(a.background(), b.background());
  if (a.background() != band) shift(a, 0.0, band);
  if (b.background() != band) shift(b, 0.0, band);
  switch (op) {
    case CsgOperation::Union:
      openvdb::tools::csgUnion(a, b);
      break;
    case CsgOperation::Intersection:
      openvdb::tools::csgIntersection(a, b);
      break;
    case CsgOperation::Difference:
      openvdb::tools::csgDifference(a, b);
      break;
  }
  b.clear();  // OpenVDB 10 may leave some of B's nodes behind
}

ImageData csg(const ImageData& a, const ImageData& b, CsgOperation op) {
  a.validate();
  b.validate();
  if (a.dims != b.dims || !(a.origin == b.origin) || !(a.spacing == b.spacing)) {
    throw Error("csg: the images are not on the same grid (dims, origin and spacing must match)");
  }
  const DataArray& sa = scalars_of(a, "csg");
  const DataArray& sb = scalars_of(b, "csg");
  ImageData out;
  out.dims = a.dims;
  out.origin = a.origin;
  out.spacing = a.spacing;
  const std::size_t n = a.num_points();
  const auto combine = [op](double x, double y) {
    switch (op) {
      case CsgOperation::Union:
        return std::min(x, y);
      case CsgOperation::Intersection:
        return std::max(x, y);
      case CsgOperation::Difference:
        return std::max(x, -y);
    }
    return x;
  };
  if (sa.type() == ScalarType::Float32 && sb.type() == ScalarType::Float32) {
    DataArray r = DataArray::uninitialized(sa.name(), ScalarType::Float32, 1, n);
    const float* x = sa.values<float>().data();
    const float* y = sb.values<float>().data();
    float* z = r.values<float>().data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                        for (std::size_t i = rg.begin(); i != rg.end(); ++i) {
                          z[i] = static_cast<float>(combine(x[i], y[i]));
                        }
                      });
    out.point_data.add(std::move(r), AttributeRole::Scalars);
  } else {
    DataArray r = DataArray::uninitialized(sa.name(), ScalarType::Float64, 1, n);
    double* z = r.values<double>().data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                        for (std::size_t i = rg.begin(); i != rg.end(); ++i) {
                          z[i] = combine(sa.get(i), sb.get(i));
                        }
                      });
    out.point_data.add(std::move(r), AttributeRole::Scalars);
  }
  return out;
}

openvdb::FloatGrid::Ptr offset(const openvdb::FloatGrid& field, double distance) {
  ensure_openvdb_initialized();
  auto r = field.deepCopy();
  shift(*r, distance);
  return r;
}

void offset_in_place(openvdb::FloatGrid& field, double distance) {
  ensure_openvdb_initialized();
  shift(field, distance);
}

ImageData offset(const ImageData& field, double distance) {
  field.validate();
  if (!std::isfinite(distance)) throw Error("offset: the distance is not finite");
  const DataArray& s = scalars_of(field, "offset");
  ImageData out;
  out.dims = field.dims;
  out.origin = field.origin;
  out.spacing = field.spacing;
  DataArray r = s;
  r.visit([&](auto& buf) {
    using T = typename std::decay_t<decltype(buf)>::value_type;
    if constexpr (std::is_floating_point_v<T>) {
      const T d = static_cast<T>(distance);
      for (auto& v : buf) v -= d;
    } else {
      throw Error("offset: the scalars '" + s.name() + "' are not floating point");
    }
  });
  out.point_data.add(std::move(r), AttributeRole::Scalars);
  return out;
}

PolyData offset_surfaces(const ImageData& field, const std::vector<double>& distances,
                         ContourOptions options) {
  if (distances.empty()) throw Error("offset surfaces: no distances given");
  options.values = distances;
  return contour_image(field, options);
}

PolyData offset_surfaces(const openvdb::FloatGrid& field, const std::vector<double>& distances,
                         ContourOptions options) {
  if (distances.empty()) throw Error("offset surfaces: no distances given");
  const double bg = field.background();
  for (double d : distances) {
    if (!(std::abs(d) < bg)) {
      throw Error("offset surfaces: distance " + num(d) +
                  " is not inside the narrow band (half "
                  "width " +
                  num(bg) + ")");
    }
  }
  options.values = distances;
  return contour_vdb(field, options);
}

}  // namespace isoforge
