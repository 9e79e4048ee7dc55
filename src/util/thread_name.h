// Names memloop's threads as `top -H`, `perf` and /proc/<pid>/task/*/comm show them, so that a
// profile says which of them took the time (the LTM writer, the search helper, a forest build).
#pragma once

namespace memloop {

// Names the calling thread "memloop-" + `role` (Linux keeps the first 15 characters: roles of up
// to 7 stay whole). Does nothing where threads cannot be named.
void NameThisThread(const char* role);

}  // namespace memloop
