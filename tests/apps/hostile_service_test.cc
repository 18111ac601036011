// Issue 29, tried again (session 18): `tinbase serve` as a separate process, spoken to over a
// raw socket by a hostile but fair client: requests that are not HTTP, bodies that are not
// GeoJSON or hold absurd numbers, ids out of range, many edits at once, and a SIGKILL in the
// middle of edits. Every bad request is answered with a 4xx JSON error and changes nothing (a
// checksum of every table), the server keeps serving, and whatever it acknowledged is in a store
// that `check --full` passes. The cases are listed in docs/reliability.md ("Tried again").
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/serve_child.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::ServeChild;
using testing::TableChecksums;
using testing::TempDir;

struct Reply {
  int status = 0;  // 0: no answer (the connection closed or timed out first)
  std::string text;
};

// Sends `request` as it is (no framing added) and reads until the server closes.
Reply Exchange(int port, const std::string& request) {
  Reply reply;
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return reply;
  timeval timeout{30, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    size_t sent = 0;
    while (sent < request.size()) {
      const ssize_t n = ::send(fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<size_t>(n);
    }
    char buffer[4096];
    ssize_t n = 0;
    while ((n = ::recv(fd, buffer, sizeof buffer, 0)) > 0)
      reply.text.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  if (reply.text.rfind("HTTP/1.", 0) == 0 && reply.text.size() > 12)
    reply.status = std::atoi(reply.text.c_str() + 9);
  return reply;
}

std::string Request(const std::string& method, const std::string& target,
                    const std::string& body = "",
                    const std::string& content_type = "application/geo+json") {
  std::string r = method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n";
  if (!body.empty() || method != "GET")
    r += "Content-Type: " + content_type + "\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\n";
  return r + "\r\n" + body;
}

std::string Feature(const std::string& geometry, const std::string& properties = "{}") {
  return R"({"type":"Feature","properties":)" + properties + R"(,"geometry":)" + geometry + "}";
}

// A square of side `side` centred at (x, y) of the Hamersley DEM's middle, as GeoJSON.
std::string Square(double x, double y, double side) {
  const std::string x0 = std::to_string(x - side / 2), x1 = std::to_string(x + side / 2);
  const std::string y0 = std::to_string(y - side / 2), y1 = std::to_string(y + side / 2);
  return R"({"type":"Polygon","coordinates":[[[)" + x0 + "," + y0 + "],[" + x1 + "," + y0 + "],[" +
         x1 + "," + y1 + "],[" + x0 + "," + y1 + "],[" + x0 + "," + y0 + "]]]}";
}

constexpr double kCx = 539300, kCy = 7497340;

class HostileServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = dir_.Path("s.tinbase");
    RunWrite(store_, "init " + Quote(store_) + " --crs EPSG:28350");
    RunWrite(store_,
             "dem import " + Quote(store_) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 20");
  }
  void ExpectClean() {
    const testing::CliResult check = RunCli("check --full " + Quote(store_));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  }
  TempDir dir_;
  std::string store_;
};

struct BadRequest {
  std::string request;
  int status;
  std::string message;  // in the answer's text
};

TEST_F(HostileServiceTest, BadRequestsAreRefusedAndChangeNothing) {
  const auto before = TableChecksums(store_);
  ServeChild serve(store_);
  const std::string features = "/surfaces/terrain/features";
  const std::string fill = features + "?mode=fill";
  const std::string square = Feature(Square(kCx, kCy, 1000));
  std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const std::vector<BadRequest> cases = {
      // Not HTTP, or HTTP that lies about itself.
      {"GARBAGE\r\n\r\n", 400, ""},
      {"GET / HTTP/9.9\r\n\r\n", 0, ""},
      {"GET /surfaces HTTP/1.1\r\nHost: x\r\nX-Long: " + std::string(100000, 'a') +
           "\r\nConnection: close\r\n\r\n",
       0, ""},
      {"POST " + fill +
           " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
           "Content-Length: -1\r\nConnection: close\r\n\r\n",
       413, "too_large"},
      {"POST " + fill +
           " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
           "Transfer-Encoding: chunked\r\nConnection: close\r\n\r\nzz\r\n{}\r\n0\r\n\r\n",
       400, ""},
      {"POST " + fill +
           " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
           "Content-Length: 1000\r\nConnection: close\r\n\r\n{\"type\":",
       0, ""},
      // Bodies that are not GeoJSON.
      {Request("POST", fill, ""), 400, "malformed JSON"},
      {Request("POST", fill, "[]"), 400, ""},
      {Request("POST", fill, "null"), 400, ""},
      {Request("POST", fill, deep), 400, ""},
      {Request("POST", fill, "{\"type\":\"Feature\",\"x\":\"\xff\xfe\"}"), 400, "malformed JSON"},
      {Request("POST", fill, square, "text/plain"), 415, "unsupported_media_type"},
      {Request("POST", fill, square.substr(0, 40)), 400, "malformed JSON"},
      // GeoJSON with what no surface can take.
      {Request("POST", fill,
               Feature(R"({"type":"Polygon","coordinates":[[[539000,7497000],[1e300,7497000],)"
                       R"([540000,7498000],[539000,7497000]]]})")),
       400, "1e+300"},
      {Request("POST", fill,
               Feature(R"({"type":"Polygon","coordinates":[[[539000,7497000],["7.3",7497000],)"
                       R"([540000,7498000],[539000,7497000]]]})")),
       400, "is not a finite number"},
      {Request("POST", fill,
               Feature(R"({"type":"Polygon","coordinates":[[[539000,7497000],[540000,7498000],)"
                       R"([540000,7497000],[539000,7498000],[539000,7497000]]]})")),
       400, "ring crosses itself"},
      {Request("POST", fill, Feature(R"({"type":"Point","coordinates":[539000,7497000]})")), 400,
       "geometry is a Point"},
      {Request("POST", fill, Feature(Square(0, 0, 10))), 400, "outside"},
      {Request("POST", features + "?mode=bogus", square), 400, "bogus"},
      {Request("POST", features + "?mode=replace&level=1e100", square), 400, "level"},
      {Request("POST", features + "?mode=replace&level=1e12", square), 400, "relief"},
      {Request("POST", fill + "&crs=EPSG:999999", square), 400, "crs"},
      {Request("POST", fill + "&crs=EPSG:4978", square), 400, ""},
      {Request("POST", fill, Feature(Square(kCx, kCy, 1000), "{\"mode\":7}")), 400, "mode"},
      {Request("POST", "/surfaces/nosuch/features?mode=fill", square), 404, "nosuch"},
      // Ids that are no feature.
      {Request("DELETE", features + "/abc"), 400, "is not a whole number"},
      {Request("DELETE", features + "/99999999999999999999"), 400, "out of range"},
      {Request("DELETE", features + "/-1"), 400, "out of range"},
      {Request("DELETE", features + "/12345"), 404, "12345"},
      {Request("PUT", features + "/12345", square), 404, "12345"},
      {Request("PUT", features + "/1e3", square), 400, "is not a whole number"},
  };
  for (const BadRequest& c : cases) {
    SCOPED_TRACE(c.request.substr(0, 120));
    const Reply reply = Exchange(serve.port(), c.request);
    if (c.status != 0) {
      EXPECT_EQ(reply.status, c.status) << reply.text.substr(0, 400);
    } else {
      EXPECT_TRUE(reply.status == 0 || (reply.status >= 400 && reply.status < 500))
          << reply.text.substr(0, 400);
    }
    EXPECT_NE(reply.text.find(c.message), std::string::npos) << reply.text.substr(0, 400);
    // Still serving, after each.
    EXPECT_EQ(Exchange(serve.port(), Request("GET", "/surfaces")).status, 200);
  }
  serve.Stop();
  EXPECT_EQ(TableChecksums(store_), before);
}

// Sixteen clients post overlapping squares at once: the service's edits take turns, each lands
// (201) and the store checks clean with every acknowledged feature in it.
TEST_F(HostileServiceTest, ManyEditsAtOnceAllLand) {
  ServeChild serve(store_);
  std::atomic<int> created{0};
  std::vector<std::thread> clients;
  for (int k = 0; k < 16; ++k)
    clients.emplace_back([&, k] {
      const int column = k % 4, row = k / 4;
      const std::string body = Feature(Square(kCx + column * 600.0, kCy + row * 600.0, 900));
      const Reply r =
          Exchange(serve.port(), Request("POST", "/surfaces/terrain/features?mode=fill", body));
      if (r.status == 201) ++created;
    });
  for (std::thread& t : clients) t.join();
  serve.Stop();
  EXPECT_EQ(created.load(), 16);
  ExpectClean();
  auto db = Connection::Open(store_, Connection::Mode::kReadOnly);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(*) FROM features"), 16);
}

// The server killed with SIGKILL while clients post: every acknowledged feature is there, no
// feature is there that the log does not have, and the store checks clean.
TEST_F(HostileServiceTest, KilledWhileEditingLeavesWholeEdits) {
  int64_t acknowledged = 0;
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE(round);
    ServeChild serve(store_);
    std::atomic<int> created{0};
    std::atomic<bool> stop{false};
    std::vector<std::thread> clients;
    for (int k = 0; k < 4; ++k)
      clients.emplace_back([&, k] {
        for (int i = 0; !stop; ++i) {
          const double x = kCx + ((k * 7 + i * 3 + round) % 12 - 6) * 500.0;
          const std::string body = Feature(Square(x, kCy + (k - 2) * 700.0, 800));
          const Reply r =
              Exchange(serve.port(), Request("POST", "/surfaces/terrain/features?mode=fill", body));
          if (r.status == 201) ++created;
        }
      });
    std::this_thread::sleep_for(std::chrono::milliseconds(400 + 300 * round));
    serve.Kill();
    stop = true;
    for (std::thread& t : clients) t.join();
    ExpectClean();
    auto db = Connection::Open(store_, Connection::Mode::kReadOnly);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    const int64_t features = *(*db)->QueryInt("SELECT count(*) FROM features");
    const int64_t logged = *(*db)->QueryInt("SELECT count(*) FROM changes WHERE action <> 'build'");
    EXPECT_EQ(features, logged);
    acknowledged += created.load();
    // A commit whose answer the kill cut off is there without an acknowledgement.
    EXPECT_GE(features, acknowledged);
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace tinbase
