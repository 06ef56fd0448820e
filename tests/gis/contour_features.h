// The features of a contour file read back with OGR, for comparing two files.
#pragma once

#include <ogrsf_frmts.h>
#include <string>
#include <tuple>
#include <vector>

namespace pcl_vts::test {

/// elev, closed, the geometry as WKB: one per feature, in the file's order.
using ContourFeature = std::tuple<double, int, std::vector<unsigned char>>;

/// The features of the file's first layer; empty when it cannot be opened.
inline std::vector<ContourFeature> contourFeatures(const std::string& path)
{
  GDALAllRegister();
  std::vector<ContourFeature> out;
  GDALDataset* ds = static_cast<GDALDataset*>(
      GDALOpenEx(path.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr));
  if (!ds)
    return out;
  OGRLayer* layer = ds->GetLayer(0);
  layer->ResetReading();
  while (OGRFeature* feature = layer->GetNextFeature()) {
    const OGRGeometry* g = feature->GetGeometryRef();
    std::vector<unsigned char> wkb(g ? g->WkbSize() : 0);
    if (g)
      g->exportToWkb(wkbNDR, wkb.data());
    out.emplace_back(feature->GetFieldAsDouble("elev"),
                     feature->GetFieldAsInteger("closed"), std::move(wkb));
    OGRFeature::DestroyFeature(feature);
  }
  GDALClose(ds);
  return out;
}

} // namespace pcl_vts::test
