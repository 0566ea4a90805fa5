// Harada's two-level split (GPU Pro 7, ch. 4, Fig. 4.5): the frame is cut into horizontal
// bands, one per machine, and each machine cuts its band vertically across its own GPUs.
// Any balancer can run at either level (RegionBalancer, region.h); these pure functions
// give each level the paper's direction.
#pragma once

#include <string>

#include "balance/balancer.h"
#include "util/rect.h"

namespace multiray::balance {

// The spec a balancer runs with at the top level (the MPI master): `semi-static` without
// an explicit `split` cuts whole rows there (the machines' horizontal bands: one band a
// rank, not a band and partial rows); any other spec is returned unchanged. Throws
// std::invalid_argument for a malformed spec.
std::string top_level_spec(const std::string& spec);

// The direction the level above cut along, read from the part it handed down: a part as
// wide as the frame and less high is a row band, one as high and less wide a column band;
// anything else (a tile, the whole frame, an empty or oversized rect) is `none`.
CutAxis band_axis(const Rect& part, int frame_width, int frame_height);

// Whether the lower level's balancer, which natively cuts along `inner`, must plan its part
// transposed so that it cuts across the `outer` bands (or along them, with
// `same_direction`). No transposition when either level has no direction.
bool lower_level_transposed(CutAxis outer, CutAxis inner, bool same_direction);

}  // namespace multiray::balance
