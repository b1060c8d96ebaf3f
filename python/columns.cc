#include <string>

#include "python/numpy_owned.h"

namespace py = pybind11;

namespace bead::python {
namespace {

constexpr double kNaN = BeadGeometry::kNaN;

// The statuses as a NumPy array of text (dtype <U24), filled in place: a
// list of Python strings would cost as much as measuring the profiles.
py::array Statuses(const std::vector<ProfileStatus>& s) {
  constexpr py::ssize_t kWidth = 24;
  py::array out(py::dtype("<U24"), std::vector<py::ssize_t>{static_cast<py::ssize_t>(s.size())});
  auto* to = static_cast<char32_t*>(out.mutable_data());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char* name = StatusName(s[i]);
    py::ssize_t k = 0;
    for (; name[k] != '\0' && k < kWidth; ++k) to[i * kWidth + k] = static_cast<char32_t>(name[k]);
    for (; k < kWidth; ++k) to[i * kWidth + k] = 0;
  }
  return out;
}

}  // namespace

py::dict GeometryColumns(const std::vector<BeadGeometry>& g) {
  auto valid = [](const BeadGeometry& b, double v) { return b.valid() ? v : kNaN; };
  py::dict out;
  out["area_mm2"] = Column<double>(g, [&](const BeadGeometry& b) { return valid(b, b.area_mm2); });
  out["width_mm"] = Column<double>(g, [&](const BeadGeometry& b) { return valid(b, b.width_mm); });
  out["height_mm"] = Column<double>(g, [&](const BeadGeometry& b) { return valid(b, b.height_mm); });
  out["center_x_mm"] = Column<double>(g, [&](const BeadGeometry& b) { return valid(b, b.center_x_mm); });
  out["area_sigma_mm2"] = Column<double>(g, [&](const BeadGeometry& b) { return valid(b, b.area_sigma_mm2); });
  out["valid"] = Flags(g, [](const BeadGeometry& b) { return b.valid(); });
  out["reference_rms_mm"] = Column<double>(g, [](const BeadGeometry& b) { return b.reference.residual_rms_mm; });
  out["threshold_mm"] = Column<double>(g, [](const BeadGeometry& b) { return b.threshold_mm; });
  std::vector<ProfileStatus> s;
  for (const BeadGeometry& b : g) s.push_back(b.status);
  out["status"] = Statuses(s);
  return out;
}

py::dict RowColumns(const std::vector<GeometryRow>& rows) {
  // As the geometry CSV writes them (io/geometry_csv.cc): a geometry value
  // only where the profile is valid.
  auto valid = [](const GeometryRow& r, double v) { return r.geometry.valid() ? v : kNaN; };
  py::dict out;
  out["profile"] = Column<int64_t>(rows, [](const GeometryRow& r) { return r.profile; });
  out["t_s"] = Column<double>(rows, [](const GeometryRow& r) { return r.t_s; });
  out["encoder"] = Column<int64_t>(rows, [](const GeometryRow& r) { return r.encoder; });
  out["area_mm2"] = Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.geometry.area_mm2); });
  out["width_mm"] = Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.geometry.width_mm); });
  out["height_mm"] = Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.geometry.height_mm); });
  out["area_corrected_mm2"] =
      Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.area_corrected_mm2); });
  out["valid"] = Flags(rows, [](const GeometryRow& r) { return r.geometry.valid(); });
  out["center_x_mm"] = Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.geometry.center_x_mm); });
  out["reference_rms_mm"] =
      Column<double>(rows, [](const GeometryRow& r) { return r.geometry.reference.residual_rms_mm; });
  out["reference_points"] =
      Column<int64_t>(rows, [](const GeometryRow& r) { return r.geometry.reference.points_used; });
  out["threshold_mm"] = Column<double>(rows, [](const GeometryRow& r) { return r.geometry.threshold_mm; });
  out["dropped_points"] = Column<int64_t>(rows, [](const GeometryRow& r) { return r.geometry.dropped_points; });
  std::vector<ProfileStatus> s;
  for (const GeometryRow& r : rows) s.push_back(r.geometry.status);
  out["status"] = Statuses(s);
  out["area_sigma_mm2"] =
      Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.geometry.area_sigma_mm2); });
  out["occlusion_bias_mm2"] =
      Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.occlusion_bias_mm2); });
  out["area_corrected_sigma_mm2"] =
      Column<double>(rows, [&](const GeometryRow& r) { return valid(r, r.area_corrected_sigma_mm2); });
  return out;
}

py::dict FlowColumns(const FlowResult& flow) {
  const auto& s = flow.samples;
  py::dict out;
  out["t_s"] = Column<double>(s, [](const FlowSample& x) { return x.t_s; });
  out["encoder"] = Column<int64_t>(s, [](const FlowSample& x) { return x.encoder; });
  out["surface_speed_mm_s"] = Column<double>(s, [](const FlowSample& x) { return x.surface_speed_mm_s; });
  out["area_mm2"] = Column<double>(s, [](const FlowSample& x) { return x.area_mm2; });
  out["area_corrected_mm2"] = Column<double>(s, [](const FlowSample& x) { return x.area_corrected_mm2; });
  out["flow_mm3_s"] = Column<double>(s, [](const FlowSample& x) { return x.flow_mm3_s; });
  out["screw_rpm"] = Column<double>(s, [](const FlowSample& x) { return x.screw_rpm; });
  out["profile"] = Column<int64_t>(s, [](const FlowSample& x) { return x.profile; });
  out["valid"] = Flags(s, [](const FlowSample& x) { return x.valid; });
  out["occlusion_bias_mm2"] = Column<double>(s, [](const FlowSample& x) { return x.occlusion_bias_mm2; });
  out["area_corrected_sigma_mm2"] = Column<double>(s, [](const FlowSample& x) { return x.area_corrected_sigma_mm2; });
  out["flow_sigma_mm3_s"] = Column<double>(s, [](const FlowSample& x) { return x.flow_sigma_mm3_s; });
  out["total_volume_mm3"] = flow.total_volume_mm3;
  return out;
}

}  // namespace bead::python
