// Automatic exposure: metering on rendered radiance, as a camera's reflected-light meter
// does. A meter assumes the scene averages to middle grey; so the exposure is the one that
// maps the image's log-average luminance (its geometric mean: Reinhard et al., "Photographic
// Tone Reproduction for Digital Images", 2002, eq. 1) to the key 0.18. A log average is
// robust to the few very bright pixels (the sun's glint, a path tracer's fireflies) that
// would drag an arithmetic mean; the darkest and brightest few percent of zones are left out as
// well (a histogram meter's usual trimming), so a black background or a light source in view does
// not decide the exposure alone.
#pragma once

#include "core/image.h"

namespace multiray {

// The middle grey a metered image's log-average luminance is mapped to.
constexpr float kMeterKey = 0.18f;
// Metered exposures are kept within this many stops of 0: an image that is black (or
// nearly, before light has reached it) must not be amplified without bound.
constexpr float kMeterMaxStops = 10.0f;
// About this many metering zones (square blocks of pixels whose radiance is averaged
// before the log; see exposure.cpp).
constexpr int kMeterZones = 24 * 24;
// Zones whose mean luminance is at most this are black: not metered (see exposure.cpp).
constexpr float kMeterBlack = 1e-6f;
// The share of zones left out at each end of the luminance histogram.
constexpr float kMeterTrim = 0.02f;

// The exposure, in stops, that brings `fb`'s trimmed log-average luminance (Rec. 709
// weights on linear RGB) over its zones that are not black, to kMeterKey; 0 for an image
// with no such zone. Deterministic: it depends
// only on the pixels, so it does not depend on how the frame was split.
float metered_exposure_ev(const Framebuffer& fb);

}  // namespace multiray
