#include "libbead/io/rig_yaml.h"

#include <algorithm>
#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/rig_keys.h"
#include "libbead/io/yaml_text.h"

namespace bead {
namespace {

class RigParser {
 public:
  explicit RigParser(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    throw Error(Located(file_, YamlPlace(node, key), what));
  }

  YAML::Node Child(const YAML::Node& parent, const std::string& parent_key, const std::string& key,
                   bool required = true) const {
    const std::string full = parent_key.empty() ? key : parent_key + "." + key;
    if (!parent.IsMap()) Fail(parent, parent_key, "must be a mapping with key '" + key + "'");
    YAML::Node child = parent[key];
    if (!child.IsDefined() || child.IsNull()) {
      if (required) Fail(parent, full, "missing key (docs/data-formats.md lists the rig file's keys)");
      return YAML::Node(YAML::NodeType::Undefined);
    }
    return child;
  }

  double Number(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) Fail(node, key, "must be a number");
    try {
      const double v = node.as<double>();
      if (!std::isfinite(v)) Fail(node, key, "must be a finite number, got '" + node.Scalar() + "'");
      return v;
    } catch (const YAML::Exception&) {
      Fail(node, key, "must be a number, got '" + node.Scalar() + "'");
    }
  }

  long Integer(const YAML::Node& node, const std::string& key) const {
    const double v = Number(node, key);
    if (v != std::floor(v)) Fail(node, key, "must be a whole number, got '" + node.Scalar() + "'");
    // Beyond +-2^53 a double no longer holds every whole number (and a long
    // not every double): no counter or bit count of a rig is that large.
    if (std::abs(v) > 9007199254740992.0) Fail(node, key, "is out of range, got '" + node.Scalar() + "'");
    return static_cast<long>(v);
  }

  std::pair<double, double> Pair(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence() || node.size() != 2) Fail(node, key, "must be a pair [a, b]");
    return {Number(node[0], key + "[0]"), Number(node[1], key + "[1]")};
  }

  // The part: section (format 1.1): bed flat or cylinder, its radius.
  PartBed Part(const YAML::Node& part) const {
    if (!part.IsMap()) Fail(part, "part", "must be a mapping (bed: flat or cylinder, bed_radius_mm)");
    PartBed bed;
    if (const YAML::Node shape = part["bed"]; shape.IsDefined()) {
      const std::string s = shape.IsScalar() ? shape.Scalar() : "";
      if (s == "cylinder")
        bed.shape = PartBed::Shape::kCylinder;
      else if (s != "flat")
        Fail(shape, "part.bed", "must be flat or cylinder, got '" + s + "'");
    }
    if (const YAML::Node r = part["bed_radius_mm"]; r.IsDefined() && !r.IsNull()) {
      if (bed.shape != PartBed::Shape::kCylinder)
        Fail(r, "part.bed_radius_mm", "is for a cylinder bed (bed: cylinder)");
      bed.radius_mm = Number(r, "part.bed_radius_mm");
      if (!(bed.radius_mm > 0.0)) Fail(r, "part.bed_radius_mm", "must be a positive radius in mm");
    }
    return bed;
  }

  Rig Parse(const YAML::Node& root, bool areas_required, bool wheel_required, bool& has_areas) const {
    if (!root.IsMap()) Fail(root, "", "a rig file must be a YAML mapping (name, encoder, wheel, offset, sensor)");
    Rig rig;
    if (YAML::Node name = root["name"]; name.IsDefined() && name.IsScalar()) rig.name = name.Scalar();
    if (const YAML::Node part = root["part"]; part.IsDefined() && !part.IsNull()) rig.part = Part(part);
    // A part rig needs none of the wheel's sections; with none of them it
    // is a rig without a wheel.
    const bool no_wheel = !root["encoder"].IsDefined() && !root["wheel"].IsDefined() && !root["offset"].IsDefined();
    if (no_wheel && rig.part && wheel_required)
      Fail(root, "encoder",
           "missing key: this is a part rig (a part: section, no wheel), and this command works on a run on the "
           "wheel (a part scan is measured by bead measure)");
    if (!wheel_required && no_wheel)
      rig.has_wheel = false;
    else
      Wheel(root, rig);
    return Sensor(root, rig, areas_required, has_areas);
  }

  void Wheel(const YAML::Node& root, Rig& rig) const {
    const YAML::Node enc = Child(root, "", "encoder");
    const YAML::Node cpr = Child(enc, "encoder", "counts_per_rev");
    rig.encoder.counts_per_rev = Number(cpr, "encoder.counts_per_rev");
    // Whole numbers, held in an int only once within +-2^31 (the rules'
    // range check comes after, IsValid).
    const long b = Integer(Child(enc, "encoder", "bits"), "encoder.bits");
    rig.encoder.bits = static_cast<int>(std::clamp(b, -1L, 65L));
    const long d = Integer(Child(enc, "encoder", "direction"), "encoder.direction");
    rig.encoder.direction = static_cast<int>(std::clamp(d, -2L, 2L));

    const YAML::Node wheel = Child(root, "", "wheel");
    const YAML::Node diam = Child(wheel, "wheel", "diameter_mm");
    rig.wheel_diameter_mm = Number(diam, "wheel.diameter_mm");
    // Optional, from `bead calibrate wheel`.
    if (const YAML::Node e = wheel["eccentricity_mm"]; e.IsDefined()) {
      rig.wheel_eccentricity_mm = Number(e, "wheel.eccentricity_mm");
      const YAML::Node phase = Child(wheel, "wheel", "eccentricity_phase_deg");
      rig.wheel_eccentricity_phase_deg = Number(phase, "wheel.eccentricity_phase_deg");
    }

    const YAML::Node offset = Child(root, "", "offset");
    rig.offset_counts = Number(Child(offset, "offset", "counts"), "offset.counts");
  }

  Rig Sensor(const YAML::Node& root, Rig rig, bool areas_required, bool& has_areas) const {
    const YAML::Node sensor = Child(root, "", "sensor", areas_required);
    if (!sensor.IsDefined()) {
      has_areas = false;
      return rig;
    }
    const YAML::Node areas = Child(sensor, "sensor", "reference_areas_mm", areas_required);
    has_areas = areas.IsDefined();
    if (has_areas && (!areas.IsSequence() || areas.size() != 2))
      Fail(areas, "sensor.reference_areas_mm", "must hold exactly two x ranges, [[x0, x1], [x2, x3]]");
    ReferenceArea ra[2] = {rig.reference_left, rig.reference_right};
    for (int i = 0; i < 2 && has_areas; ++i) {
      const std::string key = "sensor.reference_areas_mm[" + std::to_string(i) + "]";
      const auto [lo, hi] = Pair(areas[i], key);
      ra[i] = ReferenceArea{lo, hi};
    }
    if (ra[0].x_min_mm > ra[1].x_min_mm) std::swap(ra[0], ra[1]);
    rig.reference_left = ra[0];
    rig.reference_right = ra[1];
    if (YAML::Node origin = Child(sensor, "sensor", "laser_origin_mm", false); origin.IsDefined()) {
      const auto [x, z] = Pair(origin, "sensor.laser_origin_mm");
      rig.laser_origin = LaserOrigin{x, z};
    }
    return rig;
  }

  // The rules (core/rig.h IsValid), a broken one named at its key's line.
  void Check(const YAML::Node& root, const Rig& rig, bool has_areas) const {
    std::string key, error;
    if (IsValid(rig, has_areas, &key, &error)) return;
    Fail(NodeAt(root, key), key, error);
  }

 private:
  // The node of a dotted key ("encoder.bits", "sensor.reference_areas_mm[1]"),
  // or the deepest one there is.
  static YAML::Node NodeAt(const YAML::Node& root, const std::string& key) {
    YAML::Node n = root;
    std::size_t start = 0;
    while (start < key.size()) {
      const std::size_t dot = key.find('.', start);
      std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
      int index = -1;
      if (const std::size_t b = part.find('['); b != std::string::npos) {
        index = std::stoi(part.substr(b + 1));
        part = part.substr(0, b);
      }
      YAML::Node next = n[part];
      if (!next.IsDefined()) return n;
      n = next;
      if (index >= 0 && n.IsSequence() && static_cast<std::size_t>(index) < n.size())
        n = n[static_cast<std::size_t>(index)];
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    return n;
  }

 public:
 private:
  std::string file_;
};

void WriteWheel(YAML::Node& doc, const Rig& rig) {
  doc["encoder"]["counts_per_rev"] = rig.encoder.counts_per_rev;
  doc["encoder"]["bits"] = rig.encoder.bits;
  doc["encoder"]["direction"] = rig.encoder.direction;
  doc["wheel"]["diameter_mm"] = rig.wheel_diameter_mm;
  if (rig.wheel_eccentricity_mm > 0.0) {
    doc["wheel"]["eccentricity_mm"] = rig.wheel_eccentricity_mm;
    doc["wheel"]["eccentricity_phase_deg"] = rig.wheel_eccentricity_phase_deg;
  } else {
    doc["wheel"].remove("eccentricity_mm");
    doc["wheel"].remove("eccentricity_phase_deg");
  }
  doc["offset"]["counts"] = rig.offset_counts;
}

void WritePart(YAML::Node& doc, const PartBed& bed) {
  doc["part"]["bed"] = bed.shape == PartBed::Shape::kCylinder ? "cylinder" : "flat";
  if (bed.radius_mm > 0.0)
    doc["part"]["bed_radius_mm"] = bed.radius_mm;
  else
    doc["part"].remove("bed_radius_mm");
}

}  // namespace

RigFile ParseRig(const std::string& text, const std::string& name, bool areas_required, bool wheel_required) {
  RigFile out;
  out.document = ParseYamlText(text, name);
  out.warnings = RigKeyWarnings(out.document, name);
  const RigParser parser(name);
  out.rig = parser.Parse(out.document, areas_required, wheel_required, out.has_reference_areas);
  parser.Check(out.document, out.rig, out.has_reference_areas);
  return out;
}

RigFile ReadRigFile(const std::string& path, bool areas_required) {
  return ParseRig(ReadTextFile(path, "rig file"), path, areas_required);
}

RigFile ReadPartRigFile(const std::string& path) { return ParseRig(ReadTextFile(path, "rig file"), path, true, false); }

RigFile MakeRigFile(const Rig& rig) {
  RigFile out;
  out.rig = rig;
  out.document = YAML::Node(YAML::NodeType::Map);
  return out;
}

void WriteRigFile(const std::string& path, const RigFile& file) {
  YAML::Node doc = YAML::Clone(file.document);
  const Rig& rig = file.rig;
  if (!rig.name.empty()) doc["name"] = rig.name;
  if (rig.has_wheel) WriteWheel(doc, rig);
  if (rig.part) WritePart(doc, *rig.part);
  YAML::Node areas(YAML::NodeType::Sequence);
  for (const ReferenceArea& a : {rig.reference_left, rig.reference_right}) {
    YAML::Node pair(YAML::NodeType::Sequence);
    pair.SetStyle(YAML::EmitterStyle::Flow);
    pair.push_back(a.x_min_mm);
    pair.push_back(a.x_max_mm);
    areas.push_back(pair);
  }
  areas.SetStyle(YAML::EmitterStyle::Flow);
  doc["sensor"]["reference_areas_mm"] = areas;
  if (rig.laser_origin) {
    YAML::Node origin(YAML::NodeType::Sequence);
    origin.SetStyle(YAML::EmitterStyle::Flow);
    origin.push_back(rig.laser_origin->x_mm);
    origin.push_back(rig.laser_origin->z_mm);
    doc["sensor"]["laser_origin_mm"] = origin;
  }
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(10);
  emitter << doc;
  AtomicFile out(path);
  out.stream() << emitter.c_str() << "\n";
  out.Commit();
}

}  // namespace bead
