// multiray::balance: the whole public surface in one include. Link multiray::balance
// (find_package(multiray)); it needs nothing but the C++ standard library.
#pragma once

#include "balance/balancer.h"
#include "balance/dlb.h"
#include "balance/hybrid.h"
#include "balance/layout.h"
#include "balance/plan.h"
#include "balance/queue.h"
#include "balance/semi_static.h"
#include "balance/simulate.h"
#include "balance/static_ratios.h"
#include "balance/stats.h"
#include "balance/uniform.h"
#include "partition/apportion.h"
#include "partition/bands.h"
#include "partition/cdf_split.h"
#include "partition/coverage.h"
#include "partition/rect.h"
#include "partition/scanline.h"
#include "partition/shuffled_strips.h"
#include "partition/tiles.h"
#include "partition/weight_map.h"
