// bead.measure_part and bead.part_flow: a part scan (format 1.1) measured
// layer on layer and its flow along the toolpath, as `bead measure` and
// `bead flow` do on one, columns as NumPy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_flow.h"
#include "libbead/part/part_profile_processor.h"
#include "python/numpy_owned.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bead::python {
namespace {

Rig PartRigWarning(const std::string& path) {
  const RigFile file = ReadPartRigFile(path);
  for (const std::string& w : file.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return file.rig;
}

std::vector<part::PartGeometryRow> MeasureRows(const Rig& rig, const std::string& path, unsigned threads) {
  const RunArchive scan = ReadPartScan(path, false, false);
  std::vector<part::PartGeometryRow> rows;
  part::MeasurePartFile(path, *scan.part, rig, {}, threads, [&](const part::PartGeometryRow& r) { rows.push_back(r); });
  return rows;
}

py::dict PartColumns(const std::vector<part::PartGeometryRow>& rows) {
  using Row = part::PartGeometryRow;
  auto ok = [](const Row& r, double v) { return r.bead.valid() ? v : Row::kNaN; };
  py::dict out;
  out["profile"] = Column<int64_t>(rows, [](const Row& r) { return r.profile; });
  out["t_s"] = Column<double>(rows, [](const Row& r) { return r.t_s; });
  out["layer"] = Column<int64_t>(rows, [](const Row& r) { return r.layer; });
  out["path_mm"] = Column<double>(rows, [](const Row& r) { return r.path_mm; });
  out["area_mm2"] = Column<double>(rows, [&](const Row& r) { return ok(r, r.bead.area_mm2); });
  out["width_mm"] = Column<double>(rows, [&](const Row& r) { return ok(r, r.bead.width_mm); });
  out["height_mm"] = Column<double>(rows, [&](const Row& r) { return ok(r, r.bead.height_mm); });
  out["area_corrected_mm2"] = Column<double>(rows, [](const Row& r) { return r.area_corrected_mm2; });
  out["valid"] = Flags(rows, [](const Row& r) { return r.bead.valid(); });
  out["center_x_mm"] = Column<double>(rows, [&](const Row& r) { return ok(r, r.bead.center_x_mm); });
  out["offset_below_mm"] = Column<double>(rows, [](const Row& r) { return r.offset_below_mm; });
  // As the CSV: no shift where none was sought (layer 0, the bed).
  auto registered = [&](const Row& r, double v) { return std::isnan(r.bead.shift_sigma_mm) ? Row::kNaN : ok(r, v); };
  out["shift_mm"] = Column<double>(rows, [&](const Row& r) { return registered(r, r.bead.shift_mm); });
  out["shift_sigma_mm"] = Column<double>(rows, [&](const Row& r) { return ok(r, r.bead.shift_sigma_mm); });
  out["shift_found"] = Flags(rows, [](const Row& r) { return r.bead.shift_constrained; });
  out["registration_rms_mm"] =
      Column<double>(rows, [&](const Row& r) { return registered(r, r.bead.registration_rms_mm); });
  out["noise_mm"] = Column<double>(rows, [](const Row& r) { return r.bead.noise_mm; });
  out["area_corrected_sigma_mm2"] =
      Column<double>(rows, [&](const Row& r) { return ok(r, r.area_corrected_sigma_mm2); });
  std::vector<std::string> status;
  for (const Row& r : rows) status.emplace_back(part::AddedStatusName(r.bead.status));
  out["status"] = status;
  return out;
}

py::dict MeasurePartColumns(const std::string& rig_path, const std::string& scan, unsigned threads) {
  const Rig rig = PartRigWarning(rig_path);
  std::vector<part::PartGeometryRow> rows;
  {
    py::gil_scoped_release free;
    rows = MeasureRows(rig, scan, threads);
  }
  return PartColumns(rows);
}

py::dict PartFlow(const std::string& rig_path, const std::string& scan_path, unsigned threads) {
  const Rig rig = PartRigWarning(rig_path);
  std::vector<part::PartFlowRow> flow;
  part::PartScanFlow f;
  {
    py::gil_scoped_release free;
    const RunArchive scan = ReadPartScan(scan_path, false, true);
    if (!scan.log) throw Error(Located(scan_path, "/log", "missing group: the flow along the path needs the log"));
    // `bead flow`'s own: the rows filtered along each layer's path too.
    f = part::MeasurePartScanFlow(scan_path, *scan.part, &*scan.log, rig, {}, threads, nullptr,
                                  [&](const part::PartFlowRow& row) { flow.push_back(row); });
  }
  using Row = part::PartFlowRow;
  py::dict out;
  out["t_s"] = Column<double>(flow, [](const Row& r) { return r.t_s; });
  out["layer"] = Column<int64_t>(flow, [](const Row& r) { return r.layer; });
  out["path_mm"] = Column<double>(flow, [](const Row& r) { return r.path_mm; });
  out["head_speed_mm_s"] = Column<double>(flow, [](const Row& r) { return r.head_speed_mm_s; });
  out["area_mm2"] = Column<double>(flow, [](const Row& r) { return r.area_mm2; });
  out["area_corrected_mm2"] = Column<double>(flow, [](const Row& r) { return r.area_corrected_mm2; });
  out["flow_mm3_s"] = Column<double>(flow, [](const Row& r) { return r.flow_mm3_s; });
  out["screw_rpm"] = Column<double>(flow, [](const Row& r) { return r.screw_rpm; });
  out["profile"] = Column<int64_t>(flow, [](const Row& r) { return r.profile; });
  out["valid"] = Flags(flow, [](const Row& r) { return r.valid; });
  out["layer_volume_mm3"] = f.volumes_mm3;
  return out;
}

// One profile's geometry as the processor gives it (bed frame).
py::dict ProcessProfile(part::PartProfileProcessor& p,
                        const py::array_t<float, py::array::c_style | py::array::forcecast>& x,
                        const py::array_t<float, py::array::c_style | py::array::forcecast>& z, int64_t layer,
                        double path_mm, double frame_x_mm, double frame_z_mm) {
  if (x.ndim() != 1 || z.ndim() != 1 || x.size() != z.size())
    throw py::value_error("x_mm and z_mm must be 1-D arrays of one length (a profile's points, mm)");
  const ProfileView view{{x.data(), static_cast<std::size_t>(x.size())},
                         {z.data(), static_cast<std::size_t>(z.size())}};
  const part::PartProfileGeometry& g = p.Process(view, {layer, path_mm, frame_x_mm, frame_z_mm});
  const bool valid = g.bead.status == ProfileStatus::kValid && g.no_surface.empty();
  py::dict out;
  out["valid"] = valid;
  out["status"] = g.no_surface.empty() ? std::string(StatusName(g.bead.status)) : std::string("no_surface_below");
  out["why"] = g.no_surface;
  const double nan = std::nan("");
  out["area_mm2"] = valid ? g.bead.area_mm2 : nan;
  out["area_sigma_mm2"] = valid ? g.bead.area_sigma_mm2 : nan;
  out["width_mm"] = valid ? g.bead.width_mm : nan;
  out["height_mm"] = valid ? g.bead.height_mm : nan;
  out["center_x_mm"] = valid ? g.bead.center_x_mm : nan;
  out["shift_mm"] = layer > 0 ? g.shift_mm : nan;
  out["shift_sigma_mm"] = g.shift_sigma_mm;
  out["shift_found"] = g.shift_constrained;
  return out;
}

}  // namespace

// A part scan's places and its log's path, added to read_run's dict.
void AddPartArrays(RunArchive& run, py::dict& out) {
  PartPlaces& p = *run.part;
  const auto n = static_cast<py::ssize_t>(p.size());
  out["kind"] = "part";
  out["layer"] = Owned(std::move(p.layer), {n});
  out["path_mm"] = Owned(std::move(p.path_mm), {n});
  out["frame_z_mm"] = Owned(std::move(p.frame_z_mm), {n});
  out["frame_x_mm"] = Owned(std::move(p.frame_x_mm), {n});
}

void AddPartLogArrays(AcquisitionLog& l, py::dict& log) {
  const auto m = static_cast<py::ssize_t>(l.size());
  log["layer"] = Owned(std::move(l.layer), {m});
  log["path_mm"] = Owned(std::move(l.path_mm), {m});
  if (!l.head_speed_mm_s.empty()) log["head_speed_mm_s"] = Owned(std::move(l.head_speed_mm_s), {m});
}

void AddPart(py::module_& m) {
  py::class_<part::PartProfileProcessor>(m, "PartProfileProcessor",
                                         "A part's profiles measured as they arrive (acquisition software), each "
                                         "against the layer below kept as it passed: the area seen, as the wheel's "
                                         "per-profile area (bead measure adds the groove a bead hides).")
      .def(py::init([](const std::string& rig, std::size_t max_points) {
             return part::PartProfileProcessor(PartRigWarning(rig), {}, max_points);
           }),
           "rig"_a, "max_points"_a = 2048, "rig: a rig file with the reference areas (layer 0's bed line).")
      .def("process", &ProcessProfile, "x_mm"_a, "z_mm"_a, "layer"_a, "path_mm"_a, "frame_x_mm"_a = 0.0,
           "frame_z_mm"_a = 0.0,
           "One profile, in scan order (a layer needs the one before): its points in the profiler's frame (mm) and "
           "where it lies (format 1.1's layer, path_mm, frame_x_mm, frame_z_mm). Returns a dict: valid, status, "
           "why (words, where the layer below is not known there), area_mm2, area_sigma_mm2, width_mm, height_mm, "
           "center_x_mm (bed frame), shift_mm, shift_sigma_mm, shift_found (the layer below's lateral "
           "registration).");
  m.def("measure_part", &MeasurePartColumns, "rig"_a, "scan"_a, "threads"_a = 0,
        "Measure a part scan (format 1.1, kind = \"part\") layer on layer, as `bead measure` does on one: each "
        "profile against the layer below at its place along the path (layer 0 against the bed), the layer below "
        "registered laterally.\n\nrig: a rig file with the reference areas (no wheel needed). Returns the part "
        "geometry CSV's columns as [N] arrays: profile, t_s (s), layer, path_mm, area_mm2 (what the layer added), "
        "width_mm, height_mm (mm), area_corrected_mm2 (less the groove the bead hides under its overhangs), "
        "valid, center_x_mm, offset_below_mm (wall wander; NaN where the passes' shift was not found), shift_mm, "
        "shift_sigma_mm, shift_found, registration_rms_mm, noise_mm (mm), status (list of str), "
        "area_corrected_sigma_mm2.");
  m.def("part_flow", &PartFlow, "rig"_a, "scan"_a, "threads"_a = 0,
        "The flow along a part scan's toolpath, as `bead flow` computes it on one: each profile's time is when the "
        "nozzle laid its place (from the log's layer and path_mm), flow_mm3_s = head_speed_mm_s x the corrected "
        "area, filtered along each layer's path (a Hampel filter). valid is 0 (flow_mm3_s NaN) where the log never "
        "had the nozzle at the place, or the profile's corrected area was refused (the area seen counts what an "
        "overhanging bead hides: `bead measure` says why).\n\nReturns [N] arrays t_s (s), layer, path_mm (mm), "
        "head_speed_mm_s, area_mm2, area_corrected_mm2, flow_mm3_s (mm^3/s), screw_rpm, profile, valid; and "
        "layer_volume_mm3: {layer: mm^3} (the area integrated along the path over the valid profiles; a layer with "
        "none is absent).");
}

}  // namespace bead::python
