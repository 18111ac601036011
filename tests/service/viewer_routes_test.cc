// The viewer's static files through the socket: the page at /, its files under /web/ with the
// content types browsers need, revalidation, and no way out of the web root.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

void WriteFile(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text;
}

class ViewerRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    RunWrite(store_, "init " + Quote(store_));
    web_ = dir_.Path("web");
    WriteFile(web_ + "/index.html", "<!doctype html><title>tinbase</title>");
    WriteFile(web_ + "/main.js", "export const x = 1;");
    WriteFile(web_ + "/cesium/Assets/approximateTerrainHeights.json", "{}");
    WriteFile(web_ + "/cesium/ThirdParty/draco_decoder.wasm", "\0asm");
    WriteFile(web_ + "/.hidden", "hidden");
    WriteFile(dir_.Path("secret.txt"), "SECRET");
  }
  service::ServiceOptions Options(const std::string& web_root) const {
    service::ServiceOptions options;
    options.store_path = store_;
    options.web_root = web_root;
    return options;
  }

  TempDir dir_;
  std::string store_;
  std::string web_;
};

TEST_F(ViewerRoutesTest, ServesThePageAndItsFilesWithTheirTypes) {
  TestService service(Options(web_));
  ASSERT_TRUE(service.running());
  auto client = service.Client();
  auto page = client->Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(page->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(page->body.find("<title>tinbase</title>"), std::string::npos);
  auto script = client->Get("/web/main.js");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->status, 200);
  EXPECT_EQ(script->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(script->body, "export const x = 1;");
  auto json = client->Get("/web/cesium/Assets/approximateTerrainHeights.json");
  ASSERT_TRUE(json);
  EXPECT_EQ(json->get_header_value("Content-Type"), "application/json");
  auto wasm = client->Get("/web/cesium/ThirdParty/draco_decoder.wasm");
  ASSERT_TRUE(wasm);
  EXPECT_EQ(wasm->get_header_value("Content-Type"), "application/wasm");
}

TEST_F(ViewerRoutesTest, FilesAreSentAsTheyAreEvenWhenTheBrowserAcceptsCompression) {
  TestService service(Options(web_));
  auto client = service.Client();
  client->set_decompress(false);
  auto script = client->Get("/web/main.js", {{"Accept-Encoding", "gzip, deflate, br"}});
  ASSERT_TRUE(script);
  EXPECT_EQ(script->status, 200);
  EXPECT_EQ(script->get_header_value("Content-Encoding"), "");
  EXPECT_EQ(script->body, "export const x = 1;");
}

TEST_F(ViewerRoutesTest, AnUnchangedFileIsRevalidatedWith304) {
  TestService service(Options(web_));
  auto client = service.Client();
  auto first = client->Get("/web/main.js");
  ASSERT_TRUE(first);
  const std::string tag = first->get_header_value("ETag");
  ASSERT_FALSE(tag.empty());
  EXPECT_EQ(first->get_header_value("Cache-Control"), "no-cache");
  auto again = client->Get("/web/main.js", {{"If-None-Match", tag}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_TRUE(again->body.empty());
}

TEST_F(ViewerRoutesTest, NoRequestReadsOutsideTheWebRoot) {
  std::filesystem::create_symlink(dir_.Path("secret.txt"), web_ + "/link.txt");
  TestService service(Options(web_));
  auto client = service.Client();
  for (const char* path :
       {"/web/../secret.txt", "/web/%2e%2e/secret.txt", "/web/cesium/..%2f..%2fsecret.txt",
        "/web/.hidden", "/web//main.js", "/web/main.js%00.png", "/web/cesium/%5c..%5csecret.txt"}) {
    SCOPED_TRACE(path);
    ExpectJsonError(client->Get(path), 400, "path segment");
  }
  ExpectJsonError(client->Get("/web/link.txt"), 404, "no file 'link.txt'");
  ExpectJsonError(client->Get("/web/missing.js"), 404, "no file 'missing.js'");
  // The API's own unknown paths are still the HTTP layer's 404, not a file lookup.
  ExpectJsonError(client->Get("/secret.txt"), 404, "no route for GET /secret.txt");
}

TEST_F(ViewerRoutesTest, AMissingViewerIsExplained) {
  {
    TestService service(Options(""));
    ExpectJsonError(service.Client()->Get("/"), 404, "without --web-root");
  }
  TestService service(Options(dir_.Path("unbuilt")));
  ExpectJsonError(service.Client()->Get("/"), 404, "scripts/build-web.sh");
}

}  // namespace
}  // namespace tinbase::testing
