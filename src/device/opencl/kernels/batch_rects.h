// The list of rectangles one kernel launch renders (a "batch"), shared by the path tracer
// and the volume raycaster and declared once for both sides, as launch_params.h (whose
// rules hold here: language.h's dialect, explicit layout, no implicit padding). Embedded
// after launch_params.h in both programs; the host includes it from cl_runtime.h.
//
// Why batches: on drivers with a fixed cost per launch (PoCL: about 0.1 ms for the
// writes, the enqueue and the blocking read), a balancer that cuts a frame into
// thousands of small items pays that cost per item. One launch renders up to
// MR_BATCH_MAX rects of one view instead, their pixels packed one after the other:
// work-item i belongs to the rect k with ends[k - 1] <= i < ends[k] (ends[-1] = 0) and
// renders its pixel (rect.x + j % rect.z, rect.y + j / rect.z), j = i - ends[k - 1]. Its
// outputs and its entry of the samples-per-pixel map sit at index i. Every pixel is
// still a pure function of its coordinates and seeds, so batching changes no bit.
#ifndef MULTIRAY_DEVICE_OPENCL_KERNELS_BATCH_RECTS_H
#define MULTIRAY_DEVICE_OPENCL_KERNELS_BATCH_RECTS_H

#ifdef __cplusplus
#include <stddef.h>

#include "render/shared/language.h"
#endif

#ifdef __cplusplus
namespace multiray {
#endif

// Most rects one launch renders: a short search finds a work-item's rect.
#define MR_BATCH_MAX 64

// Byte offsets on the right.
typedef struct {
  mr_uint count;                //    0: rects in use, 1..MR_BATCH_MAX
  mr_uint pad[3];               //    4: unused
  mr_uint ends[MR_BATCH_MAX];   //   16: prefix sums of the rects' pixel counts
  mr_int4 rects[MR_BATCH_MAX];  // 272: x, y, width, height of each rect, in view pixels
} BatchRects;                   // 1296

#ifdef MR_OPENCL_C
typedef char mr_batch_rects_size_check[sizeof(BatchRects) == 1296 ? 1 : -1];

// The rect of work-item `i` (binary search over the prefix sums), and in *first the index
// of that rect's first pixel in the batch; -1 when i is past the batch's last pixel.
int batch_rect_of(const __global BatchRects* b, uint i, uint* first) {
  const uint n = b->count;
  if (n == 0 || i >= b->ends[n - 1]) return -1;
  uint lo = 0, hi = n - 1;  // the answer is in [lo, hi]
  while (lo < hi) {
    const uint mid = (lo + hi) / 2;
    if (i < b->ends[mid])
      hi = mid;
    else
      lo = mid + 1;
  }
  *first = lo == 0 ? 0u : b->ends[lo - 1];
  return (int)lo;
}
#endif

#ifdef __cplusplus
static_assert(sizeof(BatchRects) == 1296);
static_assert(offsetof(BatchRects, ends) == 16);
static_assert(offsetof(BatchRects, rects) == 272);
}  // namespace multiray
#endif

#endif  // MULTIRAY_DEVICE_OPENCL_KERNELS_BATCH_RECTS_H
