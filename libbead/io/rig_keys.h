// The rig file's keys checked against docs/data-formats.md: the format
// keeps keys it does not list, but a key one edit away from a listed one
// is most likely a typo that silently changes the answer (laser_orign_mm
// read as "no laser origin"), so it is named with the key meant. A `units`
// key that says anything but millimetres would change what every number
// means: it is refused, not ignored.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace bead {

// One warning per unknown key within one edit (insert, delete, replace or
// swap two neighbours) of a key the format lists in the same mapping, each
// "file:line N: key: ... did you mean 'known'?". Throws bead::Error naming
// the place of a `units` key whose value is not mm.
std::vector<std::string> RigKeyWarnings(const YAML::Node& root, const std::string& file);

// Optimal string alignment distance (Damerau-Levenshtein without
// repeated edits of a substring).
std::size_t EditDistance(const std::string& a, const std::string& b);

}  // namespace bead
