-- wrk script of scripts/bench-serve.sh: every tile of a list requested exactly once, right after
-- the server started (its connections' SQLite page caches empty), as CesiumJS asks for them.
-- Thread k of N (run wrk with as many connections as threads, so each thread's requests are in
-- order) takes lines k, k + N, ... and stops after the answer to its last one. wrk itself runs
-- for its whole -d, so the rate is timed here: from the first request sent to the last answer
-- (of those that came within -d: the line's count says how many).
--   wrk -t N -c N -d S -s bench/serve_tiles_cold.lua http://127.0.0.1:PORT -- TILE_LIST N
-- Prints one line: "wrk,requests,seconds,bytes,p50_ms,p99_ms,max_ms,non_2xx,socket_errors" (p50 and
-- p99 from wrk's histogram, which holds these requests only).

local ffi = require("ffi")
ffi.cdef [[
  typedef struct { long tv_sec; long tv_nsec; } bench_timespec;
  int clock_gettime(int clock, bench_timespec* tp);
]]
local clock_monotonic = 1
local ts = ffi.new("bench_timespec")
local function now()
  ffi.C.clock_gettime(clock_monotonic, ts)
  return tonumber(ts.tv_sec) + tonumber(ts.tv_nsec) * 1e-9
end

local threads = {}

function setup(thread)
  threads[#threads + 1] = thread
  thread:set("thread_number", #threads)
end

function init(args)
  local n = tonumber(args[2])
  paths = {}
  local i = 0
  for line in io.lines(args[1]) do
    if i % n == thread_number - 1 then paths[#paths + 1] = line end
    i = i + 1
  end
  next_path, answered, non_200, first_sent, last_answer = 1, 0, 0, 0, 0
  wrk.headers["Accept"] = "application/vnd.quantized-mesh;extensions=octvertexnormals-metadata," ..
    "application/octet-stream;q=0.9"
  wrk.headers["Accept-Encoding"] = "gzip"
end

function request()
  if first_sent == 0 then first_sent = now() end
  local path = paths[math.min(next_path, #paths)]
  next_path = next_path + 1
  return wrk.format(nil, path)
end

function response(status, headers, body)
  answered = answered + 1
  last_answer = now()
  if status ~= 200 then non_200 = non_200 + 1 end
  if answered >= #paths then wrk.thread:stop() end
end

function done(summary, latency, requests)
  local count, bad, t0, t1 = 0, 0, math.huge, 0
  for _, thread in ipairs(threads) do
    count = count + thread:get("answered")
    bad = bad + thread:get("non_200")
    t0 = math.min(t0, thread:get("first_sent"))
    t1 = math.max(t1, thread:get("last_answer"))
  end
  local e = summary.errors
  io.write(string.format("wrk,%d,%.3f,%d,%.3f,%.3f,%.3f,%d,%d\n", count, t1 - t0,
    summary.bytes,
    latency:percentile(50) / 1e3, latency:percentile(99) / 1e3, latency.max / 1e3, bad,
    e.connect + e.read + e.write + e.timeout))
end
