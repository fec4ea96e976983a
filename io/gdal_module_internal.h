// What the GDAL module's files share (gdal_module.h): GDAL's registration,
// error capture, handle ownership and the module's error type. Internal to
// libsurfreg_gdal.so.
#pragma once

#include <cpl_error.h>
#include <gdal.h>

#include <cstdio>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>

namespace surfreg {

inline void RegisterGdalOnce() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// While alive, GDAL errors and warnings on this thread go here instead of
// stderr (GDAL's handler stack is per thread); the last failure's text is
// kept for our own one-line message.
class QuietGdal {
 public:
  QuietGdal() { CPLPushErrorHandlerEx(&Handler, this); }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;

  bool failed() const { return failed_; }
  // " (GDAL: <last failure>)", or "" when GDAL reported none.
  std::string Detail() const { return last_.empty() ? "" : " (GDAL: " + last_ + ")"; }
  // " (<last failure>)", for CRS messages (PROJ's text names itself).
  std::string Plain() const { return last_.empty() ? "" : " (" + last_ + ")"; }

 private:
  static void CPL_STDCALL Handler(CPLErr level, CPLErrorNum, const char* message) {
    auto* self = static_cast<QuietGdal*>(CPLGetErrorHandlerUserData());
    if (self == nullptr || level < CE_Failure) return;
    self->failed_ = true;
    self->last_ = message == nullptr ? "" : message;
    for (char& c : self->last_) {
      if (c == '\n' || c == '\r') c = ' ';  // our messages are one line
    }
  }

  bool failed_ = false;
  std::string last_;
};

struct DatasetCloser {
  void operator()(void* dataset) const { GDALClose(static_cast<GDALDatasetH>(dataset)); }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

// Thrown inside the module only; the entry points below turn it into their
// error text.
struct ModuleError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void Fail(const std::string& where, const std::string& what) {
  throw ModuleError(where + ": " + what);
}

inline std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// Runs `body`, turning what it throws into `*error`.
template <typename Body>
bool Guarded(std::string* error, const std::string& where, Body body) {
  try {
    body();
    return true;
  } catch (const ModuleError& e) {
    *error = e.what();
  } catch (const std::bad_alloc&) {
    *error = where + ": out of memory";
  } catch (const std::exception& e) {
    *error = where + ": " + e.what();
  }
  return false;
}

}  // namespace surfreg
