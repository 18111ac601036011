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

// GDAL's message `msg` on one line: some messages draw the text they could not parse on a second
// line and a caret under the place on a third (OGR's SQL parser: "... Occurred around :\n<text>\n
// <spaces>^"); that becomes "... at character N" so that a user's error stays one line.
inline std::string OneLineGdalMessage(std::string msg) {
  const size_t first_break = msg.find('\n');
  if (first_break == std::string::npos) return msg;
  const size_t caret = msg.rfind('^');
  const size_t caret_line = msg.rfind('\n', caret);
  std::string out = msg.substr(0, first_break);
  const std::string around = " Occurred around :";
  if (out.size() >= around.size() &&
      out.compare(out.size() - around.size(), around.size(), around) == 0)
    out.resize(out.size() - around.size());
  if (caret != std::string::npos && caret_line != std::string::npos && caret_line >= first_break)
    out += " at character " + std::to_string(caret - caret_line);
  return out;
}

// " (GDAL's last message)" or "" when there is none, to append to our own message.
inline std::string LastGdalError() {
  const char* msg = CPLGetLastErrorMsg();
  return msg != nullptr && *msg != '\0' ? " (" + OneLineGdalMessage(msg) + ")" : "";
}

}  // namespace tinbase
