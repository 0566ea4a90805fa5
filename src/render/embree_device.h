// One place where multiray creates its Embree devices, so that every one of them takes
// the same configuration.
#pragma once

#include <embree3/rtcore.h>

namespace multiray {

// A new Embree device (nullptr when Embree refuses). Its configuration string is Embree's
// default unless the environment variable MULTIRAY_EMBREE_CONFIG holds one, in Embree's
// own syntax (e.g. "isa=sse2" or "isa=avx2,verbose=1"): that forces the code path another
// machine's CPU would select, which is how docs/testing.md reproduces the last-bit
// differences between machines. Not a user option: a diagnostic for tests and bug reports.
RTCDevice new_embree_device();

}  // namespace multiray
