// Markdown and TSV of one data set (compare_report.h).
#include "compare_report.h"
#include "methods.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace pcl_vts {
namespace compare {
namespace {

/// 3 significant digits, plain notation for the usual magnitudes.
std::string sig(double value)
{
  if (!std::isfinite(value))
    return "inf";
  char text[32];
  const double a = std::fabs(value);
  if (a != 0.0 && (a < 1e-3 || a >= 1e6))
    std::snprintf(text, sizeof(text), "%.2e", value);
  else if (a >= 100.0)
    std::snprintf(text, sizeof(text), "%.0f", value);
  else
    std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

std::string seconds(double s)
{
  char text[32];
  std::snprintf(text, sizeof(text), s < 10.0 ? "%.2f" : "%.1f", s);
  return text;
}

std::string stats3(const DistanceStats& s)
{
  return sig(s.mean) + " | " + sig(s.rms) + " | " + sig(s.max);
}

} // namespace

std::string markdownSection(const DatasetInfo& info, const std::vector<MethodRow>& rows)
{
  std::ostringstream md;
  md << "## " << info.title << "\n\n";
  md << "Input: " << info.input << "; " << info.points << " points";
  for (const std::string& note : info.input_notes)
    md << "; " << note;
  md << ". Box " << sig(info.extent[0]) << " x " << sig(info.extent[1]) << " x "
     << sig(info.extent[2]) << " (input units), point spacing " << sig(info.spacing)
     << " (median nearest-neighbour distance). Local frame: offset ("
     << sig(info.offset[0]) << ", " << sig(info.offset[1]) << ", "
     << sig(info.offset[2]) << ") removed in double before any method ran.\n\n";

  md << "| method | time s | normals s | peak MiB | vertices | triangles | boundary "
        "edges | non-manifold edges | unused points | flipped | overlapping (XY) | "
        "overlap area % |\n";
  md << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
        "---: |\n";
  for (const MethodRow& row : rows) {
    md << "| " << methodTitle(row.name) << " | ";
    if (!row.failure.empty()) {
      md << "**failed: " << row.failure << "**";
      if (row.outcome.wall_seconds > 0.0)
        md << " (after " << seconds(row.outcome.wall_seconds) << " s, peak "
           << sig(static_cast<double>(row.outcome.peak_rss_kib) / 1024.0) << " MiB)";
      md << " | | | | | | | | | | |\n";
      continue;
    }
    const MeshMetrics& m = row.metrics;
    const TopologyCounts& t = m.topology;
    md << seconds(row.report.seconds) << " | "
       << (row.report.normal_seconds >= 0.0 ? seconds(row.report.normal_seconds) : "-")
       << " | " << sig(static_cast<double>(row.outcome.peak_rss_kib) / 1024.0) << " | "
       << t.vertices_used << " | " << t.triangles << " | " << t.boundary_edges << " | "
       << t.non_manifold_edges << " | "
       << (m.unused_points < 0 ? std::string("n/a (new vertices)")
                               : std::to_string(m.unused_points))
       << " | " << t.flipped << " | " << m.overlap.overlapping_triangles << " | "
       << sig(m.overlap.xy_area > 0.0
                  ? 100.0 * m.overlap.overlap_area / m.overlap.xy_area
                  : 0.0)
       << " |\n";
  }
  md << "\nError against the input points (input units; mesh -> points: area-weighted "
        "samples to the nearest point's tangent disc; points -> mesh: exact distance "
        "to the nearest triangle):\n\n";
  md << "| method | samples | mesh->points mean | RMS | max | points->mesh mean | RMS "
        "| "
        "max | Hausdorff |\n";
  md << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const MethodRow& row : rows) {
    md << "| " << methodTitle(row.name) << " | ";
    if (!row.failure.empty()) {
      md << "failed | | | | | | | |\n";
      continue;
    }
    const MeshMetrics& m = row.metrics;
    md << m.samples << " | " << stats3(m.mesh_to_points) << " | "
       << stats3(m.points_to_mesh) << " | " << sig(m.hausdorff) << " |\n";
  }
  if (info.has_truth) {
    md << "\nError against the true surface (" << info.truth_description << "):\n\n";
    md << "| method | mesh->truth mean | RMS | max | truth->mesh mean | RMS | max | "
          "Hausdorff |\n";
    md << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const MethodRow& row : rows) {
      md << "| " << methodTitle(row.name) << " | ";
      if (!row.failure.empty()) {
        md << "failed | | | | | | |\n";
        continue;
      }
      const MeshMetrics& m = row.metrics;
      md << stats3(m.mesh_to_truth) << " | " << stats3(m.truth_to_mesh) << " | "
         << sig(m.hausdorff_truth) << " |\n";
    }
  }
  md << "\nParameters and notes:\n\n";
  for (const MethodRow& row : rows) {
    md << "- " << methodTitle(row.name) << ": ";
    if (!row.report.parameters.empty())
      md << row.report.parameters;
    else
      md << "(did not report its parameters)";
    for (const std::string& note : row.report.notes)
      md << "; " << note;
    for (const std::string& note : row.notes)
      md << "; " << note;
    if (!row.failure.empty())
      md << "; **failed: " << row.failure << "**";
    md << ".\n";
  }
  md << "- Metrics: " << info.metric_description << ".\n";
  if (!info.picture_link.empty()) {
    md << "\nFrom above, then obliquely from the south-west (same camera for every "
          "method; red: boundary edges, magenta: non-manifold edges, orange: "
          "triangles seen from below, blue: hole filling, dots: input points left out, "
          "drawn when at most 1500):\n\n";
    md << "![" << info.name << " from above](" << info.picture_link << "/" << info.name
       << "_top.png)\n\n";
    md << "![" << info.name << " oblique](" << info.picture_link << "/" << info.name
       << "_oblique.png)\n";
  }
  md << "\n";
  return md.str();
}

std::string tsvRows(const DatasetInfo& info, const std::vector<MethodRow>& rows)
{
  std::ostringstream out;
  out.precision(6);
  for (const MethodRow& row : rows) {
    out << info.name << "\t" << info.points << "\t" << row.name << "\t";
    if (row.failure.empty())
      out << row.report.seconds << "\tok\n";
    else
      out << "\t" << row.failure << "\n";
  }
  return out.str();
}

} // namespace compare
} // namespace pcl_vts
