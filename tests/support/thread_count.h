// Runs test code on a chosen number of TBB threads, to show that a result does not depend on it.
//
// tbb::global_control caps the threads of the whole process; a task_arena of that size lets the
// code use all of them even past the machine's cores (4 on a 2-core VM), so the work is really
// cut as it would be on a larger machine.
#pragma once

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <utility>

#include "core/tin/tin.h"

namespace tinbase::testing {

// The thread counts every such test runs with.
inline constexpr int kThreadCounts[] = {1, 2, 4};

// Returns fn() run on at most `threads` threads (the caller's among them).
template <typename Fn>
auto WithThreads(int threads, Fn&& fn) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<size_t>(threads));
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<Fn>(fn));
}

// Expects `got` to be `want` exactly: every vertex (x, y, z, kind), triangle (vertices,
// neighbours, visibility, tag), constraint and tag, in the same order.
inline void ExpectSameTin(const Tin& got, const Tin& want) {
  ASSERT_EQ(got.vertices.size(), want.vertices.size());
  ASSERT_EQ(got.triangles.size(), want.triangles.size());
  for (size_t i = 0; i < want.vertices.size(); ++i) {
    const TinVertex &a = got.vertices[i], &b = want.vertices[i];
    ASSERT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z && a.kind == b.kind) << "vertex " << i;
  }
  for (size_t i = 0; i < want.triangles.size(); ++i) {
    const TinTriangle &a = got.triangles[i], &b = want.triangles[i];
    ASSERT_TRUE(a.v == b.v && a.n == b.n && a.visible == b.visible && a.tag == b.tag)
        << "triangle " << i;
  }
  EXPECT_EQ(got.constraints, want.constraints);
  EXPECT_EQ(got.tags, want.tags);
}

}  // namespace tinbase::testing
