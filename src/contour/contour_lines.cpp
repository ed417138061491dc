// placeholder: marching squares and polydata isolines land in a following commit
#include "contour_internal.hpp"
namespace isoforge::contour_detail {
PolyData contour_image_2d(const ImageData&, const ContourOptions&, ContourStats*) { throw Error("contour: 2D images not implemented yet"); }
PolyData contour_polydata(const PolyData&, const ContourOptions&, ContourStats*) { throw Error("contour: polydata not implemented yet"); }
}
