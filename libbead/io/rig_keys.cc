#include "libbead/io/rig_keys.h"

#include <algorithm>
#include <cctype>
#include <map>

#include "libbead/core/error.h"
#include "libbead/io/yaml_text.h"

namespace bead {
namespace {

// The keys docs/data-formats.md lists, per mapping ("" is the top level).
const std::map<std::string, std::vector<std::string>>& ListedKeys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"", {"name", "encoder", "wheel", "offset", "sensor", "part", "units"}},
      {"encoder", {"counts_per_rev", "bits", "direction"}},
      {"wheel", {"diameter_mm", "eccentricity_mm", "eccentricity_phase_deg"}},
      {"offset", {"counts"}},
      {"sensor", {"reference_areas_mm", "laser_origin_mm"}},
      {"part", {"bed", "bed_radius_mm"}},
  };
  return keys;
}

bool IsMillimetres(const std::string& v) {
  std::string s = v;
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s == "mm" || s == "millimetre" || s == "millimetres" || s == "millimeter" || s == "millimeters";
}

void CheckUnits(const YAML::Node& value, const std::string& key, const std::string& file) {
  if (value.IsScalar() && IsMillimetres(value.Scalar())) return;
  const std::string got = value.IsScalar() ? "'" + value.Scalar() + "'" : "not a word";
  throw Error(Located(file, YamlPlace(value, key),
                      "is " + got +
                          ", but every length in a rig file is in millimetres (keys end in _mm): convert "
                          "the values and set 'units: mm' or remove the key"));
}

void WarnIn(const YAML::Node& map, const std::string& section, const std::string& file,
            std::vector<std::string>& warnings) {
  const auto listed = ListedKeys().find(section);
  if (listed == ListedKeys().end() || !map.IsMap()) return;
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) continue;
    const std::string key = kv.first.Scalar();
    const std::string full = section.empty() ? key : section + "." + key;
    if (key == "units") CheckUnits(kv.second, full, file);
    const std::vector<std::string>& known = listed->second;
    if (std::find(known.begin(), known.end(), key) != known.end()) {
      if (section.empty()) WarnIn(kv.second, key, file, warnings);
      continue;
    }
    for (const std::string& k : known)
      if (EditDistance(key, k) == 1) {
        const std::string meant = section.empty() ? k : section + "." + k;
        warnings.push_back(Located(file, YamlPlace(kv.first, full),
                                   "not a key of the rig file (kept, and ignored); did you mean '" + meant + "'?"));
        break;
      }
  }
}

}  // namespace

std::size_t EditDistance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::vector<std::string> RigKeyWarnings(const YAML::Node& root, const std::string& file) {
  std::vector<std::string> warnings;
  WarnIn(root, "", file, warnings);
  return warnings;
}

}  // namespace bead
