// The align config's inputs read with its reading keys (classes, columns),
// errors naming the config key that set them (tools/align_config.h).
#include <string>

#include "measure/input_error.h"
#include "tools/align_config.h"
#include "tools/io/surface_reader.h"
#include "tools/io/surface_reader_internal.h"

namespace surfreg {

ReadOptions AlignReadOptions(const AlignConfig& config, const std::string& key) {
  const std::string path = AlignConfigValue(config, key);
  const std::string other = AlignConfigValue(config, key == "reference" ? "moving" : "reference");
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
  return options;
}

Surface ReadAlignSurface(const AlignConfig& config, const std::string& key, std::string* crs) {
  const ReadOptions options = AlignReadOptions(config, key);
  try {
    return ReadSurface(AlignConfigValue(config, key), options, crs);
  } catch (const InputError& e) {
    // A refusal of `classes` or `columns` names that key too.
    const std::string what = e.what();
    for (const char* option : {"classes", "columns"}) {
      if (config.origin.count(option) != 0 &&
          what.find(std::string("`") + option + "`") != std::string::npos) {
        throw InputError(config.Where(key) + ": " + what + " (" + config.Where(option) + ")");
      }
    }
    throw InputError(config.Where(key) + ": " + what);
  }
}

}  // namespace surfreg
