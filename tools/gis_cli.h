// pcd_to_mesh's GIS outputs (--dem, --contours, --crs and friends): their options,
// the one call after the final mesh, kept out of the tool's main file. Without GDAL
// in the build the options are still recognised and refused with a clear message.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/io/mesh_writer.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts::tools {

class CommandLine;

class GisCli {
 public:
  GisCli();
  ~GisCli();
  GisCli(const GisCli&);
  GisCli& operator=(const GisCli&);

  /// Declares the GIS options (their --help group) into cli, each setting this.
  void describe(CommandLine& cli);
  /// One option ("--dem"); false with error set for a bad value.
  bool parse(const std::string& name, const std::string& value, std::string& error);
  /// A raster or vector product is asked for.
  bool anyProduct() const;
  /// Checks the combination (validateGisOptions, its words behind the flag at fault);
  /// INVALID_PARAMETER (a usage error) otherwise, also for any GIS option in a build
  /// without GDAL.
  Status validate() const;
  /// The CRS of the run: --crs if given, else the one the input files declare (LAS
  /// projection records, GeoTIFF, a .prj beside the file; read before the points,
  /// so the in-memory and the tiled paths agree). INVALID_PARAMETER naming two
  /// files whose CRSs differ. A file's CRS that GDAL cannot parse is ignored, with a
  /// note. Empty when none.
  Status resolveCrs(const std::vector<std::string>& files,
                    std::vector<std::string>& notes);
  const std::string& crs() const { return crs_; }
  /// A short name of the CRS for a summary or a PLY comment ("EPSG:32633", or the
  /// WKT's name), empty when none.
  std::string crsName() const;
  /// Writes the products and the mesh's .prj sidecar (when a CRS is known); one
  /// summary line each.
  Status write(const TriangleMesh& mesh, const std::string& mesh_path,
               std::vector<std::string>& summary) const;
  /// The products of a mesh that is not held (a tiled run's, read back from its
  /// temporary files): the DEM and the contours out of core, their files in
  /// temp_folder. The .prj is write()'s.
  Status writeOutOfCore(const MeshSource& mesh, std::uint64_t memory,
                        const std::string& temp_folder,
                        std::vector<std::string>& summary) const;
  /// Only the mesh's .prj sidecar (when a CRS is known).
  Status writePrj(const std::string& mesh_path) const;

 private:
  struct Impl;
  Impl* impl_;
  std::string crs_;
};

} // namespace pcl_vts::tools
