// Booleans and offsets of distance fields (model/csg_sparse.hpp).
//
// Methods implemented: Boolean set operations on implicit functions as min/max (Ricci,
// "A constructive geometry for computer graphics", Computer Journal 16(2), 1973; the chapter's
// Equations 1.15-1.17); OpenVDB's narrow-band level-set CSG (Museth, "VDB", ACM TOG 32(3), 2013:
// tools::csgUnion/csgIntersection/csgDifference and their Copy forms); offsets of distance
// fields by a constant shift, with the narrow band re-trimmed to where values stay exact.

#include "isoforge/model/csg_sparse.hpp"

#include <fmt/format.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include <cmath>
#include <string>

#include "isoforge/sparse/grid.hpp"

namespace isoforge {

namespace {

void check_level_set(const openvdb::FloatGrid& g, const char* which) {
  if (g.getGridClass() != openvdb::GRID_LEVEL_SET) {
    throw Error(std::string("csg: grid ") + which + " ('" + g.getName() +
                "') is not a level set; offset an unsigned distance field first");
  }
  if (!(g.background() > 0)) {
    throw Error(fmt::format("csg: grid {} has background {:g}, a level set needs a positive one",
                            which, g.background()));
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
    throw Error(fmt::format("offset: the field's background is {:g}, must be positive", bg));
  }
  if (!std::isfinite(distance)) throw Error("offset: the distance is not finite");
  if (!(std::abs(distance) < bg)) {
    throw Error(
        fmt::format("offset: |distance| = {:g} is not inside the narrow band (half width "
                    "{:g})",
                    std::abs(distance), bg));
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

}  // namespace

openvdb::FloatGrid::Ptr csg(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b,
                            CsgOperation op) {
  ensure_openvdb_initialized();
  check_level_set(a, "A");
  check_level_set(b, "B");
  check_same_transform(a, b, "csg");
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
  check_same_transform(a, b, "csg");
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

VdbContourResult offset_surfaces(const openvdb::FloatGrid& field,
                                 const std::vector<double>& distances, ContourOptions options) {
  if (distances.empty()) throw Error("offset surfaces: no distances given");
  const double bg = field.background();
  for (double d : distances) {
    if (!(std::abs(d) < bg)) {
      throw Error(
          fmt::format("offset surfaces: distance {:g} is not inside the narrow band (half "
                      "width {:g})",
                      d, bg));
    }
  }
  options.values = distances;
  return contour_vdb(field, options);
}

}  // namespace isoforge
