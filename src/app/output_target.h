// Where `render` writes its images and stats, from -o/--out: a folder, or a file pattern.
//
//  -o out            a folder: out/frame_0000.png, out/frame_0001.png, ..., out/stats.json
//  -o render.png     one file (one frame): render.png, and render.stats.json beside it
//  -o shot_####.png  a pattern, as Blender and pbrt users write it: the run of '#' is the
//                    frame number, zero-padded to its length (shot_0000.png ...), and the
//                    stats go to shot.stats.json
//  -o shot_##.exr    the same with linear OpenEXR files only (no PNG)
// Several views add _viewNN before the extension and a quilt (_quilt); a shadow catcher's
// RGBA layer adds _rgba (docs/ar.md); --overlay's picture of the split adds _split; --aov's
// multi-layer EXR beside a PNG adds _aov. A name ends in
// an image extension (.png, .exr, any case) exactly when it is a file pattern; anything else is a
// folder.
#pragma once

#include <string>

namespace multiray::app {

struct OutputTarget {
  std::string dir;       // the folder written into (created, locked and checked)
  std::string prefix;    // file name before the frame number
  int digits = 4;        // the frame number's minimum width; 0: no number (one frame)
  std::string suffix;    // file name between the frame number and the extension
  bool png = true;       // write PNG files (display colours)
  bool exr = false;      // write OpenEXR files (linear radiance)
  std::string stats;     // the stats file's name in `dir`
  bool pattern = false;  // a file pattern (false: a folder of frame_NNNN files)

  // The path of frame `frame`'s image without its extension; `tag` is "", "_viewNN",
  // "_quilt", "_rgba", or any of them followed by "_split" or "_aov".
  std::string image_base(int frame, const std::string& tag = "") const;
  std::string stats_path() const { return dir + "/" + stats; }
  // Whether `name`, a file name in `dir`, is one this target writes (for any frame), i.e.
  // an earlier run's output that a new run would replace.
  bool owns(const std::string& name) const;
};

// Reads -o/--out. `exr_flag` is --exr (PNG and EXR). Throws InputError for a pattern
// that cannot name every frame (one file, several frames; two runs of '#') or whose
// extension contradicts --exr.
OutputTarget parse_output_target(const std::string& out, int frames, bool exr_flag);

// The folder used when -o is not given: `base` if it holds no earlier run's outputs, else
// the first of base-2, base-3, ... that does not (so a second run never stops on the
// first's outputs, and never replaces them).
std::string first_free_folder(const std::string& base);

}  // namespace multiray::app
