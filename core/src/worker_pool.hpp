#pragma once
// Worker threads kept from one frame to the next for the fast path's parallel
// phases (pixels, rays, the tree pass). Starting a thread costs tens of
// microseconds and a cold cache each time, and a frame has three such phases.
#include <functional>

namespace lom {

// Runs work(0) .. work(parts - 1) at once and returns when all are done:
// part 0 on the calling thread, the others on the shared workers (started on
// first use). If another caller is using the workers at that moment (two maps
// fused at once), the parts run on threads of their own instead. An exception
// thrown by a part is rethrown here once all parts are done.
void runParts(int parts, const std::function<void(int)>& work);

}  // namespace lom
