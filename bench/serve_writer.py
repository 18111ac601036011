#!/usr/bin/env python3
"""The writing client of scripts/bench-serve.sh: POSTs one small polygon feature (a 16-gon of
radius RADIUS m, mode fill, tag "bench") at a uniform random place of the box every PERIOD
seconds (start to start; at once when an insert took longer) for SECONDS, on one keep-alive
connection, and prints one line:
  writer,posts,created,other_status,p50_ms,max_ms,first_error
Usage: serve_writer.py PORT SURFACE MINX MINY MAXX MAXY SECONDS [PERIOD] [RADIUS]
"""
import http.client
import json
import math
import random
import sys
import time


def polygon(cx, cy, radius):
    angles = [2 * math.pi * k / 16 for k in range(16)]
    ring = [[cx + radius * math.cos(a), cy + radius * math.sin(a)] for a in angles]
    ring.append(ring[0])
    return {"type": "Feature", "properties": {"mode": "fill", "tag": "bench"},
            "geometry": {"type": "Polygon", "coordinates": [ring]}}


def main():
    port, surface = int(sys.argv[1]), sys.argv[2]
    minx, miny, maxx, maxy = map(float, sys.argv[3:7])
    seconds = float(sys.argv[7])
    period = float(sys.argv[8]) if len(sys.argv) > 8 else 0.1
    radius = float(sys.argv[9]) if len(sys.argv) > 9 else 3.0
    rng = random.Random(26)
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    headers = {"Content-Type": "application/geo+json"}
    latencies, created, other, first_error = [], 0, 0, ""
    start = time.monotonic()
    k = 0
    while time.monotonic() - start < seconds:
        due = start + k * period
        if due > time.monotonic():
            time.sleep(due - time.monotonic())
        k += 1
        cx = rng.uniform(minx + radius, maxx - radius)
        cy = rng.uniform(miny + radius, maxy - radius)
        body = json.dumps(polygon(cx, cy, radius))
        t0 = time.monotonic()
        conn.request("POST", f"/surfaces/{surface}/features", body, headers)
        answer = conn.getresponse()
        text = answer.read()
        latencies.append(time.monotonic() - t0)
        if answer.status == 201:
            created += 1
        else:
            other += 1
            if not first_error:
                first_error = f"{answer.status} {text[:200].decode(errors='replace')}"
    latencies.sort()
    p50 = latencies[len(latencies) // 2] * 1e3 if latencies else 0
    worst = latencies[-1] * 1e3 if latencies else 0
    print(f"writer,{len(latencies)},{created},{other},{p50:.1f},{worst:.1f},"
          f"{first_error.replace(',', ';').replace(chr(10), ' ')}")


if __name__ == "__main__":
    main()
