-- wrk script of scripts/bench-serve.sh: terrain tiles drawn at random from a list, as a CesiumJS
-- client asks for them (Accept with the extensions, gzip), for as long as wrk runs.
--   wrk -t N -c N -d S -s bench/serve_tiles_warm.lua http://127.0.0.1:PORT -- TILE_LIST [identity]
-- With "identity" the requests do not accept gzip.
-- TILE_LIST: one request path a line (/surfaces/S/tiles/Z/X/Y.terrain...).
-- Prints one line: "wrk,requests,seconds,bytes,p50_ms,p99_ms,max_ms,non_2xx,socket_errors".

local thread_count = 0

function setup(thread)
  thread_count = thread_count + 1
  thread:set("thread_number", thread_count)
end

function init(args)
  paths = {}
  for line in io.lines(args[1]) do paths[#paths + 1] = line end
  math.randomseed(7919 * thread_number)
  wrk.headers["Accept"] = "application/vnd.quantized-mesh;extensions=octvertexnormals-metadata," ..
    "application/octet-stream;q=0.9"
  if args[2] ~= "identity" then wrk.headers["Accept-Encoding"] = "gzip" end
end

function request()
  return wrk.format(nil, paths[math.random(#paths)])
end

function done(summary, latency, requests)
  local e = summary.errors
  io.write(string.format("wrk,%d,%.3f,%d,%.3f,%.3f,%.3f,%d,%d\n", summary.requests,
    summary.duration / 1e6, summary.bytes, latency:percentile(50) / 1e3,
    latency:percentile(99) / 1e3, latency.max / 1e3, e.status,
    e.connect + e.read + e.write + e.timeout))
end
