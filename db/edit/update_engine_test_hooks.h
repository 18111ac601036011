// The test-only seam of the edit path, kept off the public option structs and the engine's API
// as LevelDB keeps its TEST_ methods off its public DB: tests install hooks for the edits their
// thread runs; the engine and the polygon editor ask for them at the points listed below. Nothing
// but tests installs hooks, and without them every TEST_ function is a no-op.
//
// Thread-safety: hooks are installed per thread (the edits a test runs on its own thread see
// them; other threads do not).
#pragma once

#include <functional>

#include "core/base/status.h"

namespace tinbase {

// Called with a step number; a non-OK Status aborts the edit with that Status.
using FaultHook = std::function<Status(int step)>;

struct UpdateEngineTestHooks {
  // Before each write step of an edit (1 to 7, db/edit/mesh_delta_writer.h), and with step 0
  // before each edit's transaction of the polygon editor begins (a test writes from another
  // connection there). The atomicity tests inject failures with it.
  FaultHook fault;
  // Each edit that begins from the mesh rows the one before kept (db/mesh_cache.h) first checks
  // them against the store (MeshCache::VerifyAgainstStore).
  bool verify_mesh = false;
  // Called once the edit holds its region's lock (db/edit/region_lock.h), before it writes: the
  // concurrent-writer tests see there which edits hold their locks at once.
  std::function<void()> region_locked = {};
};

// Installs `hooks` for the edits this thread runs while the object lives; the hooks installed
// before come back when it goes.
class ScopedUpdateEngineTestHooks {
 public:
  explicit ScopedUpdateEngineTestHooks(UpdateEngineTestHooks hooks);
  ~ScopedUpdateEngineTestHooks();
  ScopedUpdateEngineTestHooks(const ScopedUpdateEngineTestHooks&) = delete;
  ScopedUpdateEngineTestHooks& operator=(const ScopedUpdateEngineTestHooks&) = delete;

 private:
  UpdateEngineTestHooks hooks_;
  const UpdateEngineTestHooks* previous_;
};

// The fault hook's Status for `step` (Ok when none is installed). The hooks are uninstalled
// while it runs, so an edit the hook itself makes (another connection's) sees none.
Status TEST_FaultStep(int step);

// Whether the installed hooks ask for verify_mesh.
bool TEST_VerifyMesh();

// Runs the region_locked hook, if one is installed.
void TEST_RegionLocked();

}  // namespace tinbase
