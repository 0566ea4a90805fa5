// "Did you mean ...?" for a mistyped name: the nearest of a list of candidates by edit
// distance, as the command line (options, commands) and the Python module (keywords) say
// it. Header-only.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace multiray {

// Levenshtein distance: insertions, deletions and substitutions.
inline size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The candidate nearest `name` within two edits (one edit, or fewer than half its length),
// or "" when none is that near.
template <typename Names>
std::string nearest_name(const std::string& name, const Names& candidates) {
  std::string best;
  size_t best_distance = 3;
  for (const std::string& candidate : candidates) {
    const size_t d = edit_distance(name, candidate);
    if (d < best_distance && (d <= 1 || 2 * d < name.size())) best = candidate, best_distance = d;
  }
  return best;
}

}  // namespace multiray
