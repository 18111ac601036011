// TinHash: a fingerprint of a Tin, FNV-1a over the bytes of every vertex's coordinates and every
// triangle's corners, in order. Two TINs with one hash are the same TIN bit for bit (barring a
// collision), so a test can pin a builder's output and a benchmark can show that a change to a
// builder kept it (bench/dense_bench.cc, tests/core/tin/greedy_dense_test.cc). Not for storage:
// the bytes hashed are the machine's doubles. Thread-safety: pure.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/tin/tin.h"

namespace tinbase {

inline uint64_t TinHash(const Tin& tin) {
  uint64_t h = 1469598103934665603ULL;
  const auto add = [&h](const void* data, size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 1099511628211ULL;
  };
  for (const TinVertex& v : tin.vertices) {
    add(&v.x, sizeof v.x);
    add(&v.y, sizeof v.y);
    add(&v.z, sizeof v.z);
  }
  for (const TinTriangle& t : tin.triangles) add(t.v.data(), sizeof(uint32_t) * 3);
  return h;
}

}  // namespace tinbase
