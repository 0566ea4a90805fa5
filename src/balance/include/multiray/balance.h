// The installed entry point of multiray::balance: `#include <multiray/balance.h>` after
// find_package(multiray) gives the whole balancing library (balance/balance.h) and its
// registry. Only installed: in the source tree, include "balance/balance.h".
#pragma once

#include "balance/balance.h"
