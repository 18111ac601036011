// Small helpers every user of GDAL/OGR in core/ shares: driver registration, owning dataset
// pointers, and a scope that keeps GDAL's own error printing quiet while its messages are
// turned into Status values. Thread-safety: registration is once-only; QuietGdalErrors acts on
// the calling thread's error handler stack only.
#pragma once

#include <gdal_priv.h>

#include <memory>
#include <mutex>
#include <string>

namespace tinbase {

// Registers GDAL's drivers the first time it is called.
inline void RegisterGdalDriversOnce() {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
}

struct GdalDatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using GdalDatasetPtr = std::unique_ptr<GDALDataset, GdalDatasetCloser>;

// While alive, GDAL errors on this thread are recorded (CPLGetLastErrorMsg) but not printed:
// we report them through Status with the user's file name instead.
class QuietGdalErrors {
 public:
  QuietGdalErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdalErrors() { CPLPopErrorHandler(); }
  QuietGdalErrors(const QuietGdalErrors&) = delete;
  QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;
};

// " (GDAL's last message)" or "" when there is none, to append to our own message.
inline std::string LastGdalError() {
  const char* msg = CPLGetLastErrorMsg();
  return msg != nullptr && *msg != '\0' ? std::string(" (") + msg + ")" : "";
}

}  // namespace tinbase
