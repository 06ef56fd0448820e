// The Markdown section of one data set in docs/comparison.md (two tables: cost and
// topology, then error; parameters, notes and pictures), and tab-separated rows for
// the time plot. A method that failed keeps its row, with the reason.
#pragma once

#include "child_process.h"
#include "mesh_metrics.h"
#include "method_report.h"

#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

struct MethodRow {
  std::string name;     ///< vts-raw, vts, gp3, poisson, bpa
  std::string failure;  ///< empty when the method produced a mesh with metrics
  ChildOutcome outcome; ///< time and memory of its process
  MethodReport report;
  MeshMetrics metrics;
  std::vector<std::string> notes; ///< the parent's notes (Poisson trimming)
};

struct DatasetInfo {
  std::string name;  ///< file-name-safe label ("synthetic_1e5")
  std::string title; ///< heading
  std::string input; ///< where the points came from
  std::size_t points = 0;
  std::vector<std::string> input_notes;
  double spacing = 0.0;
  double extent[3] = {0, 0, 0};
  double offset[3] = {0, 0, 0};
  bool has_truth = false;
  std::string truth_description;
  std::string metric_description; ///< sampling density, threads
  std::string picture_link;       ///< prefix for the PNGs in Markdown; empty = none
};

std::string markdownSection(const DatasetInfo& info,
                            const std::vector<MethodRow>& rows);

/// "name<TAB>points<TAB>method<TAB>seconds-or-empty<TAB>status" per row.
std::string tsvRows(const DatasetInfo& info, const std::vector<MethodRow>& rows);

} // namespace compare
} // namespace pcl_vts
