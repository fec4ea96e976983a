#include "terrain/terrain_request.h"

#include <string>

#include "measure/input_error.h"
#include "io/raster_io.h"
#include "io/surface_reader_internal.h"

namespace surfreg {

bool TerrainSettings::Active(const std::string& reference, const std::string& moving) const {
  // A LAS file may carry a CRS, which only the terrain reading resolves.
  const auto las = [](const std::string& path) { return io_internal::Extension(path) == ".las"; };
  return IsRasterPath(reference) || IsRasterPath(moving) || las(reference) || las(moving) ||
         !reference_crs.empty() ||
         !moving_crs.empty() || lod > 0 || !dod.empty() || !dod_png.empty() ||
         !histogram_png.empty() || !change_csv.empty() || !known_matrix.empty() ||
         !mask_raster.empty() || !sigma_reference.empty() || !sigma_moving.empty() ||
         lod_confidence > 0 || !dod_sigma.empty() || !dod_thresholded.empty() ||
         error_model != "independent" || !variogram_png.empty() || !change_mask.empty();
}

std::string TerrainRequest::Where(const std::string& key) const {
  const auto found = origin.find(key);
  return found != origin.end() ? found->second : "key '" + key + "'";
}

const std::string& InputPath(const TerrainRequest& request, const std::string& key) {
  return key == "reference" ? request.reference : request.moving;
}

ReadOptions InputReadOptions(const TerrainRequest& config, const std::string& key) {
  const std::string& path = InputPath(config, key);
  const std::string& other = InputPath(config, key == "reference" ? "moving" : "reference");
  const auto las = [](const std::string& p) { return io_internal::Extension(p) == ".las"; };
  const auto text = [](const std::string& p) {
    const std::string ext = io_internal::Extension(p);
    return ext == ".xyz" || ext == ".txt" || ext == ".csv";
  };
  // A key meant for the other input's format is not this one's business
  // (a LAS file's ground against a DEM); one that fits neither is refused
  // by the reader of each.
  ReadOptions options;
  if (las(path) || !las(other)) options.classes = config.classes;
  if (text(path) || !text(other)) options.columns = config.columns;
  options.threads = config.options.num_threads;
  return options;
}

Surface ReadInput(const TerrainRequest& config, const std::string& key, std::string* crs) {
  const ReadOptions options = InputReadOptions(config, key);
  try {
    return ReadSurface(InputPath(config, key), options, crs);
  } catch (const InputError& e) {
    // A refusal of `classes` or `columns` names that key too.
    const std::string what = e.what();
    for (const char* option : {"classes", "columns"}) {
      if (config.Given(option) &&
          what.find(std::string("`") + option + "`") != std::string::npos) {
        throw InputError(config.Where(key) + ": " + what + " (" + config.Where(option) + ")");
      }
    }
    throw InputError(config.Where(key) + ": " + what);
  }
}

}  // namespace surfreg
