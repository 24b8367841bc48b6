// Structured box (Tet4) and rectangle (Tri3/Quad4) meshes for tests, benchmarks and examples.
#pragma once

#include <array>

#include "fem/mesh.h"

namespace fracdem
{

// nx*ny*nz hexahedral cells of size lx/nx x ly/ny x lz/nz starting at origin,
// each split into 6 positive-volume tets around its main diagonal (Kuhn
// split: the same split in every cell keeps neighbouring faces conforming).
// Node (i, j, k) has index i + (nx+1)*(j + (ny+1)*k). Node sets "xmin",
// "xmax", "ymin", "ymax", "zmin", "zmax"; region 0; no element sets.
// Throws std::invalid_argument for non-positive counts or lengths.
Mesh make_box_tet_mesh(int nx, int ny, int nz, double lx, double ly, double lz,
                       const std::array<double, 3>& origin = {0.0, 0.0, 0.0});

// nx*ny cells in the x-y plane (z = 0), counter-clockwise Quad4, or each cell
// split into two counter-clockwise Tri3 along its (i,j)-(i+1,j+1) diagonal.
// Node (i, j) has index i + (nx+1)*j. Node sets "xmin", "xmax", "ymin",
// "ymax"; region 0; dim = 2.
Mesh make_rect_mesh(int nx, int ny, double lx, double ly,
                    const std::array<double, 2>& origin = {0.0, 0.0},
                    ElemType type = ElemType::Quad4);

} // namespace fracdem
