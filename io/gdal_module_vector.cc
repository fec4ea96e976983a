// Vector masks through OGR, inside libsurfreg_gdal.so (see gdal_module.h):
// the polygon rings of one layer, with their names and the layer's CRS.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <map>
#include <mutex>
#include <memory>
#include <string>

#include "io/gdal_module.h"

namespace surfreg {
namespace {

// GDAL's own errors stay off stderr; the last one goes into our message.
struct QuietErrors {
  QuietErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietErrors() { CPLPopErrorHandler(); }
  std::string Detail() const {
    const char* last = CPLGetLastErrorMsg();
    return last != nullptr && *last != '\0' ? std::string(" (GDAL: ") + last + ")" : "";
  }
};

// OGC names as users know them ("LineString", not "Line String").
std::string TypeName(OGRwkbGeometryType type) {
  switch (wkbFlatten(type)) {
    case wkbPoint: return "Point";
    case wkbLineString: return "LineString";
    case wkbMultiPoint: return "MultiPoint";
    case wkbMultiLineString: return "MultiLineString";
    case wkbGeometryCollection: return "GeometryCollection";
    case wkbNone: return "no geometry";
    default: return OGRGeometryTypeToName(wkbFlatten(type));
  }
}

void AddPolygon(const OGRPolygon& polygon, const std::string& name, VectorRings* out) {
  const int interior = polygon.getNumInteriorRings();
  for (int k = -1; k < interior; ++k) {
    const OGRLinearRing* ring = k < 0 ? polygon.getExteriorRing() : polygon.getInteriorRing(k);
    if (ring == nullptr || ring->IsEmpty()) continue;
    std::vector<std::array<double, 2>> points;
    for (int i = 0; i < ring->getNumPoints(); ++i) points.push_back({ring->getX(i), ring->getY(i)});
    if (points.size() > 1 && points.front() == points.back()) points.pop_back();  // closed in OGR
    out->rings.push_back(std::move(points));
    out->names.push_back(name + " ring " + std::to_string(k + 2));
  }
}

}  // namespace

bool ReadVectorRings(const std::string& path, const std::string& layer_name, VectorRings* out,
                     std::string* error) {
  try {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    QuietErrors quiet;
    GDALDatasetUniquePtr dataset(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (dataset == nullptr) {
      *error = path + ": cannot read as a vector file" + quiet.Detail();
      return false;
    }
    OGRLayer* layer = nullptr;
    if (layer_name.empty()) {
      if (dataset->GetLayerCount() > 0) layer = dataset->GetLayer(0);
      if (layer == nullptr) {
        *error = path + ": has no layers";
        return false;
      }
    } else {
      layer = dataset->GetLayerByName(layer_name.c_str());
      if (layer == nullptr) {
        std::string names;
        for (int k = 0; k < dataset->GetLayerCount(); ++k) {
          names += (k == 0 ? "'" : ", '") + std::string(dataset->GetLayer(k)->GetName()) + "'";
        }
        *error = path + ": no layer '" + layer_name + "' (layers: " +
                 (names.empty() ? "none" : names) + ")";
        return false;
      }
    }
    std::map<std::string, int> other;  // what the layer holds besides polygons
    for (auto& feature : *layer) {
      const OGRGeometry* geometry = feature->GetGeometryRef();
      if (geometry == nullptr) {
        ++other["no geometry"];
        continue;
      }
      std::unique_ptr<OGRGeometry> linear;
      const OGRwkbGeometryType type = wkbFlatten(geometry->getGeometryType());
      if (type == wkbCurvePolygon || type == wkbMultiSurface) {  // arcs: as line segments
        linear.reset(geometry->getLinearGeometry());
        if (linear != nullptr) geometry = linear.get();
      }
      const std::string name = "feature " + std::to_string(feature->GetFID());
      switch (wkbFlatten(geometry->getGeometryType())) {
        case wkbPolygon: AddPolygon(*geometry->toPolygon(), name, out); break;
        case wkbMultiPolygon: {
          const OGRMultiPolygon& parts = *geometry->toMultiPolygon();
          for (int k = 0; k < parts.getNumGeometries(); ++k) {
            AddPolygon(*parts.getGeometryRef(k), name + " polygon " + std::to_string(k + 1), out);
          }
          break;
        }
        default: ++other[TypeName(geometry->getGeometryType())];
      }
    }
    if (out->rings.empty()) {
      std::string found;
      for (const auto& [type, count] : other) {
        found += (found.empty() ? "" : ", ") + std::to_string(count) + " " + type;
      }
      *error = path + ": layer '" + layer->GetName() + "' has no polygon features (found " +
               (found.empty() ? "no features" : found) + ")";
      return false;
    }
    if (const OGRSpatialReference* srs = layer->GetSpatialRef()) {
      char* wkt = nullptr;
      const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
      if (srs->exportToWkt(&wkt, options) == OGRERR_NONE && wkt != nullptr) out->crs_wkt = wkt;
      CPLFree(wkt);
    }
    return true;
  } catch (const std::exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
}

}  // namespace surfreg
