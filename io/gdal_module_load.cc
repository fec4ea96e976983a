// Finding and loading libsurfreg_gdal.so (see gdal_module.h).
#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "io/gdal_module.h"

namespace surfreg {
namespace {

constexpr const char* kFileName = "libsurfreg_gdal.so";

std::string DirectoryOf(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// Where to look, in order (gdal_module.h).
std::vector<std::string> Candidates() {
  std::vector<std::string> paths;
  if (const char* named = std::getenv("SURFREG_GDAL_MODULE"); named != nullptr && *named != '\0') {
    paths.push_back(named);
    return paths;  // the user's choice, and nothing else
  }
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&Gdal), &info) != 0 && info.dli_fname != nullptr) {
    const std::string here = DirectoryOf(info.dli_fname);
    paths.push_back(here + "/" + kFileName);
#ifdef SURFREG_GDAL_MODULE_FROM_BIN
    paths.push_back(here + "/" SURFREG_GDAL_MODULE_FROM_BIN "/" + kFileName);
#endif
  }
#ifdef SURFREG_GDAL_MODULE_INSTALLED
  paths.push_back(SURFREG_GDAL_MODULE_INSTALLED);
#endif
#ifdef SURFREG_GDAL_MODULE_BUILT
  paths.push_back(SURFREG_GDAL_MODULE_BUILT);
#endif
  return paths;
}

struct Loaded {
  const GdalModule* module = nullptr;
  std::string why;  // when module is null
};

Loaded Load() {
  Loaded loaded;
#ifdef SURFREG_WITHOUT_GDAL
  loaded.why = "this surfreg was built without GDAL (cmake -DSURFREG_GDAL=OFF, or libgdal-dev missing)";
  return loaded;
#endif
  const char* named = std::getenv("SURFREG_GDAL_MODULE");
  const bool chosen = named != nullptr && *named != '\0';
  std::string tried;
  for (const std::string& path : Candidates()) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* text = dlerror();
      // A missing candidate is normal; a present one that fails is the news.
      const std::string message = text != nullptr ? text : "";
      if (chosen || message.find("No such file") == std::string::npos) tried += "; " + message;
      continue;
    }
    using Entry = const GdalModule* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, "surfreg_gdal_module"));
    const GdalModule* module = entry != nullptr ? entry() : nullptr;
    if (module != nullptr && module->version == kGdalModuleVersion) {
      loaded.module = module;  // kept loaded for the process's life
      return loaded;
    }
    // An older module lacks entry points (e.g. vector masks): never call it.
    tried += "; " + path +
             (module == nullptr ? " is not a surfreg GDAL module"
                                : " is GDAL module version " + std::to_string(module->version) +
                                      ", but this surfreg needs version " +
                                      std::to_string(kGdalModuleVersion) +
                                      " (reinstall surfreg, or point SURFREG_GDAL_MODULE at its module)");
    dlclose(handle);
  }
  loaded.why = "cannot load " + std::string(kFileName) +
               (chosen ? " from SURFREG_GDAL_MODULE"
                       : " (looked next to the program, in the install and build trees)") +
               tried;
  return loaded;
}

}  // namespace

const GdalModule& Gdal(const std::string& what) {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = Load(); });
  if (loaded.module == nullptr) throw InputError(what + ": needs GDAL, but " + loaded.why);
  return *loaded.module;
}

}  // namespace surfreg
