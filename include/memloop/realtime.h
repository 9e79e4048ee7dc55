// A detector that other programs cannot delay (issue 37). On a machine shared with other jobs,
// the per-image thread at the usual priority waits for the CPU for tens of milliseconds at times,
// whatever T_time: a real-time priority for it, as robots give their perception, keeps an image
// within T_time while others run. Call it on the thread that will call Detector::Process, before
// the Detector is made: the detector's per-image helpers inherit it, its background threads (LTM
// writer, forest builds) give it up.
#pragma once

namespace memloop {

// Puts the calling thread (and the threads it starts after) under SCHED_FIFO at `priority`
// (1-99). Throws Error naming the priority and the cause when it is out of range or the system
// refuses (it takes root, CAP_SYS_NICE or an `ulimit -r` of at least `priority`).
void SetThisThreadsRealTimePriority(int priority);

// The calling thread's real-time priority: 1-99 under SCHED_FIFO or SCHED_RR, 0 otherwise.
int ThisThreadsRealTimePriority();

}  // namespace memloop
