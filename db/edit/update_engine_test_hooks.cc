#include "db/edit/update_engine_test_hooks.h"

#include <utility>

namespace tinbase {
namespace {

thread_local const UpdateEngineTestHooks* g_hooks = nullptr;

}  // namespace

ScopedUpdateEngineTestHooks::ScopedUpdateEngineTestHooks(UpdateEngineTestHooks hooks)
    : hooks_(std::move(hooks)), previous_(g_hooks) {
  g_hooks = &hooks_;
}

ScopedUpdateEngineTestHooks::~ScopedUpdateEngineTestHooks() { g_hooks = previous_; }

Status TEST_FaultStep(int step) {
  const UpdateEngineTestHooks* hooks = g_hooks;
  if (hooks == nullptr || !hooks->fault) return Status::Ok();
  g_hooks = nullptr;
  Status status = hooks->fault(step);
  g_hooks = hooks;
  return status;
}

bool TEST_VerifyMesh() { return g_hooks != nullptr && g_hooks->verify_mesh; }

void TEST_RegionLocked() {
  if (g_hooks != nullptr && g_hooks->region_locked) g_hooks->region_locked();
}

}  // namespace tinbase
