// The change feed through a real socket: a long poll and server-sent events hear of this
// service's edits and of edits made by the CLI in another process, resume from a transaction,
// and let the service stop while a client is still listening.
#include <gtest/gtest.h>

#include <future>
#include <string>

#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

constexpr double kLon = 7.25, kLat = 43.85;  // on land in N43E007

class ChangeRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStore(store_);
    service::ServiceOptions options;
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  int64_t Post(double lon) {
    const nlohmann::json a =
        JsonAnswer(PostGeoJson(*service_->Client(), "/surfaces/t/features?crs=EPSG:4326",
                               LonLatSquare(lon, kLat, 0.003, {{"mode", "fill"}})),
                   201);
    return a.is_object() && a.contains("tx") ? a["tx"].get<int64_t>() : -1;
  }
  // The events an event stream from `since` sends until one with transaction `until` came.
  std::string EventsUntil(const httplib::Headers& headers, const std::string& path, int64_t until) {
    std::string text;
    const std::string wanted = "id: " + std::to_string(until) + "\n";
    auto client = service_->Client();
    auto r = client->Get(path, headers, [&](const char* data, size_t size) {
      text.append(data, size);
      return text.find(wanted) == std::string::npos;  // false: cancel, we have it
    });
    EXPECT_EQ(r.error(), httplib::Error::Canceled) << text;
    return text;
  }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

TEST_F(ChangeRoutesTest, ALongPollFromZeroAnswersAtOnceWithTheBuild) {
  const nlohmann::json feed = JsonAnswer(service_->Client()->Get("/changes?since=0"));
  ASSERT_EQ(feed["changes"].size(), 1u) << feed.dump();
  const nlohmann::json& build = feed["changes"][0];
  EXPECT_EQ(build["tx"], 1);
  EXPECT_EQ(feed["last"], 1);
  EXPECT_EQ(build["action"], "build");
  EXPECT_EQ(build["surface"], "t");
  EXPECT_EQ(build["feature"], nullptr);
  EXPECT_GT(build["added"].get<int64_t>(), 1000);
  // N43E007 is the 1-degree cell from 7E 43N; the surface covers it to within a cell or two.
  const auto& lonlat = build["bbox_lonlat"];
  ASSERT_EQ(lonlat.size(), 4u) << build.dump();
  EXPECT_NEAR(lonlat[0].get<double>(), 7.0, 0.05);
  EXPECT_NEAR(lonlat[1].get<double>(), 43.0, 0.05);
  EXPECT_NEAR(lonlat[2].get<double>(), 8.0, 0.05);
  EXPECT_NEAR(lonlat[3].get<double>(), 44.0, 0.05);
}

TEST_F(ChangeRoutesTest, ALongPollWaitsForTheNextEditOfThisService) {
  auto poll = std::async(std::launch::async, [&] {
    return JsonAnswer(service_->Client()->Get("/changes?since=1&wait=60"));
  });
  const int64_t tx = Post(kLon);
  const nlohmann::json feed = poll.get();
  ASSERT_EQ(feed["changes"].size(), 1u) << feed.dump();
  EXPECT_EQ(feed["changes"][0]["tx"], tx);
  EXPECT_EQ(feed["changes"][0]["action"], "polygon add");
  EXPECT_EQ(feed["last"], tx);
  // Without since, a poll waits for what comes after the newest change; wait=0 answers at once.
  const nlohmann::json none = JsonAnswer(service_->Client()->Get("/changes?wait=0"));
  EXPECT_EQ(none["changes"], nlohmann::json::array());
  EXPECT_EQ(none["last"], tx);
}

TEST_F(ChangeRoutesTest, EditsOfTheCliInAnotherProcessAppear) {
  auto poll = std::async(std::launch::async, [&] {
    return JsonAnswer(service_->Client()->Get("/changes?since=1&wait=60"));
  });
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square) << LonLatSquare(kLon, kLat, 0.003).dump();
  const CliResult add =
      RunCli("polygon add " + Quote(store_) + " " + Quote(square) + " --surface t --mode erase");
  ASSERT_EQ(add.exit_code, 0) << add.err;
  const nlohmann::json feed = poll.get();
  ASSERT_EQ(feed["changes"].size(), 1u) << feed.dump();
  EXPECT_EQ(feed["changes"][0]["tx"], 2);
  EXPECT_EQ(feed["changes"][0]["feature"], 1);
}

TEST_F(ChangeRoutesTest, ServerSentEventsCarryEachChange) {
  auto events = std::async(std::launch::async, [&] {
    return EventsUntil({{"Accept", "text/event-stream"}}, "/changes?since=1", 3);
  });
  const int64_t first = Post(kLon);
  const int64_t second = Post(kLon + 0.01);
  ASSERT_EQ(second, 3);
  const std::string text = events.get();
  // Two events, in order, each "id", "event", "data" and a blank line.
  const size_t a = text.find("id: " + std::to_string(first) + "\nevent: change\ndata: {");
  const size_t b = text.find("id: " + std::to_string(second) + "\nevent: change\ndata: {");
  ASSERT_NE(a, std::string::npos) << text;
  ASSERT_NE(b, std::string::npos) << text;
  EXPECT_LT(a, b);
  const size_t data = text.find("data: ", a) + 6;
  const nlohmann::json change =
      nlohmann::json::parse(text.substr(data, text.find('\n', data) - data));
  EXPECT_EQ(change["tx"], first);
  EXPECT_EQ(change["action"], "polygon add");
  EXPECT_EQ(change["surface"], "t");
  EXPECT_EQ(text.find("id: 1\n"), std::string::npos) << "since=1 skips the build";
}

TEST_F(ChangeRoutesTest, AReconnectingEventSourceResumesAfterItsLastEventId) {
  Post(kLon);
  const std::string text =
      EventsUntil({{"Accept", "text/event-stream"}, {"Last-Event-ID", "0"}}, "/changes", 2);
  EXPECT_NE(text.find("id: 1\nevent: change\n"), std::string::npos) << text;
  EXPECT_NE(text.find("id: 2\nevent: change\n"), std::string::npos) << text;
}

TEST_F(ChangeRoutesTest, BadParametersAreJsonErrors) {
  ExpectJsonError(service_->Client()->Get("/changes?since=-1"), 400, "parameter 'since'");
  ExpectJsonError(service_->Client()->Get("/changes?since=abc"), 400, "parameter 'since'");
  ExpectJsonError(service_->Client()->Get("/changes?since=0&wait=61"), 400, "parameter 'wait'");
  ExpectJsonError(service_->Client()->Get(
                      "/changes", {{"Accept", "text/event-stream"}, {"Last-Event-ID", "x"}}),
                  400, "Last-Event-ID");
}

// Waiting feed clients may take only half the request threads, so readers are still served.
TEST_F(ChangeRoutesTest, FeedClientsLeaveThreadsForReaders) {
  service_.reset();
  service::ServiceOptions options;
  options.store_path = store_;
  options.threads = 2;  // one for the feed
  service_ = std::make_unique<TestService>(options);
  JsonAnswer(service_->Client()->Get("/changes?wait=0"));
  JsonAnswer(service_->Client()->Get("/changes?wait=0"));  // the first gave its slot back
  std::promise<void> opened;
  bool first = true;
  auto stream = std::async(std::launch::async, [&] {
    return service_->Client()->Get("/changes", {{"Accept", "text/event-stream"}},
                                   [&](const char*, size_t) {
                                     if (first) opened.set_value();
                                     first = false;
                                     return true;
                                   });
  });
  opened.get_future().wait();
  ExpectJsonError(service_->Client()->Get("/changes?wait=0"), 503,
                  "the change feed already has 1 waiting clients");
  JsonAnswer(service_->Client()->Get("/surfaces/t"));
  service_.reset();
  stream.get();
}

// Stopping the service ends the streams and polls still open, instead of waiting for them.
TEST_F(ChangeRoutesTest, StoppingTheServiceEndsOpenStreams) {
  std::promise<std::string> opened;  // the stream's first bytes
  auto stream = std::async(std::launch::async, [&] {
    bool first = true;
    auto client = service_->Client();
    return client->Get("/changes", {{"Accept", "text/event-stream"}},
                       [&](const char* data, size_t size) {
                         if (first) opened.set_value(std::string(data, size));
                         first = false;
                         return true;
                       });
  });
  const std::string text = opened.get_future().get();
  EXPECT_EQ(text.rfind("retry: ", 0), 0u) << text;
  service_.reset();  // must end the open stream rather than wait for it
  stream.get();
}

}  // namespace
}  // namespace tinbase::testing
