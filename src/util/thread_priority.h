// Background work must not take the CPU from the per-image thread. On the 2-core machines memloop
// targets, the detector, the LTM writer and a background build of the forest compete for two
// cores; an iteration that waits for one overruns T_time (issue 9: single iterations of 67-101 ms
// with 15-80 ms in one step, the rest of the step at its usual few ms).
#pragma once

namespace memloop {

// How much nicer than the rest of the process background builds run (Linux nice levels: a
// thread at +10 gets about a tenth of the CPU of one at 0 when both want it).
constexpr int kBackgroundNiceness = 10;

// Lowers the calling thread's scheduling priority by kBackgroundNiceness (Linux: that thread
// only). Returns false where it cannot (not Linux, or refused); the work then runs as before.
bool LowerThisThreadsPriority();

// The calling thread's nice level (Linux; 0 elsewhere).
int ThisThreadsNiceness();

}  // namespace memloop
