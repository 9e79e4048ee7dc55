#include "util/thread_priority.h"

#include <cerrno>
#include <cstring>
#include <string>

#include "memloop/errors.h"

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace memloop {

#ifdef __linux__
namespace {
id_t ThisThreadsId() { return static_cast<id_t>(syscall(SYS_gettid)); }

bool UnderRealTimePolicy(int policy) { return policy == SCHED_FIFO || policy == SCHED_RR; }
}  // namespace

int ThisThreadsNiceness() {
  errno = 0;
  const int niceness = getpriority(PRIO_PROCESS, ThisThreadsId());
  return errno == 0 ? niceness : 0;
}

int ThisThreadsRealTimePriority() {
  int policy = SCHED_OTHER;
  sched_param param{};
  if (pthread_getschedparam(pthread_self(), &policy, &param) != 0) return 0;
  return UnderRealTimePolicy(policy) ? param.sched_priority : 0;
}

bool StepBelowRealTimePriority() {
  const int priority = ThisThreadsRealTimePriority();
  if (priority == 0) return true;
  // A lower real-time priority, or leaving the policy, is always allowed (sched(7)).
  sched_param param{};
  param.sched_priority = priority > 1 ? priority - 1 : 0;
  return pthread_setschedparam(pthread_self(), priority > 1 ? SCHED_FIFO : SCHED_OTHER, &param) ==
         0;
}

bool LowerThisThreadsPriority() {
  if (ThisThreadsRealTimePriority() > 1) return StepBelowRealTimePriority();
  // On Linux a nice level belongs to the thread (PRIO_PROCESS with a thread id); it counts only
  // under SCHED_OTHER.
  return StepBelowRealTimePriority() &&
         setpriority(PRIO_PROCESS, ThisThreadsId(), ThisThreadsNiceness() + kBackgroundNiceness) ==
             0;
}

void SetThisThreadsRealTimePriority(int priority) {
  const int lowest = sched_get_priority_min(SCHED_FIFO);
  const int highest = sched_get_priority_max(SCHED_FIFO);
  if (priority < lowest || priority > highest) {
    throw Error("real-time priority " + std::to_string(priority) + " is out of range (" +
                std::to_string(lowest) + "-" + std::to_string(highest) + ")");
  }
  sched_param param{};
  param.sched_priority = priority;
  const int failed = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (failed != 0) {
    throw Error("cannot run at real-time priority " + std::to_string(priority) +
                " (SCHED_FIFO): " + std::strerror(failed) +
                "; it takes root, CAP_SYS_NICE or `ulimit -r " + std::to_string(priority) + "`");
  }
}
#else
int ThisThreadsNiceness() { return 0; }
int ThisThreadsRealTimePriority() { return 0; }
bool StepBelowRealTimePriority() { return true; }
bool LowerThisThreadsPriority() { return false; }
void SetThisThreadsRealTimePriority(int priority) {
  throw Error("real-time priority " + std::to_string(priority) +
              ": not supported on this system (Linux only)");
}
#endif

}  // namespace memloop
