#pragma once
// The files of a tiled measure in parts (terrain/tiled_partial.h): a shard's
// partial result (`surfreg measure --tile=N --shard=K/N --partial=P.json`),
// the checkpoint of a running tiled measure (for `--resume`), and the DoD
// kept in horizontal bands of rows until they are joined into one GeoTIFF.
//
// A partial is one JSON object: "surfreg": "tiled measure part", the
// settings it was measured with (inputs and options, compared by the merge
// and the resume), the state (doubles in 17 significant digits, which read
// back as the same doubles; NaN as null), the report's fields (files, CRSs,
// frame, weights) and its DoD band ("dod", a path relative to the partial).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terrain/tiled_partial.h"
#include "tools/measure_run.h"

namespace surfreg {

// A band of the DoD: rows [first_row, first_row + rows) of a raster of
// columns x raster_rows cells (its geotransform and CRS), in file `path`.
struct DodBand {
  std::string path;
  int32_t first_row = 0, rows = 0, columns = 0, raster_rows = 0;
  std::array<double, 6> geotransform{};  // the whole raster's
  std::string crs_wkt;
};

// A partial as read back.
struct PartFile {
  std::string path;
  std::string settings;
  TiledPartial part;
  MeasureReport report;  // the fields a merged report needs (no summary)
  DodBand dod;           // path "" without a DoD
};

// The JSON of `part` with `settings`, the report's fields (null: none, a
// checkpoint) and its DoD band (dod.path made relative to `json_path`'s
// directory).
std::string PartJson(const TiledPartial& part, const std::string& settings,
                     const MeasureReport* report, const DodBand& dod, const std::string& json_path);

// Reads a partial or checkpoint; InputError "<path>: ..." when it is none.
PartFile ReadPart(const std::string& path);

// True if the file starts as a partial does ('{'), for `surfreg merge`.
bool LooksLikePart(const std::string& path);

// Joins the DoD bands (in row order, adjacent) into one GeoTIFF `out` of
// their rows, with `patches` (row-major) replacing the values they name;
// read and written a few hundred rows at a time. `label` starts errors.
void JoinDodBands(const std::vector<DodBand>& bands, const std::vector<TiledDodPatch>& patches,
                  const std::string& out, const std::string& label);

// surfreg merge OUT.json PART.json...: the measure of the parts as one run's
// (the --json document into OUT.json; the text report, or the JSON with
// --json, on stdout) and, with --dod=DOD.tif, their DoD bands as one GeoTIFF.
// `print_text` prints the text report (run_measure.cc's).
int MergeMeasureParts(const std::vector<std::string>& args, const std::string& dod, bool json,
                      void (*print_text)(const MeasureReport&));

}  // namespace surfreg
