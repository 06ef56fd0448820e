#include <pcl_vts/core/cell_pyramid.h>

namespace pcl_vts {

void buildCellPyramid(const CellGrid& grid, CellPyramid& pyramid)
{
  pyramid.levels.clear();
  CellPyramid::Level base;
  base.nx = grid.nx;
  base.ny = grid.ny;
  base.occupied.resize(grid.cellCount());
  for (std::size_t c = 0; c < grid.cellCount(); ++c)
    base.occupied[c] = grid.cell_start[c + 1] > grid.cell_start[c] ? 1 : 0;
  pyramid.levels.push_back(std::move(base));
  while (pyramid.levels.back().nx > 1 || pyramid.levels.back().ny > 1) {
    const CellPyramid::Level& fine = pyramid.levels.back();
    CellPyramid::Level coarse;
    coarse.nx = (fine.nx + 1) / 2;
    coarse.ny = (fine.ny + 1) / 2;
    coarse.occupied.assign(static_cast<std::size_t>(coarse.nx) * coarse.ny, 0);
    for (std::uint32_t j = 0; j < fine.ny; ++j)
      for (std::uint32_t i = 0; i < fine.nx; ++i)
        if (fine.occupied[static_cast<std::size_t>(j) * fine.nx + i])
          coarse.occupied[static_cast<std::size_t>(j / 2) * coarse.nx + i / 2] = 1;
    pyramid.levels.push_back(std::move(coarse));
  }
}

} // namespace pcl_vts
