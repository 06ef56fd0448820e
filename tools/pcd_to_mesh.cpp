// pcd_to_mesh: elevation point cloud (PCD, LAS, ASCII grid, XYZ text, PLY) -> exact
// Delaunay triangle mesh (.ply/.obj/.vtk) through the PCL-free core (runVtsPipeline),
// keeping float64 coordinates intact. Shape of PCL's tools (tools/gp3_surface.cpp): one
// "[done, ...]" line per stage; but every option is validated, each failure class has
// its own exit code and one stderr line, and the output appears only when complete
// (mesh_writer.h). --png draws the final mesh (mesh_picture.h).
#include "cli_words.h"
#include "command_line.h"
#include "gis_cli.h"
#include "input_list.h"

#ifdef PCL_VTS_MPI_TOOL
#include <pcl_vts/mpi/mpi_comm.h>
#endif

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/ground_tiles.h>
#include <pcl_vts/io/mesh_writer.h>
#include <pcl_vts/io/point_cloud_loader.h>
#include <pcl_vts/picture/mesh_picture.h>
#include <pcl_vts/preprocess_cloud.h>
#include <pcl_vts/tiling/tiled_mesh.h>

#include <pcl/console/print.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace {

/// Set on MPI ranks other than 0: they print nothing, rank 0 speaks for the job.
bool g_silent = false;

// One exit code per class of failure (listed in --help).
constexpr int EXIT_USAGE = 1;    // unknown option, bad value, bad output extension
constexpr int EXIT_INPUT = 2;    // input file missing, unreadable or not valid
constexpr int EXIT_DATA = 3;     // input read but unusable: no/too few/collinear points
constexpr int EXIT_OUTPUT = 4;   // the mesh (or the --png picture) could not be written
constexpr int EXIT_INTERNAL = 5; // a bug or out of memory

constexpr double DEFAULT_CELL_SIZE = 0.0;
constexpr pcl_vts::DuplicateRule DEFAULT_DUPLICATES = pcl_vts::DuplicateRule::LOWEST_Z;
constexpr int DEFAULT_PNG_WIDTH = 1000;
constexpr int MIN_PNG_WIDTH = 64;
constexpr int MAX_PNG_WIDTH = 8192;

// The in-memory run peaks at about 310 bytes per point read (8.5e6 LiDAR ground
// points: 2.6 GB, docs/scaling.md §5): above this many bytes per point, tile.
constexpr std::uint64_t IN_MEMORY_BYTES_PER_POINT = 320;

struct CliOptions {
  std::vector<std::string> inputs; ///< files, after folders and @LISTs are expanded
  std::string input;               ///< how messages name the input: a file or "N files"
  std::string output;
  std::uint64_t memory_limit = 0; ///< bytes; default: half the physical memory
  std::string temp_dir;           ///< default: the output's folder
  int tile_level = -1;            ///< testing knob: force the tiled path
  std::string tile_output;        ///< --tile-output: one mesh per tile + index.csv
  pcl_vts::VtsOptions vts;
  pcl_vts::CloudLoadOptions load;
  pcl_vts::PreprocessOptions preprocess;
  bool no_trim = false;
  bool no_fill = false;
  bool ascii = false;
  bool force_double = false;
  std::string png;                   ///< --png: picture of the final mesh, or none
  int png_width = DEFAULT_PNG_WIDTH; ///< pixels per view
  bool png_width_given = false;
  bool quiet = false;
  bool help = false;
  pcl_vts::tools::GisCli gis; ///< --dem, --contours, --crs (gis_cli.h)
};

/// The text of a default value in --help: "0.5", "33".
std::string shown(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

/// The options of pcd_to_mesh, each with its --help text and the setting it fills in
/// opt (applied in command-line order by parseArgs).
pcl_vts::tools::CommandLine describeOptions(CliOptions& opt);

void printHelp()
{
  CliOptions unused;
  std::printf(
      "Usage: pcd_to_mesh INPUT... OUTPUT.{ply,obj,vtk} [options]\n"
      "\n"
      "Triangulates an elevation point cloud (z = f(x, y): terrain, DEM, horizon) "
      "with\n"
      "the VTS grid method: the exact Delaunay triangulation of the XY projection,\n"
      "tiling the convex hull of the distinct XY points.\n"
      "\n"
      "Input:  one or more files, folders (every file with a supported extension in\n"
      "        them, by name) or @LIST (a text file naming one path per line), meshed\n"
      "        as one point set with the same rules. Format from the extension (any\n"
      "        case), else from the content; always\n"
      "        read in double precision:\n"
      "        .pcd  PCD (ascii, binary, binary_compressed), fields x y z or X Y Z,\n"
      "              float32, float64 or integer\n"
      "        .las  LAS 1.0-1.4, point formats 0-10 (int32 * scale + offset)\n"
      "        .laz  LAZ (LASzip-compressed LAS), point formats 0-3 and 6-10, its\n"
      "              chunks decoded on --threads\n"
      "        .asc  ESRI ASCII grid: one point per cell centre, NODATA skipped\n"
      "        .tif .tiff  GeoTIFF (band 1, through GDAL when the build found it):\n"
      "              one point per cell centre, NODATA skipped\n"
      "        .xyz .txt .csv  text, x y z per line separated by blanks, commas or\n"
      "              semicolons; optional header line naming x y z columns; extra\n"
      "              columns ignored; '#' lines are comments\n"
      "        .ply  the vertices of a PLY point cloud or mesh (faces ignored)\n"
      "Output: format from the extension (any case): .ply (binary little-endian "
      "unless\n"
      "        --ascii), .obj, .vtk (legacy ASCII polydata). Vertex coordinates are\n"
      "        written exactly: double PLY properties whenever float32 would round,\n"
      "        text numbers that read back to the same double. The file is written\n"
      "        to a temporary file in the same folder and renamed when complete.\n"
      "        When holes were filled, vertices carry a flag 'inserted' (1 = added\n"
      "        by hole filling): a uchar PLY property, VTK point scalars, an OBJ "
      "count.\n"
      "\n"
      "An option's value follows it (--cell-size 2) or an equal sign (--cell-size=2);\n"
      "options and file arguments come in any order, '--' ends the options; a\n"
      "repeated option: the last one counts.\n"
      "\n"
      "%s"
      "\n"
      "Exit status:\n"
      "  0  success: the mesh was written\n"
      "  1  usage error: unknown option, bad or missing option value, wrong number of\n"
      "     arguments, unknown output extension, --classes/--returns on non-LAS input\n"
      "  2  input file error: missing, unreadable, empty, unknown format, bad header,\n"
      "     truncated body, no x/y/z, a value that is not a number, corrupt LAZ\n"
      "  3  input data unusable: no points (or none left after --classes/--returns,\n"
      "     all NODATA), fewer than 3 distinct XY positions, all points collinear,\n"
      "     coordinates out of range\n"
      "  4  output error: the mesh or the --png picture could not be written (folder\n"
      "     missing, not writable, disk full); no partial file is left behind\n"
      "  5  internal error (out of memory, or a bug: please report)\n"
      "Errors print one line on stderr starting with \"pcd_to_mesh: error: \".\n",
      describeOptions(unused).help().c_str());
}

/// Exactly `expected` comma-separated finite numbers for option `name`.
bool parseNumberList(const std::string& name, const std::string& text,
                     std::size_t expected, std::vector<double>& numbers,
                     std::string& error)
{
  if (pcl_vts::tools::parseNumberList(text, expected, numbers))
    return true;
  error = name + ": '" + text + "' is not " + std::to_string(expected) +
          " comma-separated numbers";
  return false;
}

/// A finite number >= 0 (or > 0 when zero_meaning is null) for option `name`.
bool parseNonNegative(const std::string& name, const char* text, double& value,
                      std::string& error, const char* zero_meaning)
{
  const std::string shown = name + ": '" + text + "'";
  if (*text == '\0' || std::isspace(static_cast<unsigned char>(*text))) {
    error = shown + " is not a number";
    return false;
  }
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text, &end);
  if (end == text || *end != '\0') {
    error = shown + " is not a number";
    return false;
  }
  if (!std::isfinite(value) || errno == ERANGE) {
    error = shown + " is out of range (a finite number " +
            (zero_meaning ? ">= 0" : "> 0") + " is expected)";
    return false;
  }
  if (value < 0.0 || (zero_meaning == nullptr && value == 0.0)) {
    error = zero_meaning ? shown + " must be >= 0 (0 = " + zero_meaning + ")"
                         : shown + " must be > 0";
    return false;
  }
  return true;
}

/// True when path ends in ".png", any case.
bool hasPngExtension(const std::string& path)
{
  if (path.size() < 5 || path[path.size() - 5] == '/')
    return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

pcl_vts::tools::CommandLine describeOptions(CliOptions& opt)
{
  using Apply = pcl_vts::tools::CommandLine::Apply;
  // A finite number >= 0 into target; > 0 when zero_meaning is null.
  const auto nonNegative = [](const std::string& name, double& target,
                              const char* zero_meaning) -> Apply {
    return [name, &target, zero_meaning](const std::string& value, std::string& error) {
      return parseNonNegative(name, value.c_str(), target, error, zero_meaning);
    };
  };
  // --crop and --outliers: the combination checked as soon as it is set.
  const auto checkPreprocess = [&opt](const char* name, std::string& error) {
    if (pcl_vts::Status st = pcl_vts::validatePreprocessOptions(opt.preprocess);
        !st.ok()) {
      error = std::string(name) + ": " + st.message;
      return false;
    }
    return true;
  };
  const pcl_vts::PreprocessOptions pre;
  pcl_vts::tools::CommandLine cli;

  cli.group("General")
      .flag("help,h", "print this help and exit", [&opt] { opt.help = true; })
      .value("threads", "N",
             "threads for the triangulation and LAZ decoding, N >= 0; 0 = all cores "
             "(default: 0; the mesh is the same for every N)",
             [&opt](const std::string& value, std::string& error) {
               double threads = 0.0;
               if (!parseNonNegative("--threads", value.c_str(), threads, error,
                                     "all cores"))
                 return false;
               if (threads != std::floor(threads) || threads > 4096.0) {
                 error = "--threads: '" + value +
                         "' must be a whole number of threads (<= 4096)";
                 return false;
               }
               opt.vts.threads = static_cast<unsigned>(threads);
               opt.load.threads = opt.vts.threads; // LAZ chunks decode on them too
               return true;
             })
      .flag("quiet", "print nothing but errors (default: print a summary)",
            [&opt] { opt.quiet = true; });

  cli.group("LAS input")
      .value("classes", "LIST",
             "keep these classification codes, e.g. 2 (ground) or 2,9 (ground and "
             "water) (default: all classes)",
             [&opt](const std::string& value, std::string& error) {
               if (pcl_vts::tools::parseClassList(value, opt.load.classes, error))
                 return true;
               error = "--classes: " + error;
               return false;
             })
      .value("returns", "WHICH", "all | first | last (default: all)",
             [&opt](const std::string& value, std::string& error) {
               if (pcl_vts::tools::parseLasReturnFilter(value, opt.load.returns))
                 return true;
               error = "--returns: '" + value + "' is not one of all, first, last";
               return false;
             });

  cli.group("Meshing")
      .value("cell-size", "S",
             "grid cell edge length in input XY units, S >= 0; 0 = automatic from the "
             "point density (default: " +
                 shown(DEFAULT_CELL_SIZE) + ")",
             nonNegative("--cell-size", opt.vts.cell_size,
                         "automatic from the point density"))
      .value("duplicates", "RULE",
             "z kept where points share the same XY exactly: lowest | highest | mean | "
             "first (default: " +
                 std::string(pcl_vts::duplicateRuleName(DEFAULT_DUPLICATES)) + ")",
             [&opt](const std::string& value, std::string& error) {
               if (pcl_vts::tools::parseDuplicateRule(value, opt.vts.duplicate_rule))
                 return true;
               error = "--duplicates: '" + value +
                       "' is not one of lowest, highest, mean, first";
               return false;
             })
      .flag("no-trim",
            "keep the whole convex hull: do not remove outward triangles (default: "
            "trim; docs/reconstruction.md)",
            [&opt] { opt.no_trim = true; })
      .value("trim-factor", "F",
             "trim triangles whose longest edge or circumradius exceeds F x the local "
             "point spacing, F > 0 (default: " +
                 shown(pcl_vts::TrimOptions{}.trim_factor) + ")",
             nonNegative("--trim-factor",
                         opt.vts.reconstruction.trim_options.trim_factor, nullptr))
      .value("max-edge", "L",
             "also trim boundary triangles with an edge longer than L, L >= 0 in XY "
             "units; 0 = no such limit (default: 0)",
             nonNegative("--max-edge", opt.vts.reconstruction.trim_options.max_edge,
                         "no limit"))
      .flag("no-fill", "leave holes open (default: fill holes)",
            [&opt] { opt.no_fill = true; })
      .flag("no-lattice",
            "triangulate rasters by region growing too (default: the lattice fast "
            "path for points on a rectilinear lattice; the same mesh, "
            "docs/algorithm.md section 7)",
            [&opt] { opt.vts.lattice = false; })
      .flag("no-cache-blocks",
            "grow the whole triangulation by the mediatrix search (default: cache "
            "blocks of 32 x 32 cells triangulated locally first, the proven "
            "triangles kept; the same mesh, docs/scaling.md)",
            [&opt] { opt.vts.cache_blocks = false; })
      .value("max-hole-area", "A",
             "fill only holes up to this XY area, A >= 0; 0 = automatic (500 x "
             "spacing^2) (default: 0)",
             nonNegative("--max-hole-area",
                         opt.vts.reconstruction.fill_options.max_hole_area,
                         "automatic"));

  // The knobs of --ground pmf: a number > 0 each, but the window.
  using Field = double pcl_vts::PreprocessOptions::*;
  const auto pmfKnob = [&](const char* name, const char* value_name,
                           const std::string& what, Field field) {
    cli.value(name, value_name,
              "--ground pmf: " + what + ", " + value_name +
                  " > 0 (default: " + shown(pre.*field) + ")",
              nonNegative(std::string("--") + name, opt.preprocess.*field, nullptr));
  };
  cli.group("Preprocessing, in the order listed (PCL filters; original points kept)")
      .value("crop", "X0,Y0,X1,Y1",
             "keep only points with X0 <= x <= X1, Y0 <= y <= Y1 (default: no crop)",
             [&opt, checkPreprocess](const std::string& value, std::string& error) {
               std::vector<double> n;
               if (!parseNumberList("--crop", value, 4, n, error))
                 return false;
               opt.preprocess.crop = true;
               opt.preprocess.crop_min_x = n[0];
               opt.preprocess.crop_min_y = n[1];
               opt.preprocess.crop_max_x = n[2];
               opt.preprocess.crop_max_y = n[3];
               return checkPreprocess("--crop", error);
             })
      .value("voxel", "S",
             "keep one original point per S x S x S voxel, the one nearest its centre, "
             "S >= 0 (default: 0 = off)",
             nonNegative("--voxel", opt.preprocess.voxel, "off"))
      .value("grid-min", "S",
             "keep the lowest original point per S x S XY cell (pcl::GridMinimum), "
             "S >= 0 (default: 0 = off)",
             nonNegative("--grid-min", opt.preprocess.grid_min, "off"))
      .value("outliers", "K,STD",
             "drop statistical outliers, points whose mean distance to K neighbours "
             "is beyond STD deviations: pcl::StatisticalOutlierRemoval (default: off)",
             [&opt, checkPreprocess](const std::string& value, std::string& error) {
               std::vector<double> n;
               if (!parseNumberList("--outliers", value, 2, n, error))
                 return false;
               if (n[0] < 1.0 || n[0] > 10000.0 || n[0] != std::floor(n[0])) {
                 error = "--outliers: K = '" + value +
                         "' must start with a whole K in 1..10000";
                 return false;
               }
               opt.preprocess.outlier_k = static_cast<int>(n[0]);
               opt.preprocess.outlier_std = n[1];
               return checkPreprocess("--outliers", error);
             })
      .value("ground", "pmf",
             "keep only the bare-earth points found by "
             "pcl::ProgressiveMorphologicalFilter (default: off); its knobs below, "
             "their defaults for airborne LiDAR in metres (docs/ground.md)",
             [&opt](const std::string& value, std::string& error) {
               if (value != "pmf") {
                 error = "--ground: '" + value + "' is not a ground filter (pmf)";
                 return false;
               }
               opt.preprocess.ground_pmf = true;
               return true;
             });
  pmfKnob("pmf-cell", "C", "grid cell edge", &pcl_vts::PreprocessOptions::pmf_cell);
  cli.value("pmf-window", "W",
            "--ground pmf: largest window in cells, wider than the widest building, "
            "whole W in 1..4096 (default: " +
                shown(pre.pmf_max_window) + ")",
            [&opt](const std::string& value, std::string& error) {
              double v = 0.0;
              if (!parseNonNegative("--pmf-window", value.c_str(), v, error, nullptr))
                return false;
              if (v < 1.0 || v > 4096.0 || v != std::floor(v)) {
                error = "--pmf-window: '" + value +
                        "' must be a whole number of cells, 1..4096";
                return false;
              }
              opt.preprocess.pmf_max_window = static_cast<int>(v);
              return true;
            });
  pmfKnob("pmf-slope", "S", "terrain slope tolerated, rise/run",
          &pcl_vts::PreprocessOptions::pmf_slope);
  pmfKnob("pmf-initial", "H", "height threshold of the first window",
          &pcl_vts::PreprocessOptions::pmf_initial_distance);
  pmfKnob("pmf-max", "H", "largest height threshold",
          &pcl_vts::PreprocessOptions::pmf_max_distance);
  pmfKnob("pmf-base", "B", "window growth, 1, B, B^2, ... cells",
          &pcl_vts::PreprocessOptions::pmf_base);

  cli.group("Output")
      .flag("ascii",
            "ASCII PLY instead of binary (default: binary; .obj and .vtk are always "
            "ASCII)",
            [&opt] { opt.ascii = true; })
      .flag("double",
            "declare double vertex coordinates in PLY/VTK even when float32 is exact "
            "(default: only when float32 would round)",
            [&opt] { opt.force_double = true; })
      .value("png", "FILE",
             "also draw the final mesh into FILE (.png), written after the mesh: top "
             "view (north up) and oblique view from the south-west side by side, "
             "hill-shaded and coloured by height, boundary edges red, inserted points "
             "as dots (default: no picture)",
             [&opt](const std::string& value, std::string& error) {
               if (!hasPngExtension(value)) {
                 error = "--png: '" + value + "' must name a .png file";
                 return false;
               }
               opt.png = value;
               return true;
             })
      .value(
          "png-width", "N",
          "pixels per view, whole N in " + std::to_string(MIN_PNG_WIDTH) + ".." +
              std::to_string(MAX_PNG_WIDTH) +
              " (default: " + std::to_string(DEFAULT_PNG_WIDTH) + ")",
          [&opt](const std::string& value, std::string& error) {
            double width = 0.0;
            if (!parseNonNegative("--png-width", value.c_str(), width, error, nullptr))
              return false;
            if (width != std::floor(width) || width < MIN_PNG_WIDTH ||
                width > MAX_PNG_WIDTH) {
              error =
                  "--png-width: '" + value + "' must be a whole number of pixels in " +
                  std::to_string(MIN_PNG_WIDTH) + ".." + std::to_string(MAX_PNG_WIDTH);
              return false;
            }
            opt.png_width = static_cast<int>(width);
            opt.png_width_given = true;
            return true;
          });

  cli.group("Memory and tiling")
      .value("memory-limit", "SIZE",
             "memory the job may use, e.g. 512M, 4G (default: half the physical "
             "memory, " +
                 std::to_string(pcl_vts::tools::physicalMemoryBytes() / 2 >> 20) +
                 "M here), above what the process takes before reading (~90 MB of "
                 "libraries); a larger job runs tiled: inputs streamed, points "
                 "bucketed into temporary files, tiles meshed with halos grown until "
                 "every triangle is proven, the same mesh (and the same file bytes) as "
                 "in memory, trimmed, filled, --dem and --contours made out of core; "
                 "--crop and --ground pmf run tiled too (pre-tiles with the filter's "
                 "halo, the same points kept), not --voxel, --grid-min, --outliers",
             [&opt](const std::string& value, std::string& error) {
               if (pcl_vts::tools::parseByteSize(value, opt.memory_limit))
                 return true;
               error = "--memory-limit must be a size such as 512M or 4G, got '" +
                       value + "'";
               return false;
             })
      .value("temp-dir", "DIR",
             "folder for the tiled path's temporary files, removed at the end, on "
             "error and on Ctrl-C (default: the output's folder)",
             pcl_vts::tools::CommandLine::text(opt.temp_dir))
      .value("tile-output", "DIR",
             "also write one mesh per tile into DIR (which must exist): tile_C_R.ply "
             "with the triangles the tile owns and the vertices they use (seams shared "
             "exactly), and index.csv (tile bounds, counts, file names); runs tiled",
             pcl_vts::tools::CommandLine::text(opt.tile_output))
      .value("tile-level", "L",
             "testing: force the tiled path with 4^L tiles, L in 0..10",
             [&opt](const std::string& value, std::string& error) {
               char* end = nullptr;
               const long level = std::strtol(value.c_str(), &end, 10);
               if (value.empty() || *end != 0 || level < 0 || level > 10) {
                 error = "--tile-level must be a whole number in 0..10, got '" + value +
                         "'";
                 return false;
               }
               opt.tile_level = static_cast<int>(level);
               return true;
             });

  opt.gis.describe(cli); // --dem, --contours, --crs ... (gis_cli.h)
  return cli;
}

/// Parses argv; on failure error holds the one-line reason.
bool parseArgs(int argc, char** argv, CliOptions& opt, std::string& error)
{
  opt.vts.cell_size = DEFAULT_CELL_SIZE;
  opt.vts.duplicate_rule = DEFAULT_DUPLICATES;
  opt.vts.threads = 0;       // every core
  opt.vts.input_map = false; // the mesh is written from source_index alone
  opt.load.threads = 0;
  opt.vts.reconstruction = pcl_vts::ReconstructionOptions{}; // trim and fill
  std::vector<std::string> positional;
  if (!describeOptions(opt).parse(argc, argv, positional, error))
    return false;
  if (opt.help)
    return true;
  if (opt.png_width_given && opt.png.empty()) {
    error = "--png-width needs --png FILE";
    return false;
  }
  opt.vts.reconstruction.trim = !opt.no_trim;
  opt.vts.reconstruction.fill = !opt.no_fill;
  if (positional.size() < 2) {
    error = "expected INPUT... and OUTPUT.{ply,obj,vtk}, got " +
            std::to_string(positional.size()) + " file argument(s)";
    return false;
  }
  opt.output = positional.back();
  positional.pop_back();
  opt.inputs = positional; // folders and @LISTs are expanded by run(): input errors
  if (opt.memory_limit == 0)
    opt.memory_limit = std::max<std::uint64_t>(
        pcl_vts::tools::physicalMemoryBytes() / 2, std::uint64_t{256} << 20);
  if (opt.temp_dir.empty()) {
    const std::size_t slash = opt.output.rfind('/');
    opt.temp_dir = slash == std::string::npos ? "." : opt.output.substr(0, slash + 1);
  }
  return true;
}

int exitCodeFor(pcl_vts::StatusCode code)
{
  using pcl_vts::StatusCode;
  switch (code) {
  case StatusCode::OK:
    return 0;
  case StatusCode::IO_ERROR:
    return EXIT_INPUT;
  case StatusCode::EMPTY_INPUT:
  case StatusCode::CAPACITY_EXCEEDED:
  case StatusCode::TOO_FEW_POINTS:
  case StatusCode::ALL_COLLINEAR:
  case StatusCode::COORDINATE_RANGE:
    return EXIT_DATA;
  case StatusCode::INVALID_PARAMETER:
    return EXIT_USAGE;
  case StatusCode::INTERNAL_ERROR:
    return EXIT_INTERNAL;
  }
  return EXIT_INTERNAL;
}

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double peakMemoryMiB()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0; // Linux: KiB
}

/// Stdout in PCL's tool shape: "Stage ..." printed (and flushed) when the stage
/// starts, "[done, 12.3 ms : ...]" when it ends; nothing with --quiet.
class Reporter {
 public:
  explicit Reporter(bool quiet)
      : quiet_(quiet)
  {}

  void begin(const char* format, ...) __attribute__((format(printf, 2, 3)))
  {
    va_list args;
    va_start(args, format);
    print(format, args);
    va_end(args);
    std::fflush(stdout);
    open_ = !quiet_;
  }

  void done(double ms, const std::string& what)
  {
    if (quiet_)
      return;
    std::printf("[done, %.1f ms : %s]\n", ms, what.c_str());
    std::fflush(stdout);
    open_ = false;
  }

  void line(const char* format, ...) __attribute__((format(printf, 2, 3)))
  {
    va_list args;
    va_start(args, format);
    print(format, args);
    va_end(args);
  }

  /// Reports a failure: closes a pending stage line, one line on stderr (rank 0
  /// only: under MPI every rank fails with the same agreed error).
  int fail(int exit_code, const std::string& message)
  {
    if (g_silent)
      return exit_code;
    if (open_ && !quiet_)
      std::printf("[failed]\n");
    std::fflush(stdout);
    std::string one_line = message;
    for (char& c : one_line)
      if (c == '\n' || c == '\r')
        c = ' ';
    std::fprintf(stderr, "pcd_to_mesh: error: %s\n", one_line.c_str());
    return exit_code;
  }

 private:
  void print(const char* format, va_list args) const
  {
    if (!quiet_)
      std::vprintf(format, args);
  }

  bool quiet_;
  bool open_ = false;
};

/// Fails early, before minutes of work, when the output cannot be written there.
int checkOutputPath(const std::string& path, Reporter& out)
{
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    return out.fail(EXIT_OUTPUT, "cannot write '" + path + "': it is a folder");
  const std::size_t slash = path.rfind('/');
  const std::string folder =
      slash == std::string::npos ? "." : path.substr(0, slash + 1);
  if (::stat(folder.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    return out.fail(EXIT_OUTPUT, "cannot write '" + path + "': folder '" + folder +
                                     "' does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    return out.fail(EXIT_OUTPUT, "cannot write '" + path + "': folder '" + folder +
                                     "' is not writable: " + std::strerror(errno));
  return 0;
}

std::string formatMs(double ms)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", ms);
  return text;
}

/// --png: the final mesh from above and from the south-west, one camera frame for
/// both, boundary edges (halfedges without twin) red, inserted points as dots.
pcl_vts::Status drawMesh(const CliOptions& opt, const pcl_vts::TriangleMesh& mesh,
                         const std::vector<std::uint8_t>& inserted, std::string& size,
                         std::uint64_t& bytes)
{
  pcl_vts::PictureMesh picture_mesh = pcl_vts::pictureMeshOf(mesh);
  picture_mesh.vertex_marks = inserted;
  const pcl_vts::PictureFrame frame = pcl_vts::pictureFrameOf(picture_mesh);
  const std::size_t slash = opt.input.rfind('/');
  const std::string title =
      (slash == std::string::npos ? opt.input : opt.input.substr(slash + 1)) + ": " +
      std::to_string(mesh.vertexCount()) + " vertices, " +
      std::to_string(mesh.triangleCount()) + " triangles";
  pcl_vts::PictureOptions top;
  top.width = opt.png_width;
  top.caption = title + "\ntop view, north up";
  pcl_vts::PictureOptions oblique = top;
  oblique.view = pcl_vts::PictureView::OBLIQUE;
  char exaggeration[64];
  std::snprintf(exaggeration, sizeof exaggeration, ", z x %.3g",
                pcl_vts::pictureZScaleOf(frame, oblique));
  oblique.caption = title + "\noblique view from the south-west" + exaggeration;
  const pcl_vts::Picture picture =
      pcl_vts::besideEachOther({pcl_vts::renderMesh(picture_mesh, frame, top),
                                pcl_vts::renderMesh(picture_mesh, frame, oblique)},
                               opt.png_width / 50);
  size = std::to_string(picture.width) + " x " + std::to_string(picture.height) +
         " pixels";
  if (pcl_vts::Status s = pcl_vts::writePng(opt.png, picture); !s.ok())
    return s;
  struct stat st {};
  bytes =
      ::stat(opt.png.c_str(), &st) == 0 ? static_cast<std::uint64_t>(st.st_size) : 0;
  return pcl_vts::Status::success();
}

/// Appends input file f to xyz, streamed, unless the points read so far exceed what
/// the memory limit allows in memory: then `over` is set and the reading stops. A
/// file left empty by the filters (e.g. a tile without ground points) is skipped
/// when there are several inputs, not an error.
pcl_vts::Status streamInput(const CliOptions& opt, std::size_t f,
                            std::vector<double>& xyz,
                            pcl_vts::CloudDescription& description, bool& skipped,
                            bool& over)
{
  skipped = false;
  const std::size_t before = xyz.size();
  const pcl_vts::Status stop = pcl_vts::Status::error(
      pcl_vts::StatusCode::CAPACITY_EXCEEDED, "more than the memory limit allows");
  pcl_vts::Status s = pcl_vts::streamPointCloud(
      opt.inputs[f], opt.load, std::size_t{1} << 16,
      [&](const double* chunk, std::size_t n) {
        xyz.insert(xyz.end(), chunk, chunk + 3 * n);
        over = xyz.size() / 3 * IN_MEMORY_BYTES_PER_POINT > opt.memory_limit;
        return over ? stop : pcl_vts::Status::success();
      },
      description);
  if (over)
    return pcl_vts::Status::success();
  if (s.code == pcl_vts::StatusCode::EMPTY_INPUT && opt.inputs.size() > 1) {
    xyz.resize(before);
    skipped = true;
    return pcl_vts::Status::success();
  }
  return s;
}

std::string readFailure(const pcl_vts::Status& s)
{
  // The loader's only INVALID_PARAMETER: a LAS filter on another format.
  return s.code == pcl_vts::StatusCode::IO_ERROR ? "cannot read input " + s.message
         : s.code == pcl_vts::StatusCode::INVALID_PARAMETER
             ? "--classes/--returns: " + s.message
             : "input unusable: " + s.toString();
}

/// Sums one file's description into the run's.
void addDescription(const CliOptions& opt, std::size_t f,
                    const pcl_vts::CloudDescription& one, bool skipped,
                    pcl_vts::CloudDescription& all)
{
  all.points_read += one.points_read;
  all.points_kept += one.points_kept;
  const bool many = opt.inputs.size() > 1;
  if (f == 0) {
    all.format = one.format;
    all.details = many ? one.details + " (first of " +
                             std::to_string(opt.inputs.size()) + " files)"
                       : one.details;
  }
  const std::string prefix = many ? "'" + opt.inputs[f] + "': " : std::string();
  if (skipped)
    all.notes.push_back(prefix + "no point kept, skipped");
  for (const std::string& note : one.notes)
    all.notes.push_back(prefix + note);
}

std::string mib(std::uint64_t bytes)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f MiB", static_cast<double>(bytes) / 1048576.0);
  return text;
}

/// Progress of a long tiled run on stderr: rewritten in place on a terminal, one
/// line every few seconds otherwise.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet)
      : quiet_(quiet)
      , tty_(::isatty(2) != 0)
      , start_(std::chrono::steady_clock::now())
      , last_(start_)
  {}
  ~ProgressLine()
  {
    if (shown_ && tty_)
      std::fprintf(stderr, "\n");
  }
  void update(const pcl_vts::TiledProgress& p)
  {
    if (quiet_)
      return;
    const auto now = std::chrono::steady_clock::now();
    if (p.phase != current_) { // phases are string literals: one pointer each
      current_ = p.phase;
      phase_start_ = now;
    }
    const double since = std::chrono::duration<double>(now - last_).count();
    // Quiet for the first seconds (short runs print nothing), then a steady pace.
    if (since < (tty_ ? 0.5 : 5.0) && (p.phase == shown_phase_ || !shown_))
      return;
    last_ = now;
    shown_phase_ = p.phase;
    shown_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double in_phase = std::chrono::duration<double>(now - phase_start_).count();
    char text[200];
    if (p.total > 0) {
      const double done = static_cast<double>(p.done) / static_cast<double>(p.total);
      char bar[24] = "";
      if (tty_) { // [=======>            ]
        const int filled = static_cast<int>(20 * std::min(1.0, done));
        for (int k = 0; k < 20; ++k)
          bar[k] = k < filled ? '=' : k == filled ? '>' : ' ';
        bar[20] = 0;
      }
      char left[48] = "";
      if (p.done > 0 && p.done < p.total)
        std::snprintf(left, sizeof(left), ", %.0f s left in this phase",
                      in_phase * (1.0 - done) / done);
      std::snprintf(
          text, sizeof(text), "%s%s%s %llu / %llu (%.0f%%), %.0f s%s", p.phase,
          tty_ ? " [" : "", tty_ ? (std::string(bar) + "]").c_str() : "",
          static_cast<unsigned long long>(p.done),
          static_cast<unsigned long long>(p.total), 100.0 * done, elapsed, left);
    } else if (p.done > 0) {
      std::snprintf(text, sizeof(text), "%s %llu points, %.0f s", p.phase,
                    static_cast<unsigned long long>(p.done), elapsed);
    } else {
      std::snprintf(text, sizeof(text), "%s, %.0f s", p.phase, elapsed);
    }
    std::fprintf(stderr, tty_ ? "\rpcd_to_mesh: %-100s" : "pcd_to_mesh: %s\n", text);
    std::fflush(stderr);
  }

 private:
  bool quiet_, tty_, shown_ = false;
  std::chrono::steady_clock::time_point start_, last_, phase_start_;
  const char* shown_phase_ = "";
  const char* current_ = "";
};

/// The summary line of the fill, in memory and tiled alike.
void printFillLine(Reporter& out, bool off, double seconds,
                   const pcl_vts::FillResult& fill)
{
  if (off)
    out.line("  fill         [off : --no-fill]\n");
  else
    out.line(
        "  fill         [done, %.1f ms : %zu holes found, %zu filled, %zu left open "
        "(larger than %.6g), %zu points inserted]\n",
        1e3 * seconds, fill.holes_found, fill.holes_filled, fill.holes_left_open,
        fill.max_hole_area, fill.points_inserted);
}

/// The flag a tiled run's failure is about, in front of the library's words ("the
/// temporary folder is full", "the memory limit of 8 MiB is below ..."); empty when
/// none is.
std::string flagOfTiledFailure(const pcl_vts::TiledMeshReport& report)
{
  switch (report.failure) {
  case pcl_vts::TiledFailure::TEMP_FOLDER:
    return "--temp-dir: ";
  case pcl_vts::TiledFailure::MEMORY_LIMIT:
    return "--memory-limit: ";
  case pcl_vts::TiledFailure::TILE_OUTPUT:
    return "--tile-output: ";
  default:
    return "";
  }
}

/// The tiled path (tiled_mesh.h): inputs streamed twice, the mesh streamed out.
int runTiled(const CliOptions& opt, Reporter& out, Clock::time_point t_total,
             pcl_vts::JobComm& comm)
{
  const std::string why = "the input (" + opt.input + ") does not fit --memory-limit " +
                          mib(opt.memory_limit) + " in memory";
  if (!opt.tile_output.empty()) {
    struct stat st {};
    if (::stat(opt.tile_output.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) ||
        ::access(opt.tile_output.c_str(), W_OK) != 0)
      return out.fail(EXIT_OUTPUT, "--tile-output '" + opt.tile_output +
                                       "' is not a writable folder");
  }
  const pcl_vts::PreprocessOptions& pre = opt.preprocess;
  if (pre.voxel > 0.0 || pre.grid_min > 0.0 || pre.outlier_k > 0 || !opt.png.empty())
    return out.fail(
        EXIT_USAGE,
        (opt.tile_level < 0 && opt.tile_output.empty() ? why : "a tiled run") +
            std::string(": --voxel, --grid-min, --outliers and --png run in memory "
                        "only (--crop and --ground pmf run tiled too)"));
  pcl_vts::CloudDescription input;
  bool input_failed = false;
  std::vector<std::uint8_t> described(opt.inputs.size(), 0);
  pcl_vts::PointInputs inputs;
  inputs.count = opt.inputs.size();
  // Streamed: a LAS/LAZ file of any size passes through a chunk of at most a million
  // points, and of no more than 1/64 of the memory limit (the reader's chunk and the
  // job's copy of it are both alive).
  const std::size_t chunk_points = static_cast<std::size_t>(std::clamp<std::uint64_t>(
      opt.memory_limit / 64 / (3 * sizeof(double)), 4096, std::uint64_t{1} << 20));
  inputs.read = [&](std::size_t f, const pcl_vts::PointSink& sink) {
    pcl_vts::CloudDescription one;
    bool sink_failed = false;
    pcl_vts::Status s = pcl_vts::streamPointCloud(
        opt.inputs[f], opt.load, chunk_points,
        [&](const double* xyz, std::size_t n) {
          pcl_vts::Status t = sink(xyz, n);
          sink_failed = !t.ok();
          return t;
        },
        one);
    const bool skipped =
        s.code == pcl_vts::StatusCode::EMPTY_INPUT && opt.inputs.size() > 1;
    if (sink_failed)
      return s;
    if (!s.ok() && !skipped) {
      input_failed = true;
      return pcl_vts::Status::error(s.code, readFailure(s));
    }
    if (!described[f]) // read twice: scan, then bucket
      addDescription(opt, f, one, skipped, input);
    described[f] = 1;
    return pcl_vts::Status::success();
  };
  pcl_vts::TiledMeshOptions options;
  options.vts = opt.vts;
  options.temp_parent = opt.temp_dir;
  options.memory_limit = opt.memory_limit;
  options.tile_level = opt.tile_level;
  options.threads = opt.vts.threads;
  options.tile_output = opt.tile_output;
  ProgressLine progress(opt.quiet || g_silent);
  options.progress = [&](const pcl_vts::TiledProgress& p) { progress.update(p); };
  // --crop and --ground pmf: a pre-pass over pre-tiles with the filter's halo
  // (ground_tiles.h) writes the points to mesh; the job meshes those files.
  pcl_vts::GroundTilesReport ground;
  if (pre.any()) {
    options.prepare = [&](const pcl_vts::PointInputs& all, const std::string& folder,
                          pcl_vts::JobComm& job, std::vector<std::string>& files) {
      pcl_vts::GroundTilesOptions g;
      g.preprocess = pre;
      g.memory_limit = opt.memory_limit;
      g.threads = opt.vts.threads;
      g.tiles_per_side = opt.tile_level >= 0 ? 1 << opt.tile_level : 0;
      g.progress = [&](const char* phase, std::uint64_t done, std::uint64_t total) {
        if (job.rank() == 0)
          progress.update(pcl_vts::TiledProgress{phase, done, total});
      };
      g.share.rank = job.rank(); // rank 0 reads, every rank filters pre-tiles
      g.share.ranks = job.size();
      g.share.broadcast = [&job](std::string& bytes, int root) {
        job.broadcast(bytes, root);
      };
      g.share.sum = [&job](std::vector<std::uint64_t>& values) { job.sum(values); };
      g.share.start_tasks = [&job] { job.startTasks(); };
      g.share.next_task = [&job] { return job.nextTask(); };
      const auto feed = [&](const pcl_vts::GroundSink& sink) {
        for (std::size_t f = 0; f < all.count; ++f)
          if (pcl_vts::Status s = all.read(f, sink); !s.ok())
            return s;
        return pcl_vts::Status::success();
      };
      return pcl_vts::groundTiles(feed, g, folder, files, ground);
    };
    options.read_prepared = [chunk_points](const std::string& file,
                                           const pcl_vts::PointSink& sink) {
      return pcl_vts::readGroundFile(file, chunk_points, sink);
    };
  }
  pcl_vts::MeshWriteOptions write_options;
  write_options.ascii = opt.ascii;
  write_options.force_double = opt.force_double;
  write_options.comment =
      std::string("pcl_vts pcd_to_mesh: ") +
      (opt.no_trim && opt.no_fill ? "Delaunay triangulation of " : "surface mesh of ") +
      opt.input;
  if (!opt.gis.crs().empty()) // as the in-memory path writes it: the same bytes
    write_options.comment += "; crs: " + opt.gis.crsName();

  out.begin("Meshing tiled (memory limit %s, temporary files in '%s'%s) ",
            mib(opt.memory_limit).c_str(), opt.temp_dir.c_str(),
            comm.size() > 1
                ? (", " + std::to_string(comm.size()) + " MPI ranks").c_str()
                : "");
  // The DEM and contours from the final mesh, read back from the tile results (rank 0).
  std::vector<std::string> product_lines;
  double product_ms = 0;
  if (opt.gis.anyProduct())
    options.after_write = [&](const pcl_vts::MeshSource& mesh,
                              const std::string& folder) {
      const auto product_start = Clock::now();
      // An eighth of the limit for the triangles of one DEM window (at the mean
      // density; a dense window takes more).
      const pcl_vts::Status w =
          opt.gis.writeOutOfCore(mesh, opt.memory_limit / 8, folder, product_lines);
      product_ms = msSince(product_start);
      return w;
    };
  pcl_vts::TiledMeshReport report;
  const pcl_vts::Status s =
      pcl_vts::runTiledMesh(inputs, options, opt.output, write_options, report, comm);
  // Every rank returned the same status; agree on what the inputs said too.
  std::vector<std::uint64_t> totals = {input_failed ? 1u : 0u, input.points_read,
                                       input.points_kept};
  comm.sum(totals);
  input_failed = totals[0] != 0;
  input.points_read = totals[1];
  input.points_kept = totals[2];
  if (!s.ok()) {
    const int code = input_failed                              ? exitCodeFor(s.code)
                     : s.code == pcl_vts::StatusCode::IO_ERROR ? EXIT_OUTPUT
                                                               : exitCodeFor(s.code);
    if (input_failed || s.code != pcl_vts::StatusCode::TOO_FEW_POINTS)
      return out.fail(code, input_failed ? s.message
                                         : flagOfTiledFailure(report) + s.message);
    return out.fail(code, "input unusable: " + s.toString());
  }
  const double ground_seconds =
      ground.seconds_scan + ground.seconds_bucket + ground.seconds_filter;
  out.done(1e3 * (ground_seconds + report.seconds_scan + report.seconds_bucket +
                  report.seconds_mesh + report.seconds_trim + report.seconds_fill +
                  report.seconds_write),
           std::to_string(report.triangles) + " triangles");
  for (const std::string& note : input.notes)
    out.line("  %s\n", note.c_str());
  if (pre.crop)
    out.line("  crop         [done : %llu -> %llu points]\n",
             static_cast<unsigned long long>(ground.points - ground.non_finite),
             static_cast<unsigned long long>(ground.cropped));
  if (pre.ground_pmf)
    out.line("  ground       [done, %.1f ms : %llu -> %llu points, %llu pre-tiles of "
             "side %.6g with a %.6g halo, %.2f points loaded per point, largest %llu "
             "points]\n",
             1e3 * ground_seconds, static_cast<unsigned long long>(ground.cropped),
             static_cast<unsigned long long>(ground.kept),
             static_cast<unsigned long long>(ground.tiles), ground.tile_side,
             ground.halo,
             static_cast<double>(ground.points_loaded) /
                 static_cast<double>(std::max<std::uint64_t>(1, ground.cropped)),
             static_cast<unsigned long long>(ground.max_tile_points));
  out.line("  scan         [done, %.1f ms : %llu points, %llu non-finite dropped]\n",
           1e3 * report.seconds_scan, static_cast<unsigned long long>(report.points),
           static_cast<unsigned long long>(report.non_finite_dropped));
  out.line(
      "  bucket       [done, %.1f ms : %llu tiles of level %d, blocks of level %d, "
      "%s of temporary files]\n",
      1e3 * report.seconds_bucket, static_cast<unsigned long long>(report.tiles),
      report.tile_level, report.block_level, mib(report.temp_bytes).c_str());
  out.line(
      "  triangulate  [done, %.1f ms : %llu triangles, %.2f points loaded per point, "
      "largest tile %llu points, %.2f rounds per tile (at most %u)]\n",
      1e3 * report.seconds_mesh,
      static_cast<unsigned long long>(report.triangles + report.trim.triangles_removed -
                                      report.fill.triangles_added),
      static_cast<double>(report.points_loaded) /
          static_cast<double>(
              std::max<std::uint64_t>(1, report.points - report.non_finite_dropped)),
      static_cast<unsigned long long>(report.max_tile_points),
      static_cast<double>(report.rounds) /
          static_cast<double>(std::max<std::uint64_t>(1, report.tiles)),
      report.max_rounds);
  if (opt.no_trim)
    out.line("  trim         [off : --no-trim]\n");
  else
    out.line(
        "  trim         [done, %.1f ms : %zu outward triangles removed, %zu points "
        "left without triangles, %zu kept to stay manifold]\n",
        1e3 * report.seconds_trim, report.trim.triangles_removed,
        report.trim.vertices_lost, report.trim.kept_to_stay_manifold);
  printFillLine(out, opt.no_fill, report.seconds_fill, report.fill);
  out.line("  write        [done, %.1f ms : %s, %llu bytes]\n",
           1e3 * report.seconds_write,
           pcl_vts::meshFileFormatName(report.written.format),
           static_cast<unsigned long long>(report.written.bytes));
  // The products and the .prj beside the mesh (rank 0 only), before the summary as
  // in memory.
  for (const std::string& line : product_lines)
    out.line("GIS: %s\n", line.c_str());
  if (!product_lines.empty())
    out.line("GIS: written in %.1f ms\n", product_ms);
  if (pcl_vts::Status w =
          g_silent ? pcl_vts::Status::success() : opt.gis.writePrj(opt.output);
      !w.ok())
    return out.fail(EXIT_OUTPUT, w.message);
  const std::uint64_t finite = report.points - report.non_finite_dropped;
  out.line("Summary\n");
  out.line("  %-20s %zu\n", "points read", input.points_read);
  out.line("  %-20s %zu\n", "points kept", input.points_kept);
  out.line("  %-20s %llu\n", "non-finite dropped",
           static_cast<unsigned long long>(report.non_finite_dropped));
  out.line("  %-20s %llu\n", "duplicates merged",
           static_cast<unsigned long long>(finite - report.vertices));
  out.line("  %-20s %llu\n", "distinct points",
           static_cast<unsigned long long>(report.vertices));
  out.line("  %-20s %llu\n", "triangles",
           static_cast<unsigned long long>(report.triangles));
  out.line("  %-20s %llu (level %d)\n", "tiles",
           static_cast<unsigned long long>(report.tiles), report.tile_level);
  out.line("  %-20s %.1f\n", "time (ms)", msSince(t_total));
  out.line("  %-20s %.1f MiB (limit %s)\n", "peak memory", peakMemoryMiB(),
           mib(opt.memory_limit).c_str());
  out.line("  %-20s %s at most (in '%s')\n", "temporary disk",
           mib(report.temp_peak_bytes).c_str(), opt.temp_dir.c_str());
  out.line("  %-20s %s\n", "mesh written to", opt.output.c_str());
  std::fflush(stdout);
  return 0;
}

int run(CliOptions opt, pcl_vts::JobComm& comm)
{
  Reporter out(opt.quiet || g_silent);
  {
    std::vector<std::string> files;
    std::string error;
    if (!pcl_vts::tools::expandInputs(opt.inputs, files, error))
      return out.fail(EXIT_INPUT, error);
    // A folder holding the output from an earlier run would read it back as input.
    std::error_code ec;
    const std::filesystem::path output =
        std::filesystem::weakly_canonical(opt.output, ec);
    opt.inputs.clear();
    for (const std::string& file : files) {
      std::error_code file_ec;
      if (files.size() > 1 && !ec &&
          std::filesystem::weakly_canonical(file, file_ec) == output && !file_ec)
        continue;
      opt.inputs.push_back(file);
    }
    opt.input = opt.inputs.size() == 1 ? opt.inputs[0]
                                       : std::to_string(opt.inputs.size()) + " files";
  }
  const auto t_total = Clock::now();
  pcl_vts::MeshFileFormat format = pcl_vts::MeshFileFormat::PLY;
  if (pcl_vts::Status s = pcl_vts::meshFileFormatFromPath(opt.output, format); !s.ok())
    return out.fail(EXIT_USAGE, s.message);
  if (pcl_vts::Status s = pcl_vts::validateOptions(opt.vts); !s.ok())
    return out.fail(EXIT_USAGE, s.message);
  if (pcl_vts::Status s = opt.gis.validate(); !s.ok())
    return out.fail(EXIT_USAGE, s.message);
  std::vector<std::string> crs_notes; // the inputs' CRS (gis_cli.h), both paths
  if (pcl_vts::Status s = opt.gis.resolveCrs(opt.inputs, crs_notes); !s.ok())
    return out.fail(EXIT_INPUT, s.message);
  for (const std::string& note : crs_notes)
    out.line("%s\n", note.c_str());
  if (const int rc = checkOutputPath(opt.output, out); rc != 0)
    return rc;
  if (!opt.png.empty())
    if (const int rc = checkOutputPath(opt.png, out); rc != 0)
      return rc;

  out.begin("Reading '%s' ", opt.input.c_str());
  auto start = Clock::now();
  std::vector<double> xyz;
  pcl_vts::CloudDescription input;
  bool tiled = opt.tile_level >= 0 || comm.size() > 1 || !opt.tile_output.empty();
  // The inputs are streamed (LAS, LAZ, XYZ in chunks) and the reading stops as soon
  // as the points exceed what the limit allows in memory: a single file larger than
  // the limit is then never held whole.
  for (std::size_t f = 0; f < opt.inputs.size() && !tiled; ++f) {
    pcl_vts::CloudDescription one;
    bool skipped = false;
    if (pcl_vts::Status s = streamInput(opt, f, xyz, one, skipped, tiled); !s.ok())
      return out.fail(exitCodeFor(s.code), readFailure(s));
    if (!tiled)
      addDescription(opt, f, one, skipped, input);
  }
  if (tiled) {
    std::vector<double>().swap(xyz);
    out.done(msSince(start), comm.size() > 1 ? "the MPI ranks read their share: tiled"
                             : opt.tile_level >= 0
                                 ? "tiled (--tile-level)"
                                 : "more than --memory-limit allows in "
                                   "memory: tiled");
    return runTiled(opt, out, t_total, comm);
  }
  if (xyz.empty())
    return out.fail(EXIT_DATA, "input unusable: EMPTY_INPUT: no point in " + opt.input);
  const double ms_read = msSince(start);
  out.done(ms_read, std::to_string(input.points_read) + " points, " +
                        pcl_vts::cloudFileFormatName(input.format) + " " +
                        input.details +
                        (input.points_kept != input.points_read
                             ? ", " + std::to_string(input.points_kept) + " kept"
                             : std::string()));
  for (const std::string& note : input.notes)
    out.line("  %s\n", note.c_str());

  double ms_preprocess = 0.0;
  if (opt.preprocess.any()) {
    out.begin("Preprocessing %zu points ", xyz.size() / 3);
    start = Clock::now();
    std::vector<pcl_vts::PreprocessStep> steps;
    if (pcl_vts::Status s = pcl_vts::preprocessCloud(xyz, opt.preprocess, steps);
        !s.ok())
      return out.fail(exitCodeFor(s.code),
                      "input '" + opt.input + "' after preprocessing: " + s.toString());
    ms_preprocess = msSince(start);
    out.done(ms_preprocess, std::to_string(xyz.size() / 3) + " points left");
    for (const pcl_vts::PreprocessStep& st : steps)
      out.line("  %-12s [done, %.1f ms : %zu -> %zu points]\n", st.name.c_str(), st.ms,
               st.before, st.after);
  }
  const std::size_t n_points = xyz.size() / 3;

  out.begin("Meshing %zu points (grid, convex hull, region growing%s%s) ", n_points,
            opt.no_trim ? "" : ", trim", opt.no_fill ? "" : ", fill");
  start = Clock::now();
  pcl_vts::VtsResult result;
  // The input is handed over: its memory serves the post-passes' scratch.
  const pcl_vts::Status tri = pcl_vts::runVtsPipeline(std::move(xyz), opt.vts, result);
  if (tri.code == pcl_vts::StatusCode::INVALID_PARAMETER)
    return out.fail(EXIT_USAGE,
                    "options rejected for '" + opt.input + "': " + tri.message);
  if (!tri.ok())
    return out.fail(exitCodeFor(tri.code),
                    "input '" + opt.input +
                        "' cannot be triangulated: " + tri.toString());
  const pcl_vts::Diagnostics& d = result.diagnostics;
  const pcl_vts::ReconstructionDiagnostics& rd = result.reconstruction;
  out.done(msSince(start), std::to_string(d.triangles) + " triangles");
  char layout[128];
  if (d.lattice_columns > 0) // the lattice fast path (docs/algorithm.md section 7)
    std::snprintf(layout, sizeof layout, "lattice %zu x %zu, %zu fringe pieces",
                  d.lattice_columns, d.lattice_rows, d.lattice_fringe_pieces);
  else
    std::snprintf(layout, sizeof layout, "cell size %.6g, %zu cells", d.cell_size,
                  d.cells);
  out.line("  grid         [done, %.1f ms : %zu non-finite dropped, %zu duplicates "
           "merged (keep %s z), %zu distinct points, %s]\n",
           1e3 * d.seconds_grid, d.non_finite_dropped, d.duplicates_merged,
           pcl_vts::duplicateRuleName(opt.vts.duplicate_rule), d.distinct_points,
           layout);
  out.line("  hull         [done, %.1f ms : %zu hull vertices]\n", 1e3 * d.seconds_hull,
           d.hull_vertices);
  out.line("  triangulate  [done, %.1f ms : %zu triangles]\n",
           1e3 * d.seconds_triangulate,
           opt.no_trim && opt.no_fill ? d.triangles : rd.triangles_in);
  if (opt.no_trim)
    out.line("  trim         [off : --no-trim]\n");
  else
    out.line(
        "  trim         [done, %.1f ms : %zu outward triangles removed, %zu points "
        "left without triangles, local spacing %.6g]\n",
        1e3 * rd.seconds_trim, rd.trim.triangles_removed, rd.trim.vertices_lost,
        rd.trim.spacing);
  printFillLine(out, opt.no_fill, rd.seconds_fill, rd.fill);

  out.begin("Writing '%s' ", opt.output.c_str());
  start = Clock::now();
  // The canonical order (tiled_mesh.h): the same bytes as a tiled run would write,
  // on the meshing's threads.
  if (pcl_vts::Status s = pcl_vts::canonicalMesh(
          result.mesh, opt.no_fill ? nullptr : &result.reconstruction.fill.inserted,
          opt.vts.threads > 0 ? opt.vts.threads : pcl_vts::allCores());
      !s.ok())
    return out.fail(EXIT_INTERNAL, s.message);
  pcl_vts::MeshWriteOptions write_options;
  write_options.ascii = opt.ascii;
  write_options.force_double = opt.force_double;
  if (!opt.no_fill && rd.fill.inserted.size() == result.mesh.vertexCount())
    write_options.inserted = &rd.fill.inserted; // marks the points hole filling added
  write_options.comment =
      std::string("pcl_vts pcd_to_mesh: ") +
      (opt.no_trim && opt.no_fill ? "Delaunay triangulation of " : "surface mesh of ") +
      opt.input;
  if (!opt.gis.crs().empty()) // the full WKT goes to the .prj sidecar
    write_options.comment += "; crs: " + opt.gis.crsName();
  pcl_vts::MeshWriteInfo written;
  if (pcl_vts::Status s =
          pcl_vts::writeMesh(opt.output, result.mesh, write_options, &written);
      !s.ok())
    return out.fail(s.code == pcl_vts::StatusCode::IO_ERROR ? EXIT_OUTPUT
                                                            : EXIT_INTERNAL,
                    s.message);
  const double ms_write = msSince(start);
  const std::string precision = format == pcl_vts::MeshFileFormat::OBJ
                                    ? "full-precision text"
                                : written.double_vertices ? "double vertices"
                                                          : "float vertices (exact)";
  out.done(ms_write, std::string(written.ascii ? "ASCII " : "binary ") +
                         pcl_vts::meshFileFormatName(written.format) + ", " +
                         precision + ", " + std::to_string(written.bytes) + " bytes");

  double ms_picture = 0.0;
  if (!opt.png.empty()) {
    out.begin("Drawing '%s' ", opt.png.c_str());
    start = Clock::now();
    std::uint64_t bytes = 0;
    std::string size;
    if (pcl_vts::Status s =
            drawMesh(opt, result.mesh,
                     write_options.inserted ? *write_options.inserted
                                            : std::vector<std::uint8_t>{},
                     size, bytes);
        !s.ok())
      return out.fail(s.code == pcl_vts::StatusCode::IO_ERROR ? EXIT_OUTPUT
                                                              : EXIT_INTERNAL,
                      s.message);
    ms_picture = msSince(start);
    out.done(ms_picture,
             size + ", top and oblique views, " + std::to_string(bytes) + " bytes");
  }

  std::vector<std::string> gis_lines; // --dem, --contours, the .prj (gis_cli.h)
  start = Clock::now();
  // As a tiled run reports a product's failure: a file not written is EXIT_OUTPUT, a
  // bad value (an interval too small for the data) EXIT_USAGE.
  if (pcl_vts::Status s = opt.gis.write(result.mesh, opt.output, gis_lines); !s.ok())
    return out.fail(s.code == pcl_vts::StatusCode::IO_ERROR ? EXIT_OUTPUT
                                                            : exitCodeFor(s.code),
                    s.message);
  for (const std::string& line : gis_lines)
    out.line("GIS: %s\n", line.c_str());
  if (!gis_lines.empty())
    out.line("GIS: written in %.1f ms\n", msSince(start));

  out.line("Summary\n");
  out.line("  %-20s %zu\n", "points read", input.points_read);
  out.line("  %-20s %zu\n", "points kept", input.points_kept);
  if (!opt.gis.crs().empty())
    out.line("  %-20s %s\n", "coordinate system", opt.gis.crsName().c_str());
  if (opt.preprocess.any())
    out.line("  %-20s %zu (%.1f ms)\n", "after preprocessing", n_points, ms_preprocess);
  out.line("  %-20s %zu\n", "non-finite dropped", d.non_finite_dropped);
  out.line("  %-20s %zu\n", "duplicates merged", d.duplicates_merged);
  out.line("  %-20s %zu\n", "distinct points", d.distinct_points);
  out.line("  %-20s %zu\n", "hull vertices", d.hull_vertices);
  out.line("  %-20s %zu\n", "triangles", d.triangles);
  if (!opt.no_trim)
    out.line("  %-20s %zu\n", "trimmed triangles", rd.trim.triangles_removed);
  if (!opt.no_fill) {
    out.line("  %-20s %zu found, %zu filled, %zu left open, %zu not fillable\n",
             "holes", rd.fill.holes_found, rd.fill.holes_filled,
             rd.fill.holes_left_open, rd.fill.holes_skipped);
    out.line("  %-20s %zu\n", "points inserted", rd.fill.points_inserted);
  }
  out.line("  %-20s read %.1f, grid %.1f, hull %.1f, triangulate %.1f, trim %.1f, "
           "fill %.1f, write %.1f, %s%stotal %.1f\n",
           "time (ms)", ms_read, 1e3 * d.seconds_grid, 1e3 * d.seconds_hull,
           1e3 * d.seconds_triangulate, 1e3 * rd.seconds_trim, 1e3 * rd.seconds_fill,
           ms_write, opt.png.empty() ? "" : "picture ",
           opt.png.empty() ? "" : (formatMs(ms_picture) + ", ").c_str(),
           msSince(t_total));
  out.line("  %-20s %.1f MiB\n", "peak memory", peakMemoryMiB());
  out.line("  %-20s %s\n", "mesh written to", opt.output.c_str());
  if (!opt.png.empty())
    out.line("  %-20s %s\n", "picture written to", opt.png.c_str());
  std::fflush(stdout);
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  // Our own messages only: PCL's reader would add warnings and errors to stderr.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  // A closed stdout (`| head`) or a file size limit must not kill the run: the write
  // fails, is reported, and the temp file is removed.
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGXFSZ, SIG_IGN);
#ifdef PCL_VTS_MPI_TOOL
  // Every rank parses the same arguments and runs the same tiled job; rank 0 speaks.
  const pcl_vts::MpiSession mpi(&argc, &argv);
  if (!mpi.threadsSupported()) {
    std::fprintf(stderr,
                 "pcd_to_mesh: error: this MPI library cannot serialize calls from "
                 "threads (MPI_THREAD_SERIALIZED)\n");
    return EXIT_INTERNAL;
  }
  pcl_vts::MpiComm comm;
  g_silent = comm.rank() != 0;
#else
  pcl_vts::LocalComm comm;
#endif
  Reporter errors(true);
  try {
    CliOptions options;
    std::string error;
    if (!parseArgs(argc, argv, options, error))
      return errors.fail(EXIT_USAGE, error + " (see pcd_to_mesh --help)");
    if (options.help) {
      printHelp();
      return 0;
    }
    return run(options, comm);
  } catch (const std::bad_alloc&) {
    return errors.fail(EXIT_INTERNAL, "out of memory");
  } catch (const std::exception& e) {
    return errors.fail(EXIT_INTERNAL, std::string("internal error: ") + e.what());
  }
}
