#include "libbead/vision/laser_plane_yaml.h"

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/yaml_text.h"

namespace bead::vision {

LaserPlaneMap ReadLaserPlaneYaml(const std::string& path) {
  const YAML::Node root = ParseYamlText(ReadTextFile(path, "laser plane file"), path);
  auto fail = [&](const YAML::Node& node, const std::string& what) {
    throw Error(Located(path, YamlPlace(node, "points"), what));
  };
  const YAML::Node points = root.IsMap() ? root["points"] : YAML::Node(YAML::NodeType::Undefined);
  if (!points.IsDefined() || !points.IsSequence())
    fail(root, "missing: a list of [u, v, x_mm, z_mm] pairs, four or more");
  std::vector<cv::Point2d> px, mm;
  for (const YAML::Node& p : points) {
    if (!p.IsSequence() || p.size() != 4) fail(p, "each entry must be [u, v, x_mm, z_mm]");
    double v[4];
    for (std::size_t i = 0; i < 4; ++i) {
      try {
        v[i] = p[i].as<double>();
      } catch (const YAML::Exception&) {
        fail(p, "each entry must be four numbers [u, v, x_mm, z_mm]");
      }
      if (!std::isfinite(v[i])) fail(p, "each entry must be four finite numbers");
    }
    px.push_back({v[0], v[1]});
    mm.push_back({v[2], v[3]});
  }
  try {
    return FitLaserPlaneMap(px, mm);
  } catch (const Error& e) {
    throw Error(Located(path, "points", e.what()));
  }
}

}  // namespace bead::vision
