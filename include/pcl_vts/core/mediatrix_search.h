// Stage 2, the heart of VTS: for a directed edge a->b, find the point p on its left
// whose circle through a, b, p is empty (under the tie-break of incirclePerturbed).
// All circles through a and b have their centre on the edge's mediatrix; the search
// first scans the rectangle of cells supported by the edge, then, if the best circle
// found so far is not covered, widens best-first over the occupancy pyramid until no
// unvisited cell can hold a point inside or on the best circle (docs/algorithm.md).
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/cell_subdivision.h>
#include <pcl_vts/core/error_bounds.h>
#include <pcl_vts/core/export.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace pcl_vts {

struct SearchStats {
  std::size_t local = 0;         ///< searches settled inside the edge rectangle
  std::size_t widened = 0;       ///< searches that needed the pyramid stage
  std::size_t cells_visited = 0; ///< cells (or sub-cells) whose points were tested
  std::size_t points_tested = 0; ///< candidate points looked at
};

/// Reusable search state (one per thread): the block heap.
class PCL_VTS_CORE_EXPORT MediatrixSearch {
 public:
  MediatrixSearch(const CellGrid& grid, const CellPyramid& pyramid,
                  const CellSubdivision& subdivision);

  /// The Delaunay third point of the edge a->b on its left side (grid point ids), or
  /// INVALID_ID when no point lies strictly left of the line a b.
  VertexId findThirdPoint(VertexId a, VertexId b);

  const SearchStats& stats() const { return stats_; }

 private:
  struct Block {
    double key; ///< squared distance from the edge midpoint (lower bound)
    std::uint32_t level;
    std::uint32_t i;
    std::uint32_t j;
    std::uint32_t node; ///< SubCell of a crowded cell, or INVALID_ID (pyramid block)
  };
  struct Window {
    std::uint32_t i0, i1, j0, j1; ///< inclusive; empty when i0 > i1
    bool contains(std::uint32_t i, std::uint32_t j) const
    {
      return i >= i0 && i <= i1 && j >= j0 && j <= j1;
    }
  };
  struct Query {
    VertexId a, b;
    Point2 pa, pb;
    VertexId best = INVALID_ID;
    SafeDisk disk; ///< of best, when disk_fresh
    bool disk_fresh = false;
    /// Points farther than sqrt(reject_r2) from (reject_cx, reject_cy) are outside the
    /// current best circle or right of the edge: the last safe disk computed, which
    /// contains the open side of every later (smaller) circle; infinite before.
    double reject_cx = 0.0;
    double reject_cy = 0.0;
    double reject_r2 = std::numeric_limits<double>::infinity();
    void refreshDisk(const CellGrid& grid);
  };

  /// Floating-point only: the point with the smallest circumcentre offset along the
  /// mediatrix among the cells around the likely circumcentre (more of them when those
  /// are empty), or INVALID_ID. It only
  /// seeds the exact tests: a good first candidate makes the safe disk tight.
  VertexId guessThirdPoint(const Query& q) const;
  static std::size_t cellCount(const Window& w)
  {
    return static_cast<std::size_t>(w.i1 - w.i0 + 1) *
           static_cast<std::size_t>(w.j1 - w.j0 + 1);
  }
  /// Counts a visited cell and tests the points [begin, end) (none: most cells met
  /// around clustered input's voids are empty).
  void testRange(std::uint32_t begin, std::uint32_t end, Query& q)
  {
    ++stats_.cells_visited;
    if (begin < end)
      testPoints(begin, end, q);
  }
  void testPoints(std::uint32_t begin, std::uint32_t end, Query& q);
  void testCell(CellId cell, Query& q)
  {
    testRange(grid_.start(cell), grid_.start(cell + 1), q);
  }
  /// Cells i0..i1 of row j but those of `skip`: one range of points per run of
  /// cells (a row's cells are contiguous), in the same order as cell by cell.
  void testRow(std::uint32_t j, std::uint32_t i0, std::uint32_t i1, const Window& skip,
               Query& q);
  bool windowHasCrowdedCell(const Window& w) const;
  Window diskCells(const SafeDisk& disk) const;
  /// The phases of findThirdPoint, in order; each returns true when it settled the
  /// search (q.best is then the apex). The quick guess: a floating-point apex whose
  /// safe disk covers few cells.
  bool settleByGuess(Query& q);
  /// The cells spanned by the edge, dilated by one; empty when too many or crowded.
  Window edgeRectangle(const Query& q) const;
  /// The rectangle w: its foot cell first, then only the best circle's cells when they
  /// lie inside w, else every cell of w (not settled).
  bool settleInRectangle(Query& q, const Window& w);
  /// The best circle's cells outside `done`, when they are few.
  bool settleInDiskCells(Query& q, const Window& done);
  /// Long or flat cases (near the hull, across voids): the apex guessed among the
  /// cells along the edge, then certified on the cells of its safe disk row by row
  /// (the disk clipped to each row: a thin cap along the hull is a few cells per row),
  /// or, too flat for a safe disk, on the cells along the edge when the minor segment
  /// of its circle is thinner than a cell.
  bool settleAlongEdge(Query& q);
  /// One band of settleAlongEdge, e edge lengths beyond both ends; true when settled
  /// (else q.best may still have improved).
  bool settleInBand(Query& q, double e);
  /// Best-first over the pyramid, skipping the cells of `done`.
  void widen(Query& q, const Window& done);
  /// World rectangle of a block (pyramid block or sub-cell), widened by the slack.
  BlockRect blockBounds(const Block& b) const;
  /// widen: tests the points of a small pyramid block (level >= 1) at once; false
  /// (nothing done) when it holds too many points or a crowded cell.
  bool testBlockDirectly(const Block& blk, Query& q);

  const CellGrid& grid_;
  const CellPyramid& pyramid_;
  const CellSubdivision& sub_;
  std::vector<Block> heap_;
  std::vector<Window> band_, spans_; ///< settleAlongEdge's row spans
  SearchStats stats_;
};

} // namespace pcl_vts
