// The web viewer: GET / answers the page, GET /web/{path} its scripts, styles and the CesiumJS
// build (copied into the web root by scripts/build-web.sh), all from options().web_root. Paths are
// checked by ResolveStaticPath, so no request reads outside the web root.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>

#include "service/json_reply.h"
#include "service/routes.h"
#include "service/static_files.h"

namespace tinbase::service {

namespace {

// A validator that changes whenever the file is rewritten (a rebuild of the page).
std::string EntityTag(const std::filesystem::path& file) {
  std::error_code error;
  const auto size = std::filesystem::file_size(file, error);
  const auto time = std::filesystem::last_write_time(file, error);
  std::ostringstream tag;
  tag << '"' << size << '-' << time.time_since_epoch().count() << '"';
  return tag.str();
}

void ServeFile(const std::string& web_root, const std::string& relative,
               const httplib::Request& req, httplib::Response& res) {
  if (web_root.empty()) {
    ReplyError(res, 404, "no_viewer", "this service has no viewer (started without --web-root)");
    return;
  }
  auto file = ResolveStaticPath(web_root, relative);
  if (!file.ok()) {
    if (relative == "index.html" && file.status().code() == StatusCode::kNotFound) {
      ReplyError(res, 404, "no_viewer",
                 "the viewer is not built in '" + web_root + "' (scripts/build-web.sh builds it)");
      return;
    }
    ReplyStatus(res, file.status());
    return;
  }
  // Browsers revalidate every file (no-cache) and get 304 while it is unchanged, so a rebuilt
  // viewer is picked up at the next load without a stale mix of old and new modules.
  const std::string tag = EntityTag(*file);
  res.set_header("Cache-Control", "no-cache");
  res.set_header("ETag", tag);
  if (req.get_header_value("If-None-Match") == tag) {
    res.status = 304;
    return;
  }
  std::ifstream in(*file, std::ios::binary);
  auto body = std::make_shared<std::string>((std::istreambuf_iterator<char>(in)),
                                            std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) {
    ReplyError(res, 500, "io_error", "cannot read the viewer's file '" + relative + "'");
    return;
  }
  if (body->empty()) {
    res.set_content("", StaticContentType(*file));
    return;
  }
  // A provider of known length is sent as is: cpp-httplib would otherwise compress text answers
  // with brotli at its slowest setting when the browser accepts "br", which takes tens of
  // seconds for Cesium's few megabytes; on loopback the plain bytes are faster.
  res.set_content_provider(body->size(), StaticContentType(*file),
                           [body](size_t offset, size_t length, httplib::DataSink& sink) {
                             return sink.write(body->data() + offset, length);
                           });
}

}  // namespace

void RegisterViewerRoutes(httplib::Server& server, ServiceContext& context) {
  const std::string web_root = context.options().web_root;
  server.Get("/", [web_root](const httplib::Request& req, httplib::Response& res) {
    ServeFile(web_root, "index.html", req, res);
  });
  server.Get(R"(/web/(.+))", [web_root](const httplib::Request& req, httplib::Response& res) {
    ServeFile(web_root, req.matches[1].str(), req, res);
  });
}

}  // namespace tinbase::service
