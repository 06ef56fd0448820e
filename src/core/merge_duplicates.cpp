#include <pcl_vts/core/merge_duplicates.h>

namespace pcl_vts {

const char* duplicateRuleName(DuplicateRule rule)
{
  switch (rule) {
  case DuplicateRule::LOWEST_Z:
    return "lowest";
  case DuplicateRule::HIGHEST_Z:
    return "highest";
  case DuplicateRule::MEAN_Z:
    return "mean";
  case DuplicateRule::FIRST:
    return "first";
  }
  return "?";
}

namespace {

/// Index (within [first, last)) of the slot that represents the run.
std::size_t pickRepresentative(DuplicateRule rule, const std::vector<double>& z,
                               const std::vector<std::uint32_t>& source,
                               std::size_t first, std::size_t last)
{
  std::size_t best = first;
  for (std::size_t k = first + 1; k < last; ++k) {
    bool better = false;
    switch (rule) {
    case DuplicateRule::LOWEST_Z:
      better = z[k] < z[best] || (z[k] == z[best] && source[k] < source[best]);
      break;
    case DuplicateRule::HIGHEST_Z:
      better = z[k] > z[best] || (z[k] == z[best] && source[k] < source[best]);
      break;
    case DuplicateRule::MEAN_Z:
    case DuplicateRule::FIRST:
      better = source[k] < source[best];
      break;
    }
    if (better)
      best = k;
  }
  return best;
}

} // namespace

std::size_t mergeDuplicates(CellGrid& grid, DuplicateRule rule, std::vector<double>& z,
                            std::vector<std::uint32_t>& source,
                            std::vector<VertexId>& slot_to_vertex)
{
  const std::size_t slots = grid.points.size();
  slot_to_vertex.assign(slots, INVALID_ID);
  std::size_t out = 0;
  std::uint32_t cell_begin_out = 0;
  for (std::size_t c = 0; c < grid.cellCount(); ++c) {
    const std::size_t begin = grid.cell_start[c], end = grid.cell_start[c + 1];
    grid.cell_start[c] = cell_begin_out;
    for (std::size_t k = begin; k < end;) {
      std::size_t run_end = k + 1;
      while (run_end < end && grid.points[run_end] == grid.points[k])
        ++run_end;
      const std::size_t rep = pickRepresentative(rule, z, source, k, run_end);
      double vz = z[rep];
      if (rule == DuplicateRule::MEAN_Z && run_end - k > 1) {
        double sum = 0.0;
        for (std::size_t m = k; m < run_end; ++m)
          sum += z[m];
        vz = sum / static_cast<double>(run_end - k);
      }
      const Point2 p = grid.points[k];
      const std::uint32_t src = source[rep];
      for (std::size_t m = k; m < run_end; ++m)
        slot_to_vertex[m] = static_cast<VertexId>(out);
      grid.points[out] = p;
      z[out] = vz;
      source[out] = src;
      ++out;
      k = run_end;
    }
    cell_begin_out = static_cast<std::uint32_t>(out);
  }
  grid.cell_start[grid.cellCount()] = static_cast<std::uint32_t>(out);
  grid.points.resize(out);
  z.resize(out);
  source.resize(out);
  return slots - out;
}

} // namespace pcl_vts
