// Bad input and hostile clients on the read side of the service, through a real socket: every
// malformed parameter or body is a JSON 400/404/413/415 naming the problem; path parameters
// cannot reach a file (they name rows, and "..", "/" or NUL in them name nothing); a client that
// stops sending is cut by the read timeout while others are served; 100 clients at once all get
// their answers. After each case the service keeps serving.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <thread>
#include <vector>

#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

class ServiceBadInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStore(store_);
    Start(service::ServiceOptions());
  }
  void Start(service::ServiceOptions options) {
    service_.reset();
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  // The service still answers a good request.
  void ExpectStillServing() {
    const nlohmann::json a =
        JsonAnswer(service_->Client()->Get("/surfaces/t/locate?x=360000&y=4862000"));
    EXPECT_TRUE(a.contains("triangle"));
  }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

struct BadRequest {
  const char* path;
  int status;
  const char* message;
};

TEST_F(ServiceBadInputTest, MalformedParametersAreJson400sNamingThem) {
  const BadRequest cases[] = {
      {"/surfaces/t/locate?x=abc&y=1", 400, "parameter 'x': 'abc' is not a number"},
      {"/surfaces/t/locate?x=1e999&y=1", 400, "parameter 'x': '1e999' is not a finite number"},
      {"/surfaces/t/locate?x=nan&y=1", 400, "parameter 'x': 'nan' is not a finite number"},
      {"/surfaces/t/locate?x=inf&y=1", 400, "parameter 'x': 'inf' is not a finite number"},
      {"/surfaces/t/locate?x=&y=1", 400, "parameter 'x': '' is empty"},
      {"/surfaces/t/locate?x=1", 400, "missing parameter 'y'"},
      {"/surfaces/t/locate?x=1%20&y=1", 400, "parameter 'x': '1 ' is not a number"},
      {"/surfaces/t/locate?lon=7&lat=43&x=1", 400, "not both"},
      {"/surfaces/t/locate?x=1&y=2&crs=EPSG:999999", 400,
       "parameter 'crs': 'EPSG:999999' is not a coordinate system"},
      {"/surfaces/t/locate?x=1&y=2&crs=%3Cscript%3E", 400, "parameter 'crs'"},
      {"/surfaces/t/triangles?bbox=NaN,0,1,1", 400, "parameter 'bbox'"},
      {"/surfaces/t/triangles?bbox=0,0,nan,nan", 400, "parameter 'bbox'"},
      {"/surfaces/t/triangles?bbox=0,0,inf,1", 400, "parameter 'bbox'"},
      {"/surfaces/t/triangles?bbox=1,2,3", 400, "parameter 'bbox'"},
      {"/surfaces/t/triangles?bbox=3,0,1,1", 400, "parameter 'bbox'"},
      {"/surfaces/t/triangles?bbox=0,0,1,1&limit=0", 400, "parameter 'limit': '0' is out of range"},
      {"/surfaces/t/triangles?bbox=0,0,1,1&limit=-3", 400, "parameter 'limit'"},
      {"/surfaces/t/triangles?bbox=0,0,1,1&limit=99999999999999999999", 400, "parameter 'limit'"},
      {"/surfaces/t/triangles?bbox=0,0,1,1&limit=12abc", 400, "is not a whole number"},
      {"/surfaces/t/triangles/-5", 400, "'-5' is out of range"},
      {"/surfaces/t/triangles/1e3", 400, "'1e3' is not a whole number"},
      {"/surfaces/t/triangles/0x10", 400, "is not a whole number"},
      {"/surfaces/t/measures/volume?level=1e400", 400, "parameter 'level'"},
      {"/surfaces/t/export?format=obj&feature=abc", 400, "parameter 'feature'"},
      {"/surfaces/t/profile?line=1,2,3,4,5", 400, "parameter 'line'"},
  };
  for (const BadRequest& c : cases) {
    SCOPED_TRACE(c.path);
    ExpectJsonError(service_->Client()->Get(c.path), c.status, c.message);
  }
  ExpectStillServing();
}

TEST_F(ServiceBadInputTest, PathParametersNeverReachAFile) {
  const BadRequest cases[] = {
      // Decoded to "/surfaces/../../../etc/passwd/locate": no route has that shape.
      {"/surfaces/..%2F..%2F..%2Fetc%2Fpasswd/locate?x=1&y=1", 404, "no route"},
      {"/surfaces/%2e%2e/locate?x=1&y=1", 404, "no surface named '..'"},
      {"/surfaces/..", 404, "no surface named '..'"},
      {"/surfaces/t%00evil/tags", 404, "no surface named 't"},
      {"/surfaces/%2Fetc%2Fpasswd", 404, "no route"},
      {"/surfaces/t/triangles/..%2F1", 404, "no route"},
      {"/surfaces/t/triangles/%2e%2e", 400, "is not a whole number"},
      {"/surfaces/'%20OR%201=1%20--/tags", 404, "no surface named ''"},
      {"/surfaces/%ff%fe/tags", 404, "no surface named"},
  };
  for (const BadRequest& c : cases) {
    SCOPED_TRACE(c.path);
    ExpectJsonError(service_->Client()->Get(c.path), c.status, c.message);
  }
  // A long name is just a name nobody has.
  ExpectJsonError(service_->Client()->Get("/surfaces/" + std::string(4000, 'a')), 404,
                  "no surface named");
  ExpectStillServing();
}

TEST_F(ServiceBadInputTest, BadLocateBodiesAreRefusedNamingThePlace) {
  struct BadBody {
    std::string body;
    const char* type;
    int status;
    const char* message;
  };
  const char* json = "application/json";
  const BadBody cases[] = {
      {R"({"points": [[1, 2]])", json, 400,
       "not JSON: [json.exception.parse_error.101] parse error at line 1, column 20"},
      {"", json, 400, "not JSON"},
      {R"({"points": [[1, 2]]})", "text/plain", 415, "application/json"},
      {R"({"points": [[1, 2]]})", "application/x-www-form-urlencoded", 415,
       "got 'application/x-www-form-urlencoded'"},
      {R"([1, 2])", json, 400, "\"points\": [[x, y], ...]"},
      {R"({"points": 3})", json, 400, "\"points\""},
      {R"({"points": [[1, 2], [3]]})", json, 400, "points[1] is not [x, y]"},
      {R"({"points": [[1, 2], [3, "4"]]})", json, 400, "points[1][1] is not a number"},
      {R"({"points": [[1e999, 2]]})", json, 400,
       "not JSON: [json.exception.out_of_range.406] number overflow parsing '1e999'"},
      {R"({"points": [[1, 2]], "crs": 4326})", json, 400, "\"crs\" is not a string"},
      {R"({"points": [[1, 2]], "crs": "nowhere"})", json, 400,
       "'nowhere' is not a coordinate system"},
      {"{\"points\": [[1, 2]], \"x\": \"\xff\xfe\"}", json, 400, "not JSON"},
      // Deep nesting is refused, not a crash.
      {R"({"points": )" + std::string(10000, '[') + std::string(10000, ']') + "}", json, 400, ""},
  };
  for (const BadBody& c : cases) {
    SCOPED_TRACE(c.body.substr(0, 60) + " as " + c.type);
    ExpectJsonError(service_->Client()->Post("/surfaces/t/locate", c.body, c.type), c.status,
                    c.message);
  }
  ExpectStillServing();
}

TEST_F(ServiceBadInputTest, ABodyOverTheLimitIsAJson413) {
  service::ServiceOptions options;
  options.max_body_bytes = 1000;
  Start(options);
  std::string body = R"({"points": [)";
  for (int i = 0; i < 200; ++i) body += (i ? "," : "") + std::string("[360000, 4862000]");
  body += "]}";
  ExpectJsonError(service_->Client()->Post("/surfaces/t/locate", body, "application/json"), 413,
                  "larger than the service accepts");
  ExpectStillServing();
}

// A connected socket to the service.
int Connect(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  // A bound on the test, far above the service's timeout: a recv that reaches it fails the test.
  timeval tv{30, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return fd;
}

// Reads until the service closes the connection: true when it did (recv 0 or a reset), false
// when the 30 s bound ran out first.
bool ClosedByService(int fd) {
  char buffer[4096];
  while (true) {
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n > 0) continue;  // whatever it said before closing
    if (n == 0) return true;
    return errno != EAGAIN && errno != EWOULDBLOCK;
  }
}

TEST_F(ServiceBadInputTest, ASlowClientIsCutByTheReadTimeoutWhileOthersAreServed) {
  service::ServiceOptions options;
  options.read_timeout_seconds = 1;
  options.threads = 2;
  Start(options);
  // One client sends half a request and stops; another connects and sends nothing.
  const int half = Connect(service_->port());
  const std::string start = "GET /surfaces HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  ASSERT_EQ(send(half, start.data(), start.size(), 0), static_cast<ssize_t>(start.size()));
  const int silent = Connect(service_->port());
  // They hold both request threads, until the timeout frees them: then this one is answered.
  ExpectStillServing();
  EXPECT_TRUE(ClosedByService(half));
  EXPECT_TRUE(ClosedByService(silent));
  close(half);
  close(silent);
  ExpectStillServing();
}

TEST_F(ServiceBadInputTest, AHundredConcurrentClientsAllGetTheirAnswers) {
  const nlohmann::json one =
      JsonAnswer(service_->Client()->Get("/surfaces/t/locate?x=360000&y=4862000"));
  const std::string body = R"({"points": [[360000, 4862000], [0, 0], [380000, 4850000]]})";
  const nlohmann::json many =
      JsonAnswer(service_->Client()->Post("/surfaces/t/locate", body, "application/json"));
  const std::string triangle =
      "/surfaces/t/triangles/" + std::to_string(one["triangle"]["id"].get<int64_t>());
  const nlohmann::json tri = JsonAnswer(service_->Client()->Get(triangle));
  std::atomic<int> good{0};
  std::vector<std::string> failures(100);
  std::vector<std::thread> clients;
  for (int c = 0; c < 100; ++c) {
    clients.emplace_back([&, c] {
      auto client = service_->Client();
      client->set_keep_alive(c % 2 == 0);  // half reuse one connection, half open one per request
      for (int round = 0; round < 3; ++round) {
        auto a = client->Get("/surfaces/t/locate?x=360000&y=4862000");
        auto b = client->Post("/surfaces/t/locate", body, "application/json");
        auto t = client->Get(triangle.c_str());
        for (const httplib::Result* r : {&a, &b, &t}) {
          if (!*r) {
            failures[c] = "no answer in round " + std::to_string(round) + ": " +
                          httplib::to_string(r->error());
            return;
          }
        }
        if (a->status != 200 || nlohmann::json::parse(a->body) != one || b->status != 200 ||
            nlohmann::json::parse(b->body) != many || t->status != 200 ||
            nlohmann::json::parse(t->body) != tri) {
          failures[c] = "wrong answer: " + a->body.substr(0, 200);
          return;
        }
      }
      ++good;
    });
  }
  for (std::thread& t : clients) t.join();
  EXPECT_EQ(good.load(), 100);
  for (int c = 0; c < 100; ++c) EXPECT_EQ(failures[c], "") << "client " << c;
  ExpectStillServing();
}

}  // namespace
}  // namespace tinbase::testing
