// The balancing library's names for the unit of work (util/rect.h): Rect, WorkItem and
// ItemReport, so that its users write balance::Rect.
#pragma once

#include "util/rect.h"

namespace multiray::balance {

using multiray::ItemReport;
using multiray::Rect;
using multiray::WorkItem;

}  // namespace multiray::balance
