// Background work must not take the CPU from the per-image thread. On the 2-core machines memloop
// targets, the detector, the LTM writer and a background build of the forest compete for two
// cores; an iteration that waits for one overruns T_time (issue 9: single iterations of 67-101 ms
// with 15-80 ms in one step, the rest of the step at its usual few ms).
//
// A detector run at a real-time priority (memloop/realtime.h) passes it on to the threads it
// starts, since a new thread inherits its creator's policy: the per-image helpers keep it,
// background threads step below it (issue 37: under SCHED_FIFO a background build of the forest,
// at the helper's real-time priority, held the helper's core for 50 ms, and the image waited).
#pragma once

#include "memloop/realtime.h"

namespace memloop {

// How much nicer than the rest of the process background builds run (Linux nice levels: a
// thread at +10 gets about a tenth of the CPU of one at 0 when both want it).
constexpr int kBackgroundNiceness = 10;

// Lowers the calling thread's scheduling priority (Linux: that thread only), for background
// builds: under a real-time policy one step below it (StepBelowRealTimePriority), else by
// kBackgroundNiceness. Returns false where it cannot (not Linux, or refused); the work then runs
// as before.
bool LowerThisThreadsPriority();

// Under a real-time policy at priority p, puts the calling thread one step below: SCHED_FIFO at
// p - 1, or SCHED_OTHER at p = 1. The per-image threads then preempt it, other programs do not (a
// background build left to SCHED_OTHER among two busy programs hardly ran, the forest's unindexed
// part grew, and the images' searches with it: 18.7% of the images over T_time instead of 1.2%).
// Under SCHED_OTHER nothing changes. True when the thread now runs below real-time p.
bool StepBelowRealTimePriority();

// The calling thread's nice level (Linux; 0 elsewhere).
int ThisThreadsNiceness();

}  // namespace memloop
