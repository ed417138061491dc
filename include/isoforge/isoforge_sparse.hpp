#pragma once
/// \file
/// The whole API, including the functions that take or return OpenVDB grids (which brings in
/// OpenVDB's headers): isoforge/isoforge.hpp plus every sparse header.

#include "isoforge/isoforge.hpp"
#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/implicit/sample_sparse.hpp"
#include "isoforge/io/vdb.hpp"
#include "isoforge/model/csg_sparse.hpp"
#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/model/implicit_modeller_sparse.hpp"
#include "isoforge/sparse/convert.hpp"
#include "isoforge/sparse/grid.hpp"
