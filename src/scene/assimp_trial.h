// Assimp's readers allocate what a file claims before checking it against the file: a
// Quick3D file with two bytes changed took 22 GB of a 23 GB machine (docs/reliability.md,
// F6), and most of assimp's 40-odd formats have no count to check first (OFF has:
// detail::check_off_counts). So a scene in one of its formats is read once in a child
// process whose address space is limited, and only a read that fits there is done again
// in this process. Cost: assimp's formats are parsed twice; our own loaders (glTF, OBJ,
// PLY, Mitsuba) are not affected.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace multiray::detail {

// How the trial read ended.
enum class TrialResult {
  fits,       // the read ended within the limit (read or refused by the parser): go on
  too_large,  // the parser ran out of the limited address space
  crashed,    // the child died of a signal (an abort or a fault inside the parser)
};

// Runs `read` in a forked child whose address space may grow by at most `limit_bytes`
// beyond its size at the fork. `read` returns normally for any outcome the caller will
// see again in-process, and throws std::bad_alloc (or lets the kernel kill it) when the
// limit is hit. `signal` receives the signal number for `crashed`.
TrialResult trial_read(uint64_t limit_bytes, const std::function<void()>& read,
                       int* signal = nullptr);

}  // namespace multiray::detail
