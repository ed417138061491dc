// placeholder: structured/unstructured grid contouring lands in a following commit
#include "contour_internal.hpp"
namespace isoforge::contour_detail {
PolyData contour_cells(const Dataset&, const ContourOptions&, ContourStats*) { throw Error("contour: grids not implemented yet"); }
}
