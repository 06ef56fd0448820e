// ESRI ASCII grid -> double xyz. The header is "key value" lines (any case, any
// order) up to the first line that starts with a number; the body is ncols x nrows
// whitespace-separated values, rows from the top, line breaks anywhere. The claimed
// cell count is checked against the bytes left before anything is reserved.
#include "reader_guard.h"
#include "text_scan.h"

#include <pcl_vts/io/asc_grid_reader.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace pcl_vts {
namespace {

bool startsNumber(char c)
{
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

Status parseAscImpl(const char* p, const char* end, const std::string& name,
                    std::vector<double>& xyz, AscGridInfo& info, PointOutput& output)
{
  if (p == end)
    return ioError(name, "the file is empty (0 bytes)");
  if (end - p >= 3 && std::memcmp(p, "\xEF\xBB\xBF", 3) == 0)
    p += 3; // UTF-8 byte order mark
  std::map<std::string, double> header;
  std::size_t line_no = 0;
  for (;;) {
    while (p != end && (*p == ' ' || *p == '\t'))
      ++p;
    if (p == end || startsNumber(*p))
      break;
    ++line_no;
    const char* eol = p;
    while (eol != end && *eol != '\n')
      ++eol;
    const char* q = p;
    while (q != eol && !text::isSpace(*q))
      ++q;
    const std::string key = text::lower(std::string(p, q));
    while (q != eol && text::isSpace(*q))
      ++q;
    const char* v_end = eol;
    while (v_end != q && text::isSpace(v_end[-1]))
      --v_end;
    if (key.empty()) {
      p = eol == end ? end : eol + 1;
      continue;
    }
    static const char* const KEYS[] = {
        "ncols",     "nrows",    "xllcorner", "xllcenter", "yllcorner",
        "yllcenter", "cellsize", "dx",        "dy",        "nodata_value"};
    bool known = false;
    for (const char* k : KEYS)
      known = known || key == k;
    if (!known)
      return ioError(name, line_no == 1 && header.empty()
                               ? "not an ESRI ASCII grid: first line is '" +
                                     text::excerpt(p, eol) + "'"
                               : "bad ASCII grid header, line " +
                                     std::to_string(line_no) + ": unknown key '" +
                                     text::excerpt(p, q) + "'");
    double value = 0.0;
    if (!text::parseDouble(q, v_end, value))
      return ioError(name, "bad ASCII grid header, line " + std::to_string(line_no) +
                               ": " + key + " value '" + text::excerpt(q, v_end) +
                               "' is not a number");
    if (!header.emplace(key, value).second)
      return ioError(name, "bad ASCII grid header: " + key + " given twice");
    p = eol == end ? end : eol + 1;
  }
  const auto has = [&](const char* k) { return header.count(k) != 0; };
  for (const char* k : {"ncols", "nrows"})
    if (!has(k))
      return ioError(name, std::string("bad ASCII grid header: no ") + k);
  if (has("xllcorner") == has("xllcenter") || has("yllcorner") == has("yllcenter"))
    return ioError(name, "bad ASCII grid header: needs exactly one of xllcorner / "
                         "xllcenter and one of yllcorner / yllcenter");
  if (has("cellsize") ? (has("dx") || has("dy")) : !(has("dx") && has("dy")))
    return ioError(name, "bad ASCII grid header: needs cellsize (or dx and dy)");
  const double ncols = header["ncols"], nrows = header["nrows"];
  for (auto [k, v] : {std::pair{"ncols", ncols}, std::pair{"nrows", nrows}})
    if (!(v >= 1.0 && v <= 2147483647.0 && v == std::floor(v)))
      return ioError(name, std::string("bad ASCII grid header: ") + k + " " +
                               formatValue(v) + " is not an integer in [1, 2^31)");
  info.ncols = static_cast<std::size_t>(ncols);
  info.nrows = static_cast<std::size_t>(nrows);
  info.cell_dx = has("cellsize") ? header["cellsize"] : header["dx"];
  info.cell_dy = has("cellsize") ? header["cellsize"] : header["dy"];
  if (!(info.cell_dx > 0.0) || !(info.cell_dy > 0.0) || !std::isfinite(info.cell_dx) ||
      !std::isfinite(info.cell_dy))
    return ioError(name, "bad ASCII grid header: cell size " +
                             formatValue(info.cell_dx) + " x " +
                             formatValue(info.cell_dy) + " must be finite and > 0");
  info.centre_registered = has("xllcenter");
  const double x0 = has("xllcorner") ? header["xllcorner"] : header["xllcenter"];
  const double y0 = has("yllcorner") ? header["yllcorner"] : header["yllcenter"];
  if (!std::isfinite(x0) || !std::isfinite(y0))
    return ioError(name, "bad ASCII grid header: lower-left corner is not finite");
  info.xll = has("xllcorner") ? x0 : x0 - 0.5 * info.cell_dx;
  info.yll = has("yllcorner") ? y0 : y0 - 0.5 * info.cell_dy;
  info.has_nodata = has("nodata_value");
  info.nodata = info.has_nodata ? header["nodata_value"] : 0.0;

  // Each value takes at least one character and one separator.
  const std::size_t cells = info.ncols * info.nrows; // < 2^62
  const auto left = static_cast<std::size_t>(end - p);
  if (cells > left / 2 + 1)
    return ioError(name, "truncated: header claims " + std::to_string(info.ncols) +
                             " x " + std::to_string(info.nrows) + " cells, only " +
                             std::to_string(left) + " bytes of values follow");
  xyz.clear();
  xyz.reserve(3 * output.reserve(cells));
  output.begin(p);
  std::size_t cell = 0;
  for (;;) {
    while (p != end && text::isSpace(*p))
      ++p;
    if (p == end)
      break;
    if (output.full(xyz))
      if (Status s = output.handOver(xyz, p); !s.ok())
        return s;
    const char* q = p;
    while (q != end && !text::isSpace(*q))
      ++q;
    if (cell == cells)
      return ioError(
          name, "corrupt: more values than ncols x nrows = " + std::to_string(cells) +
                    " (at '" + text::excerpt(p, q) + "')");
    double z = 0.0;
    if (!text::parseDouble(p, q, z))
      return ioError(name, "corrupt: value " + std::to_string(cell + 1) + " '" +
                               text::excerpt(p, q) + "' is not a number");
    if (info.has_nodata && z == info.nodata) {
      ++info.nodata_cells;
    } else {
      const std::size_t r = cell / info.ncols, c = cell % info.ncols;
      xyz.push_back(info.xll + (static_cast<double>(c) + 0.5) * info.cell_dx);
      xyz.push_back(info.yll +
                    (static_cast<double>(info.nrows - r) - 0.5) * info.cell_dy);
      xyz.push_back(z);
    }
    ++cell;
    p = q;
  }
  if (cell != cells)
    return ioError(name, "truncated: " + std::to_string(cell) + " values, ncols x " +
                             "nrows = " + std::to_string(cells));
  if (Status s = output.finish(xyz, end, info.points); !s.ok())
    return s;
  if (info.points == 0)
    return Status::error(StatusCode::EMPTY_INPUT,
                         "'" + name + "': all " + std::to_string(cells) +
                             " cells are NODATA (" + formatValue(info.nodata) + ")");
  return Status::success();
}

} // namespace

Status parseAscGrid(const std::uint8_t* data, std::size_t size, const std::string& name,
                    std::vector<double>& xyz, AscGridInfo& info)
{
  return guardedParse(name, xyz, info, [&] {
    const char* p = reinterpret_cast<const char*>(data);
    PointOutput whole;
    return parseAscImpl(p, p + size, name, xyz, info, whole);
  });
}

Status readAscGridChunks(const std::string& path, std::size_t chunk_points,
                         const AscChunkSink& sink, AscGridInfo& info)
{
  return readMappedFileInChunks(path, sink, chunk_points, info,
                                [&](const std::uint8_t* data, std::size_t size,
                                    std::vector<double>& chunk, PointOutput& output) {
                                  const char* p = reinterpret_cast<const char*>(data);
                                  return parseAscImpl(p, p + size, path, chunk, info,
                                                      output);
                                });
}

Status readAscGrid(const std::string& path, std::vector<double>& xyz, AscGridInfo& info)
{
  return readMappedFile(path, xyz, info,
                        [&](const std::uint8_t* data, std::size_t size) {
                          return parseAscGrid(data, size, path, xyz, info);
                        });
}

} // namespace pcl_vts
