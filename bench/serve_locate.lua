-- wrk script of scripts/bench-serve.sh: GET /surfaces/SURFACE/locate?x=&y= at uniform random
-- points of the box MINX MINY MAXX MAXY (give one inside the surface: an outside point is a 404
-- and counts as an error). Each wrk thread draws its own sequence.
--   wrk -t N -c N -d S -s bench/serve_locate.lua http://127.0.0.1:PORT -- \
--     SURFACE MINX MINY MAXX MAXY
-- Prints one line: "wrk,requests,seconds,bytes,p50_ms,p99_ms,max_ms,non_2xx,socket_errors".

local thread_count = 0

function setup(thread)
  thread_count = thread_count + 1
  thread:set("thread_number", thread_count)
end

function init(args)
  surface = args[1]
  minx, miny = tonumber(args[2]), tonumber(args[3])
  maxx, maxy = tonumber(args[4]), tonumber(args[5])
  math.randomseed(7919 * thread_number)
end

function request()
  local x = minx + math.random() * (maxx - minx)
  local y = miny + math.random() * (maxy - miny)
  return wrk.format(nil, string.format("/surfaces/%s/locate?x=%.3f&y=%.3f", surface, x, y))
end

function done(summary, latency, requests)
  local e = summary.errors
  io.write(string.format("wrk,%d,%.3f,%d,%.3f,%.3f,%.3f,%d,%d\n", summary.requests,
    summary.duration / 1e6, summary.bytes, latency:percentile(50) / 1e3,
    latency:percentile(99) / 1e3, latency.max / 1e3, e.status,
    e.connect + e.read + e.write + e.timeout))
end
