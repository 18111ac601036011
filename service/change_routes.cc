// The change feed: GET /changes?since=TX, as server-sent events or as a long poll. Both read the
// store's `changes` table, so edits committed by other processes (the CLI) appear as well as
// this service's own; the notifier only wakes the waiting clients at once after an edit of this
// process, and the table is polled every kPollInterval for the others.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "db/change_log.h"
#include "service/change_json.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"

namespace tinbase::service {

namespace {

using Clock = std::chrono::steady_clock;

// How often a waiting client looks for changes of other processes.
constexpr std::chrono::milliseconds kPollInterval{500};
// An idle event stream sends a comment this often, so a client that went away is noticed (the
// write fails) and its thread freed, and proxies keep the connection open.
constexpr std::chrono::seconds kKeepAlive{15};
// At most this many changes per answer or batch of events; the client asks again from the last.
constexpr size_t kMaxBatch = 1000;

// Each waiting client of the feed holds one of the service's request threads for as long as it
// waits (cpp-httplib serves a connection on one thread); so at most half the threads wait for
// changes and the others stay free for readers and writers. A slot is taken per request and
// given back when the long poll answers or the event stream ends.
class FeedSlots {
 public:
  explicit FeedSlots(int threads) : limit_(std::max(1, threads / 2)) {}
  int limit() const { return limit_; }
  // A held slot of `slots` (given back when the last copy goes), or null when all are taken.
  static std::shared_ptr<void> Take(const std::shared_ptr<FeedSlots>& slots) {
    if (slots->taken_.fetch_add(1) >= slots->limit_) {
      slots->taken_.fetch_sub(1);
      return nullptr;
    }
    return {slots.get(), [slots](void*) { slots->taken_.fetch_sub(1); }};
  }

 private:
  const int limit_;
  std::atomic<int> taken_{0};
};

struct Batch {
  nlohmann::json changes = nlohmann::json::array();
  int64_t last = 0;  // the last transaction of `changes`, else the `since` asked for
};

// The newest transaction in the log below which none may still commit (0 when empty).
Result<int64_t> NewestChange(ServiceContext& context) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  return SettledLastTransaction(reader.store());
}

// The changes after `since` (at most kMaxBatch) up to the first number that may still commit
// (db/change_log.h SettledChangesSince), read through a fresh snapshot.
Result<Batch> ReadChanges(ServiceContext& context, ChangeJson& describe, int64_t since) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(std::vector<Change> changes, SettledChangesSince(reader.store(), since));
  Batch batch;
  batch.last = since;
  for (const Change& c : changes) {
    if (batch.changes.size() == kMaxBatch) break;
    TB_ASSIGN_OR_RETURN(nlohmann::json j, describe.Describe(reader.store(), c));
    batch.changes.push_back(std::move(j));
    batch.last = c.tx;
  }
  return batch;
}

Result<ChangeJson> Describer(ServiceContext& context) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  return ChangeJson::For(reader.store());
}

// `since=` when given; else the Last-Event-ID an EventSource sends when it reconnects; else the
// newest change, so the client hears of what comes next.
Result<int64_t> SinceOf(ServiceContext& context, const httplib::Request& req) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  if (OptionalParam(req, "since")) return IntegerParam(req, "since", 0, kMax);
  if (req.has_header("Last-Event-ID")) {
    httplib::Request as_param;
    as_param.params.emplace("Last-Event-ID", req.get_header_value("Last-Event-ID"));
    return IntegerParam(as_param, "Last-Event-ID", 0, kMax);
  }
  return NewestChange(context);
}

// Waits for a change after `since` until `deadline`, the service stopping, or kPollInterval;
// returns the newest change this service notified.
int64_t WaitForChange(ServiceContext& context, int64_t since, Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return context.changes().WaitBeyond(since, std::clamp(left, std::chrono::milliseconds(0),
                                                        std::chrono::milliseconds(kPollInterval)));
}

// The long poll: {"changes": [...], "last": TX} as soon as there is a change after `since`, or
// with no change after `wait=` seconds (default 25, at most 60).
void LongPoll(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto since = SinceOf(context, req);
  if (!since.ok()) return ReplyStatus(res, since.status());
  auto wait = IntegerParam(req, "wait", 0, 60, 25);
  if (!wait.ok()) return ReplyStatus(res, wait.status());
  auto describe = Describer(context);
  if (!describe.ok()) return ReplyStatus(res, describe.status());
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(*wait);
  int64_t waited = *since;
  while (true) {
    auto batch = ReadChanges(context, *describe, *since);
    if (!batch.ok()) return ReplyStatus(res, batch.status());
    if (!batch->changes.empty() || Clock::now() >= deadline || context.changes().shut_down()) {
      res.set_header("Cache-Control", "no-store");
      return ReplyJson(res, {{"changes", batch->changes}, {"last", batch->last}});
    }
    // A notification already seen must not make the next wait return at once again and again.
    waited = std::max(waited, WaitForChange(context, waited, deadline));
  }
}

// The state of one event stream between calls of its content provider.
struct Stream {
  std::shared_ptr<void> slot;
  ChangeJson describe;
  int64_t since = 0;
  bool started = false;
  Clock::time_point last_write = Clock::now();
};

bool WriteText(httplib::DataSink& sink, const std::string& text, Stream& stream) {
  stream.last_write = Clock::now();
  return sink.write(text.data(), text.size());
}

// One call of the stream's content provider: the changes after stream.since as events, or a
// wait of up to kPollInterval. False ends the stream (the client went away).
bool StreamStep(ServiceContext& context, Stream& stream, httplib::DataSink& sink) {
  if (context.changes().shut_down()) {
    sink.done();
    return true;
  }
  // The reconnection delay an EventSource should use; it also tells the client that the stream
  // is open before the first change.
  if (!stream.started && !WriteText(sink, "retry: 2000\n\n", stream)) return false;
  stream.started = true;
  auto batch = ReadChanges(context, stream.describe, stream.since);
  if (!batch.ok()) {
    nlohmann::json error = {{"status", HttpStatusFor(batch.status().code())},
                            {"message", batch.status().ToString()}};
    WriteText(sink, "event: error\ndata: " + error.dump() + "\n\n", stream);
    sink.done();
    return true;
  }
  for (const nlohmann::json& change : batch->changes) {
    const std::string event = "id: " + std::to_string(change["tx"].get<int64_t>()) +
                              "\nevent: change\ndata: " + change.dump() + "\n\n";
    if (!WriteText(sink, event, stream)) return false;
  }
  stream.since = batch->last;
  if (!batch->changes.empty()) return true;
  if (Clock::now() - stream.last_write >= kKeepAlive && !WriteText(sink, ": idle\n\n", stream))
    return false;
  context.changes().WaitBeyond(stream.since, kPollInterval);
  return true;
}

// Server-sent events: "id: TX", "event: change", "data: {change}" for every change after since,
// until the client goes away or the service stops.
void EventStream(ServiceContext& context, std::shared_ptr<void> slot, const httplib::Request& req,
                 httplib::Response& res) {
  auto since = SinceOf(context, req);
  if (!since.ok()) return ReplyStatus(res, since.status());
  auto describe = Describer(context);
  if (!describe.ok()) return ReplyStatus(res, describe.status());
  auto stream = std::make_shared<Stream>();
  stream->slot = std::move(slot);  // held until cpp-httplib drops the provider, stream and all
  stream->describe = std::move(*describe);
  stream->since = *since;
  res.set_header("Cache-Control", "no-store");
  res.set_chunked_content_provider("text/event-stream",
                                   [&context, stream](size_t /*offset*/, httplib::DataSink& sink) {
                                     return StreamStep(context, *stream, sink);
                                   });
}

bool WantsEvents(const httplib::Request& req) {
  return req.get_header_value("Accept").find("text/event-stream") != std::string::npos;
}

}  // namespace

void RegisterChangeRoutes(httplib::Server& server, ServiceContext& context) {
  auto slots = std::make_shared<FeedSlots>(context.options().threads);
  server.Get("/changes", [&context, slots](const httplib::Request& req, httplib::Response& res) {
    std::shared_ptr<void> slot = FeedSlots::Take(slots);
    if (!slot) {
      res.set_header("Retry-After", "5");
      return ReplyError(res, 503, "busy",
                        "the change feed already has " + std::to_string(slots->limit()) +
                            " waiting clients (half of --threads); try again later");
    }
    if (WantsEvents(req)) return EventStream(context, std::move(slot), req, res);
    LongPoll(context, req, res);
  });
}

}  // namespace tinbase::service
