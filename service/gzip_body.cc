// Gzip for answers, with zlib.
#include "service/gzip_body.h"

#include <zlib.h>

#include "service/header_lists.h"

namespace tinbase::service {

Result<std::string> Gzip(std::string_view bytes) {
  z_stream z{};
  constexpr int kGzipWindow = 15 + 16;  // 16: a gzip header and trailer instead of zlib's
  if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) !=
      Z_OK)
    return Status::IOError("zlib: cannot start gzip");
  std::string out(deflateBound(&z, static_cast<uLong>(bytes.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (rc != Z_STREAM_END) return Status::IOError("zlib: gzip did not finish");
  return out;
}

bool AcceptsGzip(const httplib::Request& req) {
  if (!req.has_header("Accept-Encoding")) return false;
  bool named = false, gzip = false, any = false;
  for (const HeaderElement& e : ParseHeaderList(req.get_header_value("Accept-Encoding"))) {
    if (e.value == "gzip" || e.value == "x-gzip") {
      named = true;
      gzip = gzip || e.q > 0;
    } else if (e.value == "*") {
      any = e.q > 0;
    }
  }
  return named ? gzip : any;
}

}  // namespace tinbase::service
