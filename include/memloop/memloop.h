// Everything a user of memloop needs.
#pragma once

#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/feature_extractor.h"
#include "memloop/image_sequence.h"
#include "memloop/options.h"
#include "memloop/params.h"
#include "memloop/place_sequence.h"
#include "memloop/result.h"
#include "memloop/synthetic_route.h"
#include "memloop/types.h"
