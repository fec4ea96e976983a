// Format dispatch, file reading and the helpers shared by all readers.
#include "io/surface_reader.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <memory>

#include "measure/input_error.h"
#include "io/raster_io.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace io_internal {

void Fail(const std::string& name, std::size_t line, const std::string& what) {
  std::string message = name;
  if (line > 0) message += ":" + std::to_string(line);
  message += ": ";
  message += what;
  throw InputError(message);
}

bool ParseCount(std::string_view token, unsigned long long* value) {
  const char* last = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), last, *value);
  return !token.empty() && ec == std::errc() && ptr == last;
}

void CheckNumber(NumberStatus status, double value, std::string_view token, const char* what,
                 const std::string& name, std::size_t line) {
  if (status == NumberStatus::kNotANumber) {
    Fail(name, line, std::string(what) + " is not a number: " + Quote(token));
  }
  if (status == NumberStatus::kOutOfRange) {
    Fail(name, line, std::string(what) + " is out of the range of double: " + Quote(token));
  }
  if (std::isnan(value)) Fail(name, line, std::string(what) + " is NaN");
  if (std::isinf(value)) Fail(name, line, std::string(what) + " is infinite");
}

bool LineCursor::Next(std::string_view* line) {
  if (pos_ >= data_.size()) return false;
  const std::size_t end = data_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? data_.size() : end;
  *line = data_.substr(pos_, stop - pos_);
  pos_ = end == std::string_view::npos ? data_.size() : end + 1;
  ++next_line_;
  return true;
}

bool NextToken(std::string_view* rest, std::string_view* token) {
  std::size_t i = 0;
  while (i < rest->size() && IsBlank((*rest)[i])) ++i;
  if (i == rest->size()) {
    *rest = {};
    return false;
  }
  std::size_t j = i;
  while (j < rest->size() && !IsBlank((*rest)[j])) ++j;
  *token = rest->substr(i, j - i);
  rest->remove_prefix(j);
  return true;
}

std::string_view StripComment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

Surface Finish(PointList&& list, const std::string& name, const ReadOptions& options) {
  if (list.points.empty()) Fail(name, 0, "no points (empty file, or only comments and headers)");
  CheckPointCount(list.points.size(), name, options);
  Surface surface = MakeSurface(list.points, std::move(list.weight), name, options.origin_step);
  ValidateSurface(surface);
  return surface;
}

std::string ReadAll(std::istream& in, const std::string& name) {
  std::string data;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof(chunk)) || in.gcount() > 0) {
    data.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) Fail(name, 0, "read error");
  return data;
}

// Whole file as bytes; unreadable files and directories are InputErrors.
std::string ReadFile(const std::string& path) {
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  errno = 0;
  std::unique_ptr<std::FILE, Closer> file(std::fopen(path.c_str(), "rb"));
  if (!file) Fail(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string data;
  std::size_t used = 0;
  // One byte more than the file, so that the first read reaches its end
  // (no doubling, no twice the file in memory); a pipe grows as it goes.
  struct stat status;
  const bool regular = fstat(fileno(file.get()), &status) == 0 && S_ISREG(status.st_mode);
  data.resize(regular ? static_cast<std::size_t>(status.st_size) + 1 : std::size_t{1} << 20);
  for (;;) {
    used += std::fread(&data[used], 1, data.size() - used, file.get());
    if (used < data.size()) break;
    data.resize(2 * data.size());
  }
  // A directory opens fine on Linux and fails here with EISDIR.
  if (std::ferror(file.get())) Fail(path, 0, std::string("cannot read: ") + std::strerror(errno));
  data.resize(used);
  return data;
}

void CheckOptionsFit(const ReadOptions& options, OptionFit kind, const std::string& format,
                     const std::string& name) {
  const std::string file = format.empty() ? "this file" : "a " + format + " file";
  if (!options.classes.empty() && kind != OptionFit::kLas) {
    Fail(name, 0, "`classes` keeps LAS classifications, but " + file + " has no classes");
  }
  if (!options.columns.empty() && kind != OptionFit::kText) {
    Fail(name, 0,
         "`columns` picks the columns of a text cloud (.xyz .txt .csv), but " + file +
             " has no columns");
  }
}

// The lower-case extension of the file name in `path`, with its dot; empty if none.
std::string Extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace io_internal

namespace {

using io_internal::Fail;

// "1.5 GiB"; "12.0 MiB" or "1500 bytes" for small sizes (tests use small limits).
std::string Size(double bytes) {
  char text[32];
  if (bytes >= 1024.0 * 1024 * 1024) {
    std::snprintf(text, sizeof(text), "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
  } else if (bytes >= 1024.0 * 1024) {
    std::snprintf(text, sizeof(text), "%.1f MiB", bytes / (1024.0 * 1024));
  } else {
    std::snprintf(text, sizeof(text), "%.0f bytes", bytes);
  }
  return text;
}

// The number after `key` in a "/proc/meminfo"-style file, times `unit`; 0 if absent.
uint64_t ReadNumber(const char* path, const char* key, uint64_t unit) {
  std::FILE* file = std::fopen(path, "r");
  if (file == nullptr) return 0;
  char line[256];
  uint64_t value = 0;
  const std::size_t key_length = std::strlen(key);
  while (std::fgets(line, sizeof(line), file) != nullptr) {
    if (std::strncmp(line, key, key_length) != 0) continue;
    char* end = nullptr;
    const unsigned long long number = std::strtoull(line + key_length, &end, 10);
    if (end != line + key_length) value = number * unit;
    break;
  }
  std::fclose(file);
  return value;
}

// What the cgroup (v2, else v1) still allows: limit - usage; 0 if unlimited or unknown.
uint64_t CgroupAvailable() {
  uint64_t limit = ReadNumber("/sys/fs/cgroup/memory.max", "", 1);  // "max" reads as 0
  uint64_t usage = ReadNumber("/sys/fs/cgroup/memory.current", "", 1);
  if (limit == 0) {
    limit = ReadNumber("/sys/fs/cgroup/memory/memory.limit_in_bytes", "", 1);
    usage = ReadNumber("/sys/fs/cgroup/memory/memory.usage_in_bytes", "", 1);
    if (limit >= (uint64_t{1} << 60)) limit = 0;  // v1 writes a huge number for "no limit"
  }
  if (limit == 0) return 0;
  return limit > usage ? limit - usage : 1;
}

uint64_t MemoryLimit(const ReadOptions& options) {
  return options.memory_limit_bytes > 0 ? options.memory_limit_bytes : AvailableMemoryBytes();
}

}  // namespace

uint64_t AvailableMemoryBytes() {
  uint64_t available = ReadNumber("/proc/meminfo", "MemAvailable:", 1024);
  if (available == 0) {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page_size = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page_size > 0) available = uint64_t(pages) * uint64_t(page_size);
  }
  const uint64_t cgroup = CgroupAvailable();
  if (cgroup > 0 && (available == 0 || cgroup < available)) available = cgroup;
  struct rlimit limit;
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      (available == 0 || limit.rlim_cur < available)) {
    available = limit.rlim_cur;
  }
  // Nothing readable (not Linux?): do not refuse anything.
  return available > 0 ? available : UINT64_MAX;
}

void CheckPointCount(uint64_t points, const std::string& name, const ReadOptions& options) {
  const double need = static_cast<double>(points) * static_cast<double>(kBytesPerPoint);
  const uint64_t limit = MemoryLimit(options);
  if (need <= static_cast<double>(limit)) return;
  Fail(name, 0,
       std::to_string(points) + " points need about " + Size(need) + ", more than the " +
           Size(static_cast<double>(limit)) + " available");
}

Surface ReadSurface(const std::string& path, const ReadOptions& options, std::string* crs, Raster* grid) {
  using io_internal::OptionFit;
  if (crs != nullptr) crs->clear();
  const std::string ext = io_internal::Extension(path);
  if (IsRasterPath(path)) {
    io_internal::CheckOptionsFit(options, OptionFit::kOther, ext, path);
    RasterReadOptions read;
    read.threads = options.threads;
    Raster raster = ReadRaster(path, read);
    if (crs != nullptr) *crs = raster.crs_wkt;
    Surface surface = RasterToSurface(raster, nullptr, options.origin_step, options.threads);
    if (grid != nullptr) {
      raster.values = {};
      *grid = std::move(raster);
    }
    return surface;
  }
  if (ext == ".laz") {
    Fail(path, 0,
         "LAZ (compressed LAS) is not supported: decompress it first, e.g. `laszip -i x.laz -o "
         "x.las` or `pdal translate x.laz x.las`");
  }
  using Parser = Surface (*)(std::string_view, const std::string&, const ReadOptions&);
  Parser parse = nullptr;
  OptionFit kind = OptionFit::kOther;
  if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    parse = io_internal::ParseXyz;
    kind = OptionFit::kText;
  }
  if (ext == ".ply") parse = io_internal::ParsePly;
  if (ext == ".off") parse = io_internal::ParseOff;
  if (ext == ".obj") parse = io_internal::ParseObj;
  if (ext == ".las") kind = OptionFit::kLas;
  if (parse == nullptr && kind != OptionFit::kLas) {
    const std::string what = ext.empty() ? std::string("no file extension to tell the format")
                                         : "unknown surface format " + io_internal::Quote(ext);
    Fail(path, 0,
         what + " (expected .xyz .txt .csv .ply .off .obj .las, or a GDAL raster: .tif .tiff .vrt "
                ".asc .img .bil .hgt .dem .nc .gpkg .flt)");
  }
  io_internal::CheckOptionsFit(options, kind, ext, path);
  // The file is held in memory while it is parsed: refuse it before reading
  // if that alone is too much (the point count is checked as it is known).
  struct stat status;
  const uint64_t limit = MemoryLimit(options);
  if (stat(path.c_str(), &status) == 0 && S_ISREG(status.st_mode) &&
      static_cast<uint64_t>(status.st_size) > limit) {
    Fail(path, 0,
         "the file is " + Size(static_cast<double>(status.st_size)) + ", more than the " +
             Size(static_cast<double>(limit)) + " available");
  }
  const std::string data = io_internal::ReadFile(path);
  if (kind == OptionFit::kLas) return io_internal::ParseLas(data, path, options, crs);
  return parse(data, path, options);
}

Surface ReadXyz(std::istream& in, const std::string& name, const ReadOptions& options) {
  io_internal::CheckOptionsFit(options, io_internal::OptionFit::kText, ".xyz", name);
  return io_internal::ParseXyz(io_internal::ReadAll(in, name), name, options);
}

Surface ReadPly(std::istream& in, const std::string& name, const ReadOptions& options) {
  io_internal::CheckOptionsFit(options, io_internal::OptionFit::kOther, ".ply", name);
  return io_internal::ParsePly(io_internal::ReadAll(in, name), name, options);
}

Surface ReadOff(std::istream& in, const std::string& name, const ReadOptions& options) {
  io_internal::CheckOptionsFit(options, io_internal::OptionFit::kOther, ".off", name);
  return io_internal::ParseOff(io_internal::ReadAll(in, name), name, options);
}

Surface ReadObj(std::istream& in, const std::string& name, const ReadOptions& options) {
  io_internal::CheckOptionsFit(options, io_internal::OptionFit::kOther, ".obj", name);
  return io_internal::ParseObj(io_internal::ReadAll(in, name), name, options);
}

Surface ReadLas(std::istream& in, const std::string& name, const ReadOptions& options,
                std::string* crs) {
  io_internal::CheckOptionsFit(options, io_internal::OptionFit::kLas, ".las", name);
  return io_internal::ParseLas(io_internal::ReadAll(in, name), name, options, crs);
}

}  // namespace surfreg
