#include "distributed/fingerprint.h"

#include <algorithm>

#include <fmt/core.h>

namespace multiray {

std::string fingerprint_difference(const PixelFingerprint& master,
                                   const PixelFingerprint& worker) {
  const size_t n = std::min(master.size(), worker.size());
  for (size_t i = 0; i < n; ++i) {
    const FingerprintPart &a = master[i], &b = worker[i];
    if (a.what != b.what) return fmt::format("{} here, {} there", a.what, b.what);
    if (a.hash != b.hash)
      return fmt::format("{} differs (content hash {:016x} here, {:016x} there)", a.what, a.hash,
                         b.hash);
  }
  if (master.size() > n) return master[n].what + " here, nothing more there";
  if (worker.size() > n) return worker[n].what + " there, nothing more here";
  return "";
}

}  // namespace multiray
