#include "util/thread_priority.h"

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#endif

namespace memloop {

#ifdef __linux__
namespace {
id_t ThisThreadsId() { return static_cast<id_t>(syscall(SYS_gettid)); }
}  // namespace

int ThisThreadsNiceness() {
  errno = 0;
  const int niceness = getpriority(PRIO_PROCESS, ThisThreadsId());
  return errno == 0 ? niceness : 0;
}

bool LowerThisThreadsPriority() {
  // On Linux a nice level belongs to the thread (PRIO_PROCESS with a thread id).
  return setpriority(PRIO_PROCESS, ThisThreadsId(), ThisThreadsNiceness() + kBackgroundNiceness) ==
         0;
}
#else
int ThisThreadsNiceness() { return 0; }
bool LowerThisThreadsPriority() { return false; }
#endif

}  // namespace memloop
