#include "libbead/vision/sensor_yaml.h"

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/yaml_text.h"

namespace bead::vision {
namespace {

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    throw Error(Located(path_, YamlPlace(node, key), what));
  }

  YAML::Node Need(const YAML::Node& parent, const char* name, const std::string& key) const {
    const YAML::Node n = parent.IsMap() ? parent[name] : YAML::Node(YAML::NodeType::Undefined);
    if (!n.IsDefined()) Fail(parent, key, "missing");
    return n;
  }

  double Number(const YAML::Node& n, const std::string& key) const {
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      Fail(n, key, "expected a number");
    }
    if (!std::isfinite(v)) Fail(n, key, "expected a finite number");
    return v;
  }

  std::vector<double> Numbers(const YAML::Node& n, std::size_t count, const std::string& key) const {
    if (!n.IsSequence() || n.size() != count) Fail(n, key, "expected a list of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(Number(n[i], key));
    return out;
  }

  cv::Matx33d Matrix(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 3) Fail(n, key, "expected a 3 x 3 matrix: three rows of three numbers");
    cv::Matx33d m;
    for (int r = 0; r < 3; ++r) {
      const std::vector<double> row = Numbers(n[static_cast<std::size_t>(r)], 3, key);
      for (int c = 0; c < 3; ++c) m(r, c) = row[static_cast<std::size_t>(c)];
    }
    return m;
  }

 private:
  std::string path_;
};

YAML::Node Flow(std::initializer_list<double> values) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (double v : values) n.push_back(v);
  return n;
}

YAML::Node Rows(const cv::Matx33d& m) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int r = 0; r < 3; ++r) n.push_back(Flow({m(r, 0), m(r, 1), m(r, 2)}));
  return n;
}

}  // namespace

SensorModel ReadSensorYaml(const std::string& path) {
  const YAML::Node root = ParseYamlText(ReadTextFile(path, "sensor file"), path);
  const Reader r(path);
  if (!root.IsMap()) r.Fail(root, "camera", "expected a mapping with camera, laser and stripe");
  SensorModel s;
  const YAML::Node camera = r.Need(root, "camera", "camera");
  s.camera.matrix = r.Matrix(r.Need(camera, "matrix", "camera.matrix"), "camera.matrix");
  const cv::Matx33d& k = s.camera.matrix;
  if (!(k(0, 0) > 0 && k(1, 1) > 0) || k(1, 0) != 0 || k(2, 0) != 0 || k(2, 1) != 0 || k(2, 2) != 1)
    r.Fail(camera["matrix"], "camera.matrix", "expected [[fx, 0 or skew, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0");
  const std::vector<double> d = r.Numbers(r.Need(camera, "distortion", "camera.distortion"), 5, "camera.distortion");
  std::copy(d.begin(), d.end(), s.camera.distortion.begin());
  const YAML::Node size_node = r.Need(camera, "image_size", "camera.image_size");
  const std::vector<double> size = r.Numbers(size_node, 2, "camera.image_size");
  if (!(size[0] >= 1 && size[1] >= 1 && size[0] <= 1e6 && size[1] <= 1e6) || size[0] != std::floor(size[0]) ||
      size[1] != std::floor(size[1]))
    r.Fail(size_node, "camera.image_size", "expected [width, height], whole pixels");
  s.camera.image_size = cv::Size(static_cast<int>(size[0]), static_cast<int>(size[1]));

  const YAML::Node laser = r.Need(root, "laser", "laser");
  const YAML::Node plane_node = r.Need(laser, "plane", "laser.plane");
  const std::vector<double> plane = r.Numbers(plane_node, 4, "laser.plane");
  const double norm = std::sqrt(plane[0] * plane[0] + plane[1] * plane[1] + plane[2] * plane[2]);
  if (!(std::abs(norm - 1.0) < 1e-6))
    r.Fail(plane_node, "laser.plane", "expected [a, b, c, d] with (a, b, c) a unit vector");
  s.plane = cv::Vec4d(plane[0], plane[1], plane[2], plane[3]);
  const YAML::Node h = r.Need(laser, "homography", "laser.homography");
  s.map.mm_from_px = r.Matrix(h, "laser.homography");
  if (!(std::abs(cv::determinant(s.map.mm_from_px)) > 0.0))
    r.Fail(h, "laser.homography", "singular: maps the image onto a line");

  const YAML::Node stripe = root["stripe"];
  if (stripe.IsDefined()) {
    if (!stripe.IsMap()) r.Fail(stripe, "stripe", "expected a mapping (axis, method, threshold, ...)");
    auto text = [&](const char* key, auto parse, auto& field) {
      const YAML::Node n = stripe[key];
      if (!n.IsDefined()) return;
      try {
        field = parse(n.as<std::string>());
      } catch (const std::exception& e) {
        r.Fail(n, std::string("stripe.") + key, e.what());
      }
    };
    text("axis", ParseStripeAxis, s.stripe.axis);
    text("method", ParseStripeMethod, s.stripe.method);
    text("rule", ParsePeakRule, s.stripe.rule);
    auto number = [&](const char* key, double& field) {
      const YAML::Node n = stripe[key];
      if (n.IsDefined()) field = r.Number(n, std::string("stripe.") + key);
    };
    number("threshold", s.stripe.threshold);
    number("min_peak", s.stripe.min_peak);
    number("min_width_px", s.stripe.min_width_px);
    number("max_width_px", s.stripe.max_width_px);
    number("steger_sigma_px", s.stripe.steger_sigma_px);
    number("min_relative", s.stripe.min_relative);
    StripeCentres probe;
    try {
      FindStripe(cv::Mat(3, 3, CV_8UC1, cv::Scalar(0)), s.stripe, probe);  // checks the options' ranges
    } catch (const Error& e) {
      r.Fail(stripe, "stripe", e.what());
    }
  }
  return s;
}

void WriteSensorYaml(const std::string& path, const SensorModel& s, const std::string& notes_yaml) {
  YAML::Node doc(YAML::NodeType::Map);
  const auto& d = s.camera.distortion;
  doc["camera"]["matrix"] = Rows(s.camera.matrix);
  doc["camera"]["distortion"] = Flow({d[0], d[1], d[2], d[3], d[4]});
  doc["camera"]["image_size"] =
      Flow({static_cast<double>(s.camera.image_size.width), static_cast<double>(s.camera.image_size.height)});
  doc["laser"]["plane"] = Flow({s.plane[0], s.plane[1], s.plane[2], s.plane[3]});
  doc["laser"]["homography"] = Rows(s.map.mm_from_px);
  YAML::Node stripe(YAML::NodeType::Map);
  stripe["axis"] = Name(s.stripe.axis);
  stripe["method"] = Name(s.stripe.method);
  stripe["rule"] = Name(s.stripe.rule);
  stripe["threshold"] = s.stripe.threshold;
  stripe["min_peak"] = s.stripe.min_peak;
  stripe["min_width_px"] = s.stripe.min_width_px;
  stripe["max_width_px"] = s.stripe.max_width_px;
  stripe["min_relative"] = s.stripe.min_relative;
  if (s.stripe.steger_sigma_px > 0.0) stripe["steger_sigma_px"] = s.stripe.steger_sigma_px;
  doc["stripe"] = stripe;
  if (!notes_yaml.empty()) doc["calibration"] = YAML::Load(notes_yaml);
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(12);
  emitter << doc;
  AtomicFile out(path);
  out.stream() << "# libbead sensor file: camera, lens distortion, laser plane, stripe (docs/data-formats.md)\n"
               << emitter.c_str() << "\n";
  out.Commit();
}

}  // namespace bead::vision
