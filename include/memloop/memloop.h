// Everything a program needs to detect loop closures (CMake target memloop::memloop).
//
// The other parts have their own headers and targets:
//   memloop/evaluation.h, ground_truth.h, run_csv.h, report.h   memloop::eval
//   memloop/synthetic_route.h, place_sequence.h                 memloop::synthetic
#pragma once

#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/feature_extractor.h"
#include "memloop/image_sequence.h"
#include "memloop/loop_closure_edits.h"
#include "memloop/map_info.h"
#include "memloop/options.h"
#include "memloop/params.h"
#include "memloop/realtime.h"
#include "memloop/result.h"
#include "memloop/types.h"
