// Camera rigs for multiview rendering (Leria et al.): one view, a stereo pair, or a K x L
// light-field grid of parallel views. A rig turns the path's camera of a frame into the
// cameras of all its views, so every view follows the animation.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace multiray {

struct CameraRig {
  int columns = 1, rows = 1;  // views across (along the camera's right) and down (its up)
  float spacing = 0.2f;       // distance between neighbouring views, scene units

  static CameraRig single() { return {}; }
  // Two views `separation` apart, left eye first.
  static CameraRig stereo(float separation) { return {2, 1, separation}; }
  static CameraRig grid(int columns, int rows, float spacing) { return {columns, rows, spacing}; }

  int view_count() const { return columns * rows; }
  // The view at the grid's centre (the middle one of odd grids; of even grids the one right
  // of and below the centre): the reference of spatial reprojection.
  int centre_view() const { return (rows / 2) * columns + columns / 2; }
  // The views of the grid every `spacing` columns and rows from the centre view (the centre
  // included), row-major; spacing 0: the centre view alone. Reprojection's references.
  std::vector<int> reference_views(int spacing) const;
  // The views in row-major order (top row first, left to right), centred on `center`,
  // all looking in its direction (parallel, not converging).
  std::vector<Camera> views(const Camera& center) const;
};

}  // namespace multiray
